#include "frameless/tile_render.h"

#include <pmmintrin.h>
#include <xmmintrin.h>

#include <algorithm>
#include <chrono>
#include <thread>

#include "core/accel/instance_top.h"
#include "core/scene/instance_moves.h"
#include "core/shading/render_sample.h"

namespace frameless {

void enable_flush_to_zero() {
  _MM_SET_FLUSH_ZERO_MODE(_MM_FLUSH_ZERO_ON);
  _MM_SET_DENORMALS_ZERO_MODE(_MM_DENORMALS_ZERO_ON);
}

namespace {

constexpr int kTile = 16;

void render_tile(const Scene& scene, const CameraBasis& camera, const TileRenderOptions& o,
                 const DynamicFrame* frame, int x0, int y0, RenderedImage& img, uint64_t& dropped) {
  const int x1 = std::min(x0 + kTile, img.width), y1 = std::min(y0 + kTile, img.height);
  for (int y = y0; y < y1; ++y)
    for (int x = x0; x < x1; ++x) {
      const size_t i = size_t(y) * img.width + x;
      Vec3 sum(0.0f);
      int n = 0;
      uint8_t levels = 0;
      for (int s = 0; s < o.spp; ++s) {
        const SampleResult r = render_sample(scene, camera, x, y, o.first_sample + s, o.jitter, frame);
        if (!r.valid) {
          ++dropped;
          continue;
        }
        if (n == 0) {
          img.depth[i] = r.depth;
          img.normal[3 * i] = r.normal.x, img.normal[3 * i + 1] = r.normal.y,
                     img.normal[3 * i + 2] = r.normal.z;
        }
        sum += r.color;
        levels = std::max(levels, r.levels);
        ++n;
      }
      const Vec3 mean = n ? sum / float(n) : Vec3(0.0f);
      img.rgb[3 * i] = mean.x, img.rgb[3 * i + 1] = mean.y, img.rgb[3 * i + 2] = mean.z;
      img.samples[i] = float(n);
      img.levels[i] = levels;
    }
}

}  // namespace

RenderedImage render_tiles(const Scene& scene, const CameraBasis& camera,
                           const TileRenderOptions& o) {
  const auto start = std::chrono::steady_clock::now();
  // Moving objects sit where they are at o.time; one read-only frame serves every worker.
  DynamicFrame frame;
  const DynamicFrame* frame_ptr = nullptr;
  if (!scene.dynamic.empty() || !scene.instance_motions.empty()) {
    evaluate_frame(scene, initial_world(scene), o.time, frame);
    frame_ptr = &frame;
  }
  if (!scene.instance_motions.empty()) {  // animated instances too, in a top level of their own
    auto moved = move_instances(*scene.accel.instance_top(), instance_moves_at(scene, o.time));
    if (moved) frame.instances = std::move(*moved);  // motions are finite offsets: always ok
  }
  RenderedImage img;
  img.width = camera.width;
  img.height = camera.height;
  const size_t n = size_t(img.width) * img.height;
  img.rgb.assign(3 * n, 0.0f);
  img.depth.assign(n, kInfinity);
  img.normal.assign(3 * n, 0.0f);
  img.samples.assign(n, 0.0f);
  img.levels.assign(n, 0);

  const int tiles_x = (img.width + kTile - 1) / kTile, tiles_y = (img.height + kTile - 1) / kTile;
  const int tiles = tiles_x * tiles_y;
  std::atomic<int> next{0}, done{0};
  std::atomic<uint64_t> dropped{0};
  auto worker = [&] {
    enable_flush_to_zero();
    uint64_t local_dropped = 0;
    for (int t; (t = next.fetch_add(1, std::memory_order_relaxed)) < tiles;) {
      render_tile(scene, camera, o, frame_ptr, (t % tiles_x) * kTile, (t / tiles_x) * kTile, img,
                  local_dropped);
      done.fetch_add(1, std::memory_order_release);
    }
    dropped.fetch_add(local_dropped, std::memory_order_relaxed);
  };
  const int threads = std::max(1, o.threads);
  const bool report = bool(o.progress);
  std::vector<std::thread> pool;
  // With progress the caller's thread only reports (it sleeps); otherwise it works too.
  for (int i = report ? 0 : 1; i < threads; ++i) pool.emplace_back(worker);
  if (report) {
    while (done.load(std::memory_order_acquire) < tiles) {
      o.progress(double(done.load(std::memory_order_relaxed)) / tiles);
      std::this_thread::sleep_for(std::chrono::milliseconds(100));
    }
  } else {
    // The caller works too: its own floating-point mode is restored afterwards.
    const unsigned int csr = _mm_getcsr();
    worker();
    _mm_setcsr(csr);
  }
  for (auto& t : pool) t.join();
  if (o.progress) o.progress(1.0);
  img.dropped = dropped.load();
  img.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return img;
}

}  // namespace frameless
