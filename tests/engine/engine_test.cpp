// Engine behaviour in deterministic mode (camera pickup bound, reproducibility, NaN handling,
// convergence) and in wall-clock mode (runs, reconfigures, reports a failing thread).
#include "frameless/engine.h"

#include <gtest/gtest.h>

#include <chrono>
#include <cmath>
#include <cstring>
#include <thread>

#include "frameless/camera_channel.h"
#include "test_shaders.h"

namespace frameless {
namespace {

using namespace frameless::testing;

std::vector<PixelSnapshot> snapshot(const Engine& e) {
  std::vector<PixelSnapshot> out(size_t(e.width()) * size_t(e.height()));
  for (int y = 0; y < e.height(); ++y)
    for (int x = 0; x < e.width(); ++x) e.read_pixel(x, y, out[size_t(y) * e.width() + x]);
  return out;
}

bool bit_identical(const std::vector<PixelSnapshot>& a, const std::vector<PixelSnapshot>& b) {
  if (a.size() != b.size()) return false;
  for (size_t i = 0; i < a.size(); ++i) {
    const auto& p = a[i];
    const auto& q = b[i];
    if (std::memcmp(&p.sample, &q.sample, sizeof p.sample) || std::memcmp(&p.mean, &q.mean, sizeof p.mean) ||
        std::memcmp(&p.variance, &q.variance, 4) || p.count != q.count || p.epoch != q.epoch ||
        std::memcmp(&p.time, &q.time, 4))
      return false;
  }
  return true;
}

TEST(CameraChannel, EpochsIncreaseAndReadsAreWhole) {
  CameraChannel ch(camera_at(0));
  EXPECT_EQ(ch.epoch(), 1u);
  EXPECT_EQ(ch.publish(camera_at(3)), 2u);
  uint32_t e = 0;
  EXPECT_EQ(ch.read(&e), camera_at(3));
  EXPECT_EQ(e, 2u);
}

// With update percentage p, each thread uses a new camera within ceil(p n_t) + 1 of its own updates.
TEST(Engine, CameraPickupWithinUpdatePercentBound) {
  for (double percent : {0.01, 0.5, 3.0, 25.0, 100.0}) {
    EngineConfig c = test_config(64, 48, 3, noisy_shader);
    c.deterministic = true;
    c.update_percent = percent;
    c.samples_per_tick = 1000;
    c.update_log_capacity = 100000;
    Engine e(kEmptyScene, c, camera_at(0));
    for (int k = 0; k < 7; ++k) e.advance(0.01);
    std::vector<size_t> before;
    for (int t = 0; t < 3; ++t) before.push_back(e.update_log(t).records.size());
    const uint32_t epoch = e.publish_camera(camera_at(1));
    for (int k = 0; k < 40; ++k) e.advance(0.01);
    std::vector<size_t> delays;
    for (int t = 0; t < 3; ++t) {
      const auto& rec = e.update_log(t).records;
      const double n = double(e.partition().pixels[size_t(t)].size());
      const size_t bound = size_t(std::ceil(percent / 100.0 * n)) + 1;
      size_t i = before[size_t(t)];
      while (i < rec.size() && rec[i].epoch != epoch) ++i;
      ASSERT_LT(i, rec.size()) << "thread " << t << " never picked up the camera";
      const size_t delay = i - before[size_t(t)] + 1;  // 1-based: the delay-th update used it
      EXPECT_LE(delay, bound) << "p=" << percent << " thread " << t;
      for (; i < rec.size(); ++i) ASSERT_EQ(rec[i].epoch, epoch);  // never goes back
      delays.push_back(delay);
    }
    if (percent == 25.0) {
      // Staggered: threads do not all switch at the same point of their sweep.
      EXPECT_FALSE(delays[0] == delays[1] && delays[1] == delays[2]);
    }
  }
}

TEST(Engine, DeterministicRunsAreBitIdentical) {
  for (RenderMode mode : {RenderMode::frameless, RenderMode::conventional}) {
    auto run = [&](uint64_t seed, int threads) {
      EngineConfig c = test_config(45, 31, threads, noisy_shader);
      c.deterministic = true;
      c.mode = mode;
      c.seed = seed;
      c.samples_per_tick = 700;
      Engine e(kEmptyScene, c, camera_at(0));
      for (int k = 0; k < 30; ++k) {
        if (k == 10) e.publish_camera(camera_at(0.5f));
        if (k == 17) e.publish_camera(camera_at(-0.5f));
        e.advance(1.0 / 60);
      }
      return snapshot(e);
    };
    const auto a = run(5, 3);
    EXPECT_TRUE(bit_identical(a, run(5, 3))) << to_string(mode);
    EXPECT_FALSE(bit_identical(a, run(6, 3))) << to_string(mode);  // the comparison can fail
  }
}

TEST(Engine, NonFiniteSamplesAreDroppedAndCounted) {
  for (RenderMode mode : {RenderMode::frameless, RenderMode::conventional}) {
    EngineConfig c = test_config(30, 20, 2, nan_shader);
    c.deterministic = true;
    c.mode = mode;
    c.samples_per_tick = 600;
    Engine e(kEmptyScene, c, camera_at(0));
    for (int k = 0; k < 12; ++k) e.advance(0.01);
    const EngineStats s = e.stats();
    EXPECT_GT(s.dropped, 0u);
    EXPECT_LT(s.dropped, s.samples);
    for (const PixelSnapshot& p : snapshot(e)) {
      EXPECT_TRUE(is_finite(p.sample) && is_finite(p.mean) && std::isfinite(p.variance));
    }
    PixelSnapshot row3;
    e.read_pixel(4, 3, row3);
    EXPECT_EQ(row3.epoch, 0u);  // every sample invalid: never published
  }
}

TEST(Engine, StillCameraConvergesAndMovingCameraRestarts) {
  EngineConfig c = test_config(16, 16, 2, noisy_shader);
  c.deterministic = true;
  c.samples_per_tick = 256 * 2;  // one sweep per tick
  c.track_variance = true;       // off by default: this test reads it
  Engine e(kEmptyScene, c, camera_at(0));
  for (int k = 0; k < 50; ++k) e.advance(0.01);
  PixelSnapshot p;
  ASSERT_TRUE(e.read_pixel(3, 9, p));
  EXPECT_EQ(p.count, 100u);  // 50 updates x 2 samples
  // Noise is 0.1 U(0,1): mean 0.05 above the pixel's smooth value, variance 0.01/12 per channel.
  EXPECT_NEAR(p.mean.z, 0.55f, 0.01f);
  EXPECT_NEAR(p.variance, 0.01 / 12, 0.0004);
  e.publish_camera(camera_at(1));
  for (int k = 0; k < 3; ++k) e.advance(0.01);
  ASSERT_TRUE(e.read_pixel(3, 9, p));
  EXPECT_EQ(p.epoch, 2u);
  EXPECT_LE(p.count, 6u);  // restarted with the new camera
  EXPECT_NEAR(p.mean.z, 0.65f, 0.05f);
}

TEST(Engine, WallClockRendersAndReconfigures) {
  EngineConfig c = test_config(40, 30, 2, noisy_shader);
  Engine e(kEmptyScene, c, camera_at(0));
  e.start();
  std::this_thread::sleep_for(std::chrono::milliseconds(50));
  EXPECT_GT(e.stats().samples, 0u);
  e.resize(50, 20);
  EXPECT_EQ(e.partition().width, 50);
  e.set_mode(RenderMode::conventional);
  e.set_threads(3);
  e.set_update_percent(10);
  std::this_thread::sleep_for(std::chrono::milliseconds(50));
  const EngineStats s = e.stats();
  EXPECT_EQ(s.threads.size(), 3u);
  EXPECT_GT(s.frames_completed, 0u);
  e.stop();
  EXPECT_FALSE(e.running());
  EXPECT_FALSE(e.error());
}

// The conventional mode measures its frame barrier (bench scaling reports it): one release per
// frame after the first, worst at least the mean, all finite; frameless mode has no barrier.
TEST(Engine, ConventionalModeMeasuresItsFrameBarrier) {
  EngineConfig c = test_config(40, 30, 2, noisy_shader);
  c.mode = RenderMode::conventional;
  Engine e(kEmptyScene, c, camera_at(0));
  e.start();
  std::this_thread::sleep_for(std::chrono::milliseconds(100));
  const EngineStats s = e.stats();
  e.stop();
  ASSERT_GT(s.frames_completed, 2u);
  EXPECT_GE(s.barrier_frames + 2, s.frames_completed);  // every barrier but the newest measured
  EXPECT_GT(s.barrier_frames, 0u);
  EXPECT_TRUE(std::isfinite(s.barrier_release_mean_us) && s.barrier_release_mean_us >= 0.0);
  EXPECT_GE(s.barrier_release_max_us, s.barrier_release_mean_us);
  EXPECT_GE(s.barrier_completion_mean_us, 0.0);
  EXPECT_GE(s.barrier_wait_mean_us, 0.0);
  EngineConfig f = test_config(40, 30, 2, noisy_shader);
  Engine g(kEmptyScene, f, camera_at(0));
  g.start();
  std::this_thread::sleep_for(std::chrono::milliseconds(30));
  EXPECT_EQ(g.stats().barrier_frames, 0u);
  g.stop();
}

TEST(Engine, FailingRenderThreadStopsEngineWithError) {
  for (bool deterministic : {false, true}) {
    EngineConfig c = test_config(20, 20, 2, throwing_shader);
    c.deterministic = deterministic;
    Engine e(kEmptyScene, c, camera_at(0));
    e.start();
    for (int k = 0; k < 400 && !e.error(); ++k) {
      if (deterministic)
        e.advance(0.01);
      else
        std::this_thread::sleep_for(std::chrono::milliseconds(5));
    }
    ASSERT_TRUE(e.error());
    EXPECT_NE(e.error()->find("shader exploded"), std::string::npos);
  }
}

TEST(Engine, RejectsInvalidConfigAndCamera) {
  EngineConfig c = test_config(20, 20, 1, noisy_shader);
  c.update_percent = 0.001;
  EXPECT_THROW(Engine(kEmptyScene, c, camera_at(0)), std::invalid_argument);
  c.update_percent = 1;
  Engine e(kEmptyScene, c, camera_at(0));
  Camera bad = camera_at(0);
  bad.look = bad.eye;
  EXPECT_THROW(e.publish_camera(bad), std::invalid_argument);
}

}  // namespace
}  // namespace frameless
