// Render threads: the per-pixel update (frameless antialiasing, Welford statistics, seqlocked
// publish), the frameless walking loop and the conventional job loop. The per-sample path holds
// no lock, allocates nothing and makes no system call.
#include <algorithm>
#include <chrono>
#include <thread>
#include <cmath>

#include "core/rng.h"
#include "frameless/adaptive.h"
#include "frameless/engine_impl.h"
#include "frameless/pixel_levels.h"
#include "frameless/running_stats.h"
#include "frameless/temporal_weight.h"
#include "frameless/tile_render.h"

namespace frameless {
namespace {

constexpr uint64_t kSeedSalt = 0x6672616d656c6573ull;  // separates engine samples from one-shot renders

// Frameless antialiasing (Scher Zagier): four strata of the pixel (2x2); each update samples a
// diagonal pair, alternating, so a pixel is fully covered after two updates.
constexpr int kStrata[2][2] = {{0, 3}, {1, 2}};

// Where and with which random stream the samples of one pixel update look: 1 or 2 samples
// (frameless antialiasing), fixed by the pixel's update count.
struct UpdateSamples {
  float px[2], py[2];
  uint64_t seed[2];
};

inline void prepare_samples(const Engine::Impl& e, uint32_t idx, uint32_t passes, UpdateSamples& u) {
  const uint32_t w = uint32_t(e.partition.width);
  const uint32_t x = idx % w, y = idx / w;
  const int spu = e.cfg.jitter ? 2 : 1;
  for (int j = 0; j < spu; ++j) {
    const uint64_t seed = sample_seed(x, y, passes * uint32_t(spu) + uint32_t(j), e.sample_seed_base);
    float px = float(x) + 0.5f, py = float(y) + 0.5f;
    if (e.cfg.jitter) {
      Rng rng(seed);
      const int s = kStrata[passes & 1u][j];
      px = float(x) + 0.5f * (float(s & 1) + rng.next_float());
      py = float(y) + 0.5f * (float(s >> 1) + rng.next_float());
    }
    u.px[j] = px, u.py[j] = py;
    u.seed[j] = mix64(seed ^ kSeedSalt);
  }
}

// The statistics and the publish of one pixel update of pixel `idx`, whose state is `p`, from
// its traced samples r[0..spu): Welford per sample, publish under the pixel's sequence lock.
// `frame` (conventional) also receives the published snapshot. `world` (null when nothing
// moves) is what the samples saw of dynamic objects, lights and materials.
inline void finish_update(Engine::Impl& e, uint32_t idx, PixelState& p, uint32_t epoch,
                          float time, ThreadCounters& ctr, PixelSnapshot* frame,
                          const DynamicFrame* world, const SampleResult* r) {
  const uint32_t passes = p.passes.load(std::memory_order_relaxed);
  const int spu = e.cfg.jitter ? 2 : 1;
  Vec3 colors[2];
  int valid = 0;
  uint8_t levels = 0;  // the reflection depth view's value: the deepest valid sample
  const SampleResult* nearest = nullptr;  // reprojection's point: the nearest valid hit
  for (int j = 0; j < spu; ++j)
    if (r[j].valid && is_finite(r[j].color)) {
      colors[valid++] = r[j].color;
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
  const bool variance = tracks_variance(e.cfg) || world;
  if (same_epoch && variance) m2 = p.m2.load(std::memory_order_relaxed);
  if (world && count > 0) {
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
                 const WorldState* world_state) {
  const int spu = e.cfg.jitter ? 2 : 1;
  const SampleShader& custom = e.cfg.shader;
  const bool packets = e.cfg.packets && !custom.fn;
  UpdateSamples u[PacketBatch::kMax];
  float px[2 * PacketBatch::kMax], py[2 * PacketBatch::kMax];
  Hit hits[2 * PacketBatch::kMax];
  for (int k = 0; k < b.n; ++k) {
    prepare_samples(e, b.idx[k], b.state[k]->passes.load(std::memory_order_relaxed), u[k]);
    for (int j = 0; j < spu; ++j) px[k * spu + j] = u[k].px[j], py[k * spu + j] = u[k].py[j];
  }
  if (packets) primary_hits(e.scene, basis, b.n * spu, px, py, hits, world);
  for (int k = 0; k < b.n; ++k) {
    if (world && world_state && world->time != b.t[k])
      advance_frame(e.scene, *world_state, b.t[k], *world);
    for (int j = 0; j < spu; ++j)
      b.r[k][j] = custom.fn ? custom.fn(custom.context, basis, u[k].px[j], u[k].py[j], u[k].seed[j])
                            : trace_sample(e.scene, basis, u[k].px[j], u[k].py[j], u[k].seed[j],
                                           world, packets ? &hits[k * spu + j] : nullptr);
  }
}

// Records a pixel update in the thread's update log (statistics runs; off: no log).
inline void log_update(const Engine::Impl& e, FramelessWorker& w, uint32_t idx, float time) {
  if (!w.log) return;
  if (w.log->records.size() < w.log->records.capacity())
    w.log->records.push_back({idx, w.epoch, e.display_tick.load(std::memory_order_relaxed), time});
  else
    ++w.log->overflow;
}

// Picks up the newest world state (dynamic objects, lights, materials, moved instances) if it changed.
void refresh_world(Engine::Impl& e, FramelessWorker& w, double time) {
  if (e.pick_up_instances(w.instances_epoch, w.frame.instances)) w.moving = true;
  if (e.world_channel.epoch() == w.world_epoch) return;
  const uint32_t ep = e.world_channel.read(w.world_buf);
  // The channel carries only what the engine published after checking it: it always fits.
  unpack_world(w.world_buf.data(), w.world_buf.size(), w.world);
  evaluate_frame(e.scene, w.world, time, w.frame);
  w.world_epoch = ep;
  w.moving = true;
}

// Picks up the newest camera if it changed.
void refresh_camera(Engine::Impl& e, uint32_t& epoch, CameraBasis& basis) {
  if (e.channel.epoch() == epoch) return;
  uint32_t ep = 0;
  const Camera cam = e.channel.read(&ep);
  basis = make_camera_basis(cam, e.partition.width, e.partition.height);
  epoch = ep;
}

// Closed-loop sampling: after the display asked for more runs, queue this thread's (their flags
// are cleared as they are queued; the display may ask again later).
void scan_asked(Engine::Impl& e, FramelessWorker& w, float now) {
  const uint64_t generation = e.wanted.generation.load(std::memory_order_acquire);
  if (generation == w.asked_generation) return;
  w.asked_generation = generation;
  w.asked.erase(w.asked.begin(), w.asked.begin() + std::ptrdiff_t(w.asked_next));
  w.asked_next = 0;
  const size_t first = w.first_slot, end = first + w.pixels->size();
  if (end == first) return;
  for (size_t r = first / kRunLength; r <= (end - 1) / kRunLength; ++r) {
    std::atomic<uint8_t>& f = e.wanted.flags[r];
    // Lists need not start or end on a run boundary: this thread queues and clears its part.
    const size_t run_first = r * kRunLength;
    const uint8_t part = run_part_bit(run_first < first, run_first + kRunLength > end && end < e.pixel_count);
    if (!(f.load(std::memory_order_relaxed) & part)) continue;
    f.fetch_and(uint8_t(~part), std::memory_order_relaxed);
    w.asked.push_back({uint32_t(std::max(r * kRunLength, first) - first), now});
  }
}

// Renders the next asked-for run (up to `budget` updates) as one batch and announces it to the
// display; returns the updates rendered. The walk's position and counters do not move.
uint64_t serve_asked(Engine::Impl& e, FramelessWorker& w, ThreadCounters& ctr, double t, double dt,
                     uint64_t budget) {
  const std::vector<uint32_t>& list = *w.pixels;
  size_t pos0 = 0, len = 0;
  // Runs whose pixels were all updated since the ask was queued (the walk got there first) are
  // dropped: the display asked for a newer sample, and it has one.
  while (w.asked_next < w.asked.size()) {
    const FramelessWorker::AskedRun run = w.asked[w.asked_next++];
    pos0 = run.pos;
    // A run that began in the previous thread's list (thread lists need not start on a run
    // boundary) ends kRunLength slots after its start, not after this list's first slot.
    len = std::min<size_t>({kRunLength - (w.first_slot + pos0) % kRunLength, list.size() - pos0, size_t(budget)});
    bool since = true;  // every pixel of the run updated since it was queued
    for (size_t k = 0; k < len && since; ++k)
      since = e.states[w.first_slot + pos0 + k].time.load(std::memory_order_relaxed) > run.time;
    if (!since) break;
    len = 0;
  }
  if (len == 0) return 0;
  PacketBatch b;
  for (size_t k = 0; k < len; ++k) {
    b.idx[b.n] = list[pos0 + k];
    b.state[b.n] = &e.states[w.first_slot + pos0 + k];
    b.t[b.n] = t + dt * double(k);
    b.frame[b.n] = nullptr;
    ++b.n;
  }
  trace_batch(e, b, w.basis, w.moving ? &w.frame : nullptr, &w.world);
  for (int k = 0; k < b.n; ++k) {
    finish_update(e, b.idx[k], *b.state[k], w.epoch, float(b.t[k]), ctr, nullptr,
                  w.moving ? &w.frame : nullptr, b.r[k]);
    log_update(e, w, b.idx[k], float(b.t[k]));
  }
  e.priority_rings[w.index].push(uint32_t(w.first_slot + pos0));  // after the publishes
  return len;
}

// The frameless walk over a thread's pixel list: up to PacketBatch::kMax consecutive visits are
// gathered in order, traced together, then published in order, adaptive skips included, so every
// counter and pixel sees the sequence of a one-by-one walk. A batch ends before a camera or world
// pick-up and at the end of the list (no pixel twice).
template <bool kAdaptive>
void run_visits(Engine::Impl& e, FramelessWorker& w, uint64_t count, double t_begin,
                        double dt) {
  const std::vector<uint32_t>& list = *w.pixels;
  const size_t n = list.size();
  if (n == 0) return;
  ThreadCounters& ctr = e.counters[w.index];
  const bool closed_loop = e.wanted.runs != 0;
  PacketBatch b;
  constexpr int kMaxEntries = 64;
  int8_t entries[kMaxEntries];  // visit order: a batch slot, or -1 for an adaptive skip
  int m = 0;
  auto flush = [&] {
    if (b.n > 0) trace_batch(e, b, w.basis, w.moving ? &w.frame : nullptr, &w.world);
    for (int k = 0; k < m; ++k) {
      const int slot = entries[k];
      if (slot >= 0) {
        finish_update(e, b.idx[slot], *b.state[slot], w.epoch, float(b.t[slot]), ctr, nullptr,
                      w.moving ? &w.frame : nullptr, b.r[slot]);
        log_update(e, w, b.idx[slot], float(b.t[slot]));
      }
      // The display derives which pixels changed from this counter: publish after the pixel.
      ctr.updates.store(++w.updates, std::memory_order_release);
    }
    b.n = 0;
    m = 0;
  };
  for (uint64_t i = 0; i < count;) {  // i counts rendered updates (adaptive skips do not count)
    if (w.countdown == 1) flush();  // the pick-up below must follow every gathered visit
    if (--w.countdown == 0) {
      w.countdown = w.interval;
      refresh_camera(e, w.epoch, w.basis);
      refresh_world(e, w, t_begin + dt * double(i));
      if (closed_loop) scan_asked(e, w, float(t_begin + dt * double(i)));
    }
    const size_t pos = w.pos;
    const uint32_t idx = list[pos];
    // A packet never spans two chunks, which lie far apart in the image once shuffled: adaptive
    // skips and asked runs shift the batches off the chunk grid, and a straddling packet costs
    // several times more. A countdown, not a division per visit, finds the chunk starts.
    if (w.chunk_left == 0) {
      if (b.n > 0) flush();
      w.chunk_left = e.partition.chunk_length(w.index, pos);
    }
    --w.chunk_left;
    PixelState& p = e.states[w.first_slot + pos];
    const bool wrapped = ++w.pos == n;
    if (wrapped) w.pos = 0;
    bool skip = false;
    if constexpr (kAdaptive) skip = adaptive_skip(e.cfg.adaptive, p, w.epoch, w.adaptive.skip_run[pos]);
    if (skip) {
      entries[m++] = -1;
    } else {
      b.idx[b.n] = idx;
      b.state[b.n] = &p;
      b.t[b.n] = t_begin + dt * double(i);
      entries[m++] = int8_t(b.n++);
      ++i;
    }
    if (wrapped || b.n == PacketBatch::kMax || m == kMaxEntries) {
      flush();
      // One asked-for run after each batch of the walk: the walk keeps at least half the updates.
      if (closed_loop && w.asked_next < w.asked.size() && i < count)
        i += serve_asked(e, w, ctr, t_begin + dt * double(i), dt, count - i);
    }
  }
  flush();
}

}  // namespace

void frameless_run(Engine::Impl& e, FramelessWorker& w, uint64_t count, double t_begin, double dt) {
  if (e.cfg.adaptive.enabled) {
    if (w.adaptive.skip_run.size() != w.pixels->size()) w.adaptive.skip_run.assign(w.pixels->size(), 0);
    run_visits<true>(e, w, count, t_begin, dt);
  } else {
    run_visits<false>(e, w, count, t_begin, dt);
  }
}

void frameless_thread_main(Engine::Impl& e, int t) {
  enable_flush_to_zero();
  try {
    FramelessWorker& w = e.workers[size_t(t)];
    // Batches of visits share one clock reading; the stop flag is checked between batches.
    constexpr uint64_t kBatch = 16;
    const uint64_t cpu0 = thread_cpu_ns();
    ThreadCounters& ctr = e.counters[t];
    // A sample-rate cap: this thread's share of it, as the time its samples so far should take.
    const int spu = samples_per_update(e.cfg);
    const double share = e.cfg.max_samples_per_s / double(std::max<size_t>(1, e.workers.size()));
    const auto start = std::chrono::steady_clock::now();
    for (uint64_t batch = 1; !e.stop_flag.load(std::memory_order_relaxed); ++batch) {
      frameless_run(e, w, kBatch, e.now(), 0.0);
      // Busy time for the balance statistics: one clock read per 64 batches keeps it off the hot path.
      if (batch % 64 == 0) ctr.busy_ns.store(thread_cpu_ns() - cpu0, std::memory_order_relaxed);
      if (share > 0.0 && batch % 4 == 0) {
        const auto due = start + std::chrono::duration_cast<std::chrono::steady_clock::duration>(
                                     std::chrono::duration<double>(double(batch * kBatch * uint64_t(spu)) / share));
        // In slices of at most 20 ms, so a stop is seen soon whatever the cap.
        while (due > std::chrono::steady_clock::now() + std::chrono::milliseconds(1) &&
               !e.stop_flag.load(std::memory_order_relaxed))
          std::this_thread::sleep_until(std::min(due, std::chrono::steady_clock::now() + std::chrono::milliseconds(20)));
      }
    }
    ctr.busy_ns.store(thread_cpu_ns() - cpu0, std::memory_order_relaxed);
  } catch (const std::exception& ex) {
    e.record_error(std::string("render thread ") + std::to_string(t) + ": " + ex.what());
  } catch (...) {
    e.record_error("render thread " + std::to_string(t) + ": unknown exception");
  }
}

void conventional_range(Engine::Impl& e, int t, const FrameState& f, size_t begin, size_t end,
                        double t_begin, double dt, PixelSnapshot* frame, PixelRecord* out) {
  ThreadCounters& ctr = e.counters[t];
  // A conventional frame sees one instant: its world is evaluated once per frame and thread.
  FramelessWorker& w = e.workers[size_t(t)];
  if (w.frame_serial != f.serial) {
    w.moving = !e.scene.dynamic.empty() || f.world_epoch > 1 || f.instances;
    if (w.moving) evaluate_frame(e.scene, f.world, f.time, w.frame);
    w.frame.instances = f.instances;
    w.frame_serial = f.serial;
  }
  const DynamicFrame* world = w.moving ? &w.frame : nullptr;
  // Consecutive pixels of a tile row as batches; the frame's world stays at one instant.
  PacketBatch b;
  for (size_t i = begin; i < end;) {  // in conventional mode slot i holds job_pixels[i]
    const size_t first = i;
    for (b.n = 0; b.n < PacketBatch::kMax && i < end; ++b.n, ++i) {
      b.idx[b.n] = e.job_pixels[i];
      b.state[b.n] = &e.states[i];
      b.t[b.n] = t_begin + dt * double(i - begin);
      b.frame[b.n] = frame ? &frame[e.job_pixels[i]] : nullptr;
    }
    trace_batch(e, b, f.basis, w.moving ? &w.frame : nullptr, nullptr);
    for (int k = 0; k < b.n; ++k)
      finish_update(e, b.idx[k], *b.state[k], f.epoch, float(b.t[k]), ctr, b.frame[k], world, b.r[k]);
    if (out)  // this thread wrote the states: relaxed reads are exact
      for (int k = 0; k < b.n; ++k) out[first + size_t(k) - begin] = record_of(e, *b.state[k], b.idx[k]);
  }
  ctr.updates.store(ctr.updates.load(std::memory_order_relaxed) + (end - begin),
                    std::memory_order_release);
}

void render_piece(Engine::Impl& e, int t, PieceJob& job) {
  const FramePiece& p = job.piece;
  // Handed-over states: whoever rendered these pixels last continues here (see PieceJob).
  for (size_t k = 0; k < job.in.size(); ++k) {
    const PixelRecord& r = job.in[k];
    PixelState& s = e.states[p.begin + k];
    s.passes.store(r.passes, std::memory_order_relaxed);
    const uint32_t idx = e.job_pixels[p.begin + k];
    publish_state(s, r.count, r.epoch, r.mean, r.m2, r.sample, r.time,
                  [&] { e.levels[idx].store(r.levels, std::memory_order_relaxed); });
  }
  ThreadCounters& ctr = e.counters[t];
  const uint64_t samples0 = ctr.samples.load(std::memory_order_relaxed);
  const uint64_t dropped0 = ctr.dropped.load(std::memory_order_relaxed);
  job.out.resize(p.end - p.begin);
  conventional_range(e, t, *job.frame, p.begin, p.end, p.t_begin, p.dt, nullptr, job.out.data());
  job.samples = ctr.samples.load(std::memory_order_relaxed) - samples0;
  job.dropped = ctr.dropped.load(std::memory_order_relaxed) - dropped0;
}

void piece_thread_main(Engine::Impl& e, int t) {
  enable_flush_to_zero();
  try {
    const uint64_t cpu0 = thread_cpu_ns();
    std::unique_ptr<PieceJob> job;
    while (e.feed->next(t, job)) {
      render_piece(e, t, *job);
      e.feed->done(t, std::move(job));
      e.counters[t].busy_ns.store(thread_cpu_ns() - cpu0, std::memory_order_relaxed);
    }
  } catch (const std::exception& ex) {
    e.record_error(std::string("render thread ") + std::to_string(t) + ": " + ex.what());
  } catch (...) {
    e.record_error("render thread " + std::to_string(t) + ": unknown exception");
  }
}

void fill_frame(Engine::Impl& e, FrameState& f, uint64_t serial) {
  f.camera = e.channel.read(&f.epoch);
  f.basis = make_camera_basis(f.camera, e.partition.width, e.partition.height);
  f.time = e.now();
  if (e.world_channel.epoch() != f.world_epoch) {
    f.world_epoch = e.world_channel.read(e.frame_world_buf);
    unpack_world(e.frame_world_buf.data(), e.frame_world_buf.size(), f.world);
  }
  e.pick_up_instances(f.instances_epoch, f.instances);
  f.serial = serial;
}

void begin_frame(Engine::Impl& e) {
  e.frame_pos = 0;
  fill_frame(e, e.frame, e.frame.serial + 1);
}

void publish_frame(Engine::Impl& e) {
  const uint32_t old = e.frames.middle.exchange(e.frames.back | FrameBuffers::kNew,
                                                std::memory_order_acq_rel);
  e.frames.back = e.frames.back2;
  e.frames.back2 = old & 3u;
  e.frames.completed.fetch_add(1, std::memory_order_release);
}

void Engine::Impl::FrameDone::operator()() noexcept {
  // Runs on one thread once all have arrived: publish the finished frame, start the next.
  e->frame_stop = e->stop_flag.load(std::memory_order_relaxed);
  if (!e->frame_stop) {
    publish_frame(*e);
    begin_frame(*e);
  }
  e->next_job.store(0, std::memory_order_relaxed);
}

void conventional_thread_main(Engine::Impl& e, int t) {
  enable_flush_to_zero();
  try {
    const uint64_t cpu0 = thread_cpu_ns();
    for (;;) {
      for (;;) {
        const uint32_t j = e.next_job.fetch_add(1, std::memory_order_relaxed);
        if (j >= e.jobs.size()) break;
        if (e.stop_flag.load(std::memory_order_relaxed)) continue;  // drain quickly on stop
        // Job j covers a contiguous range of job_pixels (tiles are laid out in job order).
        const size_t px_begin = e.job_first_pixel[j];
        const size_t px_end = e.job_first_pixel[j + 1];
        conventional_range(e, t, e.frame, px_begin, px_end, e.now(), 0.0,
                           e.frames.buf[e.frames.back].data(), nullptr);
        e.counters[t].busy_ns.store(thread_cpu_ns() - cpu0, std::memory_order_relaxed);  // per job
      }
      e.barrier->arrive_and_wait();
      if (e.frame_stop) break;
    }
  } catch (const std::exception& ex) {
    e.record_error(std::string("render thread ") + std::to_string(t) + ": " + ex.what());
    e.barrier->arrive_and_drop();
  } catch (...) {
    e.record_error("render thread " + std::to_string(t) + ": unknown exception");
    e.barrier->arrive_and_drop();
  }
}

void pool_thread_main(Engine::Impl& e, int t) {
  enable_flush_to_zero();
  uint64_t seen = 0;
  for (;;) {
    std::function<void(int)>* task = nullptr;
    {
      std::unique_lock<std::mutex> lock(e.pool_mutex);
      e.pool_cv.wait(lock, [&] { return e.pool_quit || e.pool_generation != seen; });
      if (e.pool_quit) return;
      seen = e.pool_generation;
      task = &e.pool_task;
    }
    try {
      (*task)(t);
    } catch (const std::exception& ex) {
      e.record_error(std::string("render thread ") + std::to_string(t) + ": " + ex.what());
    } catch (...) {
      e.record_error("render thread " + std::to_string(t) + ": unknown exception");
    }
    std::lock_guard<std::mutex> lock(e.pool_mutex);
    if (--e.pool_pending == 0) e.pool_done_cv.notify_all();
  }
}

}  // namespace frameless
