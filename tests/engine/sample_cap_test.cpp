// The sample-rate cap (EngineConfig::max_samples_per_s): render threads sleep when ahead of their
// share, so the engine never traces more than the cap allows (plus the batch in flight), still
// renders, stops promptly under a tiny cap, and rejects a negative cap. One-sided bounds only:
// a slow machine traces fewer samples and passes.
#include <gtest/gtest.h>

#include <chrono>
#include <thread>

#include "frameless/engine.h"
#include "test_shaders.h"

namespace frameless {
namespace {

const Scene kNoScene{};

TEST(SampleCap, TheEngineStaysBelowTheCap) {
  EngineConfig c = testing::test_config(32, 32, 2, testing::noisy_shader);
  c.max_samples_per_s = 20000;  // the shader alone runs at millions a second
  Engine e(kNoScene, c, testing::camera_at(0));
  const auto t0 = std::chrono::steady_clock::now();
  e.start();
  std::this_thread::sleep_for(std::chrono::milliseconds(300));
  const uint64_t samples = e.stats().samples;
  const double elapsed = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  e.stop();
  ASSERT_FALSE(e.error());
  EXPECT_GT(samples, 0u);
  // Each thread checks every 4 batches of 16 updates (2 samples each): 128 samples of slack.
  EXPECT_LE(double(samples), c.max_samples_per_s * elapsed + 2 * 128 + 64) << elapsed << " s";
}

TEST(SampleCap, ATinyCapStillStopsPromptly) {
  EngineConfig c = testing::test_config(16, 16, 2, testing::noisy_shader);
  c.max_samples_per_s = 1;  // a thread's first check would wait a minute
  Engine e(kNoScene, c, testing::camera_at(0));
  e.start();
  std::this_thread::sleep_for(std::chrono::milliseconds(50));
  const auto t0 = std::chrono::steady_clock::now();
  e.stop();
  EXPECT_LT(std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count(), 10.0);
  EXPECT_FALSE(e.error());
}

TEST(SampleCap, ANegativeCapIsRejected) {
  EngineConfig c;
  c.max_samples_per_s = -1;
  EXPECT_EQ(validate(c), "max_samples_per_s: must be 0 (no limit) or positive");
}

}  // namespace
}  // namespace frameless
