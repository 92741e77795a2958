// Light that bounces through the whole exchange with real threads (run under ThreadSanitizer in
// CI): igi on 3 render threads keeps each pixel's indirect mean and guides while the display
// thread (200 Hz) reads them for the discontinuity buffer and the denoiser, the camera moves, and
// a consumer takes images through the triple buffer and the on-tick callback.
#include <gtest/gtest.h>

#include <atomic>
#include <chrono>
#include <cmath>
#include <cstdlib>
#include <thread>

#include "core/scene/scene_finalize.h"
#include "core/scenes/builtin_scenes.h"
#include "display/display_thread.h"

namespace frameless {
namespace {

using Clock = std::chrono::steady_clock;

bool all_finite(const DisplayImage& img) {
  for (float v : img.rgb)
    if (!std::isfinite(v) || v < 0.0f) return false;
  return true;
}

TEST(GiDisplayExchange, IgiFiltersReadWhatRenderThreadsWrite) {
  const double seconds = std::getenv("FRAMELESS_LONG_TESTS") ? 20.0 : 1.5;
  auto scene = make_cornell();
  scene->settings.integrator = Integrator::kIgi;
  finalize_scene(*scene);
  EngineConfig c;
  c.width = 64;
  c.height = 48;
  c.threads = 3;
  c.track_variance = true;  // the denoiser's luminance weights
  Engine e(*scene, c, scene->camera);
  DisplayConfig dc;
  dc.refresh_hz = 200;
  dc.blend.denoise = true;
  dc.blend.discontinuity = true;
  DisplayThread d(e, dc);
  std::atomic<uint64_t> ticks{0}, bad{0};
  d.set_on_tick([&](const DisplayImage& img) {
    ++ticks;
    bad += !all_finite(img);
  });
  e.start();
  d.start();
  const auto begin = Clock::now();
  uint64_t consumed = 0, consumed_bad = 0;
  Camera cam = scene->camera;
  while (Clock::now() - begin < std::chrono::duration<double>(seconds)) {
    std::this_thread::sleep_for(std::chrono::milliseconds(5));
    cam.eye.x = 0.1f * std::sin(float(consumed));
    e.publish_camera(cam);
    bool fresh = false;
    const DisplayImage& img = d.acquire_latest(&fresh);
    if (fresh) {
      ++consumed;
      consumed_bad += !all_finite(img);
    }
  }
  d.stop();
  e.stop();
  EXPECT_FALSE(e.error());
  EXPECT_FALSE(d.error());
  EXPECT_GT(ticks.load(), 5u);
  EXPECT_GT(consumed, 0u);
  EXPECT_EQ(bad.load(), 0u);
  EXPECT_EQ(consumed_bad, 0u);
}

}  // namespace
}  // namespace frameless
