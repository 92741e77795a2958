// The whole render -> display -> consumer exchange with real threads (run under ThreadSanitizer
// in CI): 4 render threads, the display thread at 240 Hz, camera changes at 1 kHz, a consumer
// taking images through the triple buffer and the on-tick callback, and layout changes (thread
// count, mode, size) while everything runs. The eye shader paints camera k's epoch value k into every
// channel and the blend weight is 1, so every displayed pixel must read exactly its epoch layer:
// a torn pixel, a pixel moved to the wrong slot or a half-copied buffer would break that.
#include <gtest/gtest.h>

#include <atomic>
#include <chrono>
#include <cstdlib>
#include <thread>

#include "../engine/test_shaders.h"
#include "display/display_thread.h"

namespace frameless {
namespace {

using namespace frameless::testing;
using Clock = std::chrono::steady_clock;

// Pixels of `img` whose colour is not exactly their epoch in all three channels.
uint64_t inconsistent_pixels(const DisplayImage& img) {
  uint64_t bad = 0;
  for (size_t i = 0; i < img.epoch.size(); ++i) {
    if (img.epoch[i] == 0) continue;
    const float v = float(img.epoch[i]);
    bad += img.rgb[3 * i] != v || img.rgb[3 * i + 1] != v || img.rgb[3 * i + 2] != v;
  }
  return bad;
}

TEST(DisplayExchange, WholePixelsThroughCameraStormAndLayoutChanges) {
  const double seconds = std::getenv("FRAMELESS_LONG_TESTS") ? 30.0 : 2.0;
  EngineConfig c = test_config(96, 64, 4, eye_shader);
  c.update_percent = 0.5;
  Engine e(kEmptyScene, c, camera_at(1.0f));  // epoch 1 paints 1.0
  DisplayConfig dc;
  dc.refresh_hz = 240;
  dc.blend.alpha = 1.0f;
  DisplayThread d(e, dc);
  std::atomic<uint64_t> tick_images{0}, tick_bad{0};
  d.set_on_tick([&](const DisplayImage& img) {
    ++tick_images;
    tick_bad += inconsistent_pixels(img);
  });
  std::atomic<bool> done{false};
  uint64_t consumed = 0, consumed_bad = 0, shown = 0;
  std::thread consumer([&] {
    while (!done.load()) {
      bool fresh = false;
      const DisplayImage& img = d.acquire_latest(&fresh);
      if (fresh) {
        ++consumed;
        consumed_bad += inconsistent_pixels(img);
        for (uint32_t ep : img.epoch) shown += ep != 0;
      }
      std::this_thread::sleep_for(std::chrono::milliseconds(2));
    }
  });
  e.start();
  d.start();
  // Camera storm at 1 kHz from this (control) thread, with a layout change every quarter:
  // camera k paints k and its epoch is k (single publisher).
  const auto begin = Clock::now();
  const auto end = begin + std::chrono::duration<double>(seconds);
  uint32_t expected = 1;
  int quarter = 0;
  auto next = begin;
  while (Clock::now() < end) {
    next += std::chrono::milliseconds(1);
    std::this_thread::sleep_until(next);
    ++expected;
    ASSERT_EQ(e.publish_camera(camera_at(float(expected))), expected);
    const int q = int(4.0 * std::chrono::duration<double>(Clock::now() - begin).count() / seconds);
    if (q == quarter) continue;
    quarter = q;
    if (q == 1) e.set_threads(3);                    // new partition: every pixel changes slot
    if (q == 2) e.set_mode(RenderMode::conventional);  // slot order becomes pixel order
    if (q == 3) {
      e.resize(80, 56);  // size and layout must reach the display together
      e.set_mode(RenderMode::frameless);
    }
  }
  d.stop();
  done = true;
  consumer.join();
  e.stop();
  EXPECT_FALSE(e.error());
  EXPECT_FALSE(d.error());
  const DisplayStats s = d.stats();
  EXPECT_GT(s.ticks, 20u);  // generous: the machine may be loaded
  EXPECT_GT(s.mean_interval, 0.0);
  EXPECT_GT(s.cpu_seconds, 0.0);
  EXPECT_GT(s.pixels_updated, 0u);
  EXPECT_GT(consumed, 0u);
  EXPECT_GT(shown, 0u);
  EXPECT_GT(tick_images.load(), 0u);
  EXPECT_EQ(consumed_bad, 0u);
  EXPECT_EQ(tick_bad.load(), 0u);
}

}  // namespace
}  // namespace frameless
