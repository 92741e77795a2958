// One pixel update on a render thread, shared by the frameless walk and the conventional frames:
// where its samples look, the batch traced together, the statistics and the seqlocked publish.
// Render threads only; nothing here locks, allocates or makes a system call.
#pragma once
#include <algorithm>
#include <cmath>

#include "core/base/rng.h"
#include "core/base/sobol.h"
#include "core/scene/dynamic.h"
#include "frameless/engine_impl.h"
#include "frameless/pixel_levels.h"
#include "frameless/running_stats.h"
#include "frameless/temporal_weight.h"
#include "frameless/tile_render.h"

namespace frameless {
namespace render_detail {

inline constexpr uint64_t kSeedSalt = 0x6672616d656c6573ull;  // separates engine samples from one-shot renders

// Frameless antialiasing (Scher Zagier): four strata of the pixel (2x2); each update samples a
// diagonal pair, alternating, so a pixel is fully covered after two updates.
inline constexpr int kStrata[2][2] = {{0, 3}, {1, 2}};

// Where and with which random stream the samples of one pixel update look: 1 or 2 samples
// (frameless antialiasing), fixed by the pixel's update count.
struct UpdateSamples {
  float px[2], py[2];
  uint64_t seed[2];
  uint32_t index[2];  // the samples' indices among the pixel's samples
};

inline void prepare_samples(const Engine::Impl& e, uint32_t idx, uint32_t passes, UpdateSamples& u) {
  const uint32_t w = uint32_t(e.partition.width);
  const uint32_t x = idx % w, y = idx / w;
  const int spu = e.cfg.jitter ? 2 : 1;
  for (int j = 0; j < spu; ++j) {
    const uint64_t seed = sample_seed(x, y, passes * uint32_t(spu) + uint32_t(j), e.sample_seed_base);
    float px = float(x) + 0.5f, py = float(y) + 0.5f;
    if (e.cfg.jitter && e.scene.settings.integrator >= Integrator::kPath) {
      // Light that bounces converges over many updates: the pixel's Owen-scrambled Sobol' points
      // keep its jitter stratified at every power of two of its sample count.
      float ux, uy;
      owen_sobol_2d(passes * uint32_t(spu) + uint32_t(j), mix64(uint64_t(idx) ^ e.sample_seed_base), ux, uy);
      px = float(x) + ux;
      py = float(y) + uy;
    } else if (e.cfg.jitter) {
      Rng rng(seed);
      const int s = kStrata[passes & 1u][j];
      px = float(x) + 0.5f * (float(s & 1) + rng.next_float());
      py = float(y) + 0.5f * (float(s >> 1) + rng.next_float());
    }
    u.px[j] = px, u.py[j] = py;
    u.seed[j] = mix64(seed ^ kSeedSalt);
    u.index[j] = passes * uint32_t(spu) + uint32_t(j);
  }
}

// The statistics and the publish of one pixel update of pixel `idx`, whose state is `p`, from
// its traced samples r[0..spu): Welford per sample, publish under the pixel's sequence lock.
// `frame` (conventional) also receives the published snapshot. `history` says whether the world
// (dynamic objects, lights, materials) moves, so that old samples may no longer hold.
inline void finish_update(Engine::Impl& e, uint32_t idx, PixelState& p, uint32_t epoch,
                          float time, ThreadCounters& ctr, PixelSnapshot* frame,
                          History history, const SampleResult* r) {
  const uint32_t passes = p.passes.load(std::memory_order_relaxed);
  const int spu = e.cfg.jitter ? 2 : 1;
  Vec3 colors[2], indirect(0.0f);  // indirect: igi's share at the primary hits, summed
  int valid = 0;
  uint8_t levels = 0;  // the reflection depth view's value: the deepest valid sample
  const SampleResult* nearest = nullptr;  // reprojection's point: the nearest valid hit
  for (int j = 0; j < spu; ++j)
    if (r[j].valid && is_finite(r[j].color)) {
      colors[valid++] = r[j].color;
      indirect += r[j].indirect;
      levels = std::max(levels, r[j].levels);
      if (!nearest || r[j].depth < nearest->depth) nearest = &r[j];
    }
  ctr.samples.store(ctr.samples.load(std::memory_order_relaxed) + uint64_t(spu),
                    std::memory_order_relaxed);
  p.passes.store(passes + 1, std::memory_order_relaxed);
  if (valid < spu)
    ctr.dropped.store(ctr.dropped.load(std::memory_order_relaxed) + uint64_t(spu - valid),
                      std::memory_order_relaxed);
  if (valid == 0) {
    if (frame) {  // the frame shows what the pixel last published (the owner reads its own state)
      load_state(p, *frame);
      frame->seq = p.seq.load(std::memory_order_relaxed);
      frame->levels = e.levels[idx].load(std::memory_order_relaxed);
    }
    return;
  }

  // Running statistics restart at the first sample with a new camera.
  const bool same_epoch = p.epoch.load(std::memory_order_relaxed) == epoch;
  uint32_t count = same_epoch ? p.count.load(std::memory_order_relaxed) : 0u;
  double mean[3], m2 = 0.0;
  for (int c = 0; c < 3; ++c) mean[c] = same_epoch ? p.mean[c].load(std::memory_order_relaxed) : 0.0;
  const bool variance = tracks_variance(e.cfg) || history != History::kStill;
  if (same_epoch && variance) m2 = p.m2.load(std::memory_order_relaxed);
  if (history == History::kTemporal && count > 0) {
    // Something moves: the display's temporal rule (frameless/temporal_weight.h) sets how much
    // history the pixel keeps. Where the sample agrees, a long one: at most motion_history
    // samples, so the mean forgets (an exponential average); where it clearly differs, none (the
    // statistics restart); shorter in between. The variance shrinks to the same window.
    const Vec3& s = colors[0];
    const double sigma = count > 1 ? std::sqrt(m2 / double(count - 1)) : 0.0;
    const float t = disagreement(float(luminance(s.x, s.y, s.z)),
                                 float(luminance(mean[0], mean[1], mean[2])), float(sigma));
    const uint32_t window = std::max(1u, uint32_t(e.cfg.motion_history) - uint32_t(valid));
    const uint32_t keep = history_for_weight(temporal_weight(1.0f / float(std::min(count, window) + 1), t), count);
    if (keep == 0) {
      m2 = 0.0;
      for (double& m : mean) m = 0.0;
    } else if (keep < count) {
      m2 *= double(keep) / double(count);
    }
    count = keep;
  }
  const uint32_t kept = count;  // samples of the history the new ones join
  Vec3 sum(0.0f);
  for (int k = 0; k < valid; ++k) {
    const Vec3& s = colors[k];
    sum += s;
    if (count != 0xffffffffu) ++count;  // saturates: the mean then becomes a slow moving average
    if (variance) {
      const double lum_mean = luminance(mean[0], mean[1], mean[2]);
      const double lum = luminance(s.x, s.y, s.z);
      for (int c = 0; c < 3; ++c) mean[c] += (double(s[c]) - mean[c]) / double(count);
      const double lum_new = luminance(mean[0], mean[1], mean[2]);
      m2 += (lum - lum_mean) * (lum - lum_new);  // Welford: delta * (x - new mean)
    } else {
      for (int c = 0; c < 3; ++c) mean[c] += (double(s[c]) - mean[c]) / double(count);
    }
  }
  const Vec3 sample = sum / float(valid);

  const uint32_t seq =
      publish_state(p, count, epoch, mean, m2, sample, time, [&] {
        store_levels(e, idx, levels, frame);
        store_point(e.points[idx], *nearest);
        if (e.indirect) {  // the same mean as the colour's: the kept history plus the new samples
          PixelIndirect& d = e.indirect[idx];
          for (int c = 0; c < 3; ++c) {
            const float old = kept > 0 ? d.mean[c].load(std::memory_order_relaxed) : 0.0f;
            d.mean[c].store(float((double(old) * kept + indirect[c]) / double(count)), std::memory_order_relaxed);
          }
        }
      });

  if (frame) {
    frame->sample = sample;
    frame->mean = Vec3(float(mean[0]), float(mean[1]), float(mean[2]));
    frame->variance = count > 1 ? float(m2 / double(count - 1)) : 0.0f;
    frame->count = count;
    frame->epoch = epoch;
    frame->time = time;
    frame->seq = seq;
  }
}

// Up to kPacketSize consecutive pixel updates, traced together: with packets on, their camera
// rays go through the static scene as coherent packets (Accel::intersect_packet) and each sample
// is shaded on its own with its exact single-ray hit, so images equal ray-by-ray tracing's bit
// for bit; otherwise ray by ray, or by the custom shader.
struct PacketBatch {
  static constexpr int kMax = kPacketSize;  // pixel updates per batch (two packets with jitter)
  int n = 0;
  uint32_t idx[kMax];
  PixelState* state[kMax];
  double t[kMax];
  PixelSnapshot* frame[kMax];
  SampleResult r[kMax][2];
};

// Traces the batch's samples; `world` (if any) is advanced to each update's own instant.
void trace_batch(Engine::Impl& e, PacketBatch& b, const CameraBasis& basis, DynamicFrame* world,
                 const WorldState* world_state);

}  // namespace render_detail
}  // namespace frameless
