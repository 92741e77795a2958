// Concurrency stress of the render/display exchange (run under ThreadSanitizer in CI): 4 render
// threads, a collector at 240 Hz, camera changes at 1 kHz, about 3 seconds
// (FRAMELESS_LONG_TESTS=1: 30 s). Every collected pixel must be whole: the eye shader paints
// each camera's epoch into all channels, so a torn read would mix values.
#include <gtest/gtest.h>

#include <atomic>
#include <chrono>
#include <cstdlib>
#include <thread>

#include "collecting_sink.h"
#include "frameless/engine.h"
#include "test_shaders.h"

namespace frameless {
namespace {

using namespace frameless::testing;
using Clock = std::chrono::steady_clock;

TEST(ExchangeStress, NoTornPixelsUnderCameraStorm) {
  const double seconds = std::getenv("FRAMELESS_LONG_TESTS") ? 30.0 : 3.0;
  for (RenderMode mode : {RenderMode::frameless, RenderMode::conventional}) {
    EngineConfig c = test_config(96, 64, 4, eye_shader);
    c.mode = mode;
    c.update_percent = 0.5;
    Engine e(kEmptyScene, c, camera_at(1.0f));  // epoch 1 paints 1.0
    e.start();
    std::atomic<bool> done{false};
    uint64_t collected = 0, bad = 0, backwards = 0;
    std::thread display([&] {
      UpdateCursor cursor;
      CollectingSink sink;
      std::vector<uint32_t> last_epoch(size_t(96) * 64, 0);
      auto next = Clock::now();
      while (!done.load()) {
        next += std::chrono::microseconds(4167);  // 240 Hz
        std::this_thread::sleep_until(next);
        e.collect(cursor, sink);
        for (const CollectedPixel& u : sink.updates) {
          const float v = float(u.state.epoch);
          const PixelSnapshot& s = u.state;
          if (s.sample != Vec3(v) || s.mean != Vec3(v) || s.variance != 0.0f) ++bad;
          if (s.epoch < last_epoch[u.pixel]) ++backwards;
          last_epoch[u.pixel] = s.epoch;
          ++collected;
        }
      }
    });
    // Camera storm at 1 kHz: camera k paints k, and its epoch is k (single publisher).
    const auto end = Clock::now() + std::chrono::duration<double>(seconds / 2);
    uint32_t expected = 1;
    auto next = Clock::now();
    while (Clock::now() < end) {
      next += std::chrono::milliseconds(1);
      std::this_thread::sleep_until(next);
      ++expected;
      ASSERT_EQ(e.publish_camera(camera_at(float(expected))), expected);
    }
    done = true;
    display.join();
    e.stop();
    EXPECT_FALSE(e.error());
    EXPECT_GT(collected, 1000u) << to_string(mode);
    EXPECT_EQ(bad, 0u) << to_string(mode);
    EXPECT_EQ(backwards, 0u) << to_string(mode);
    EXPECT_GT(e.stats().samples, 0u);
  }
}

}  // namespace
}  // namespace frameless
