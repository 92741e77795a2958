// Adaptive frameless sampling: converged pixels are skipped (fewer updates on flat than on noisy
// regions), every pixel's revisit gap stays within the bound, a camera change still reaches every
// pixel within the plain engine's bound, deterministic runs stay bit-identical, and variance
// tracking is off unless something reads it. Deterministic mode, fixed seeds: no statistics.
#include <gtest/gtest.h>

#include <algorithm>
#include <chrono>
#include <cstring>
#include <thread>
#include <vector>

#include "frameless/adaptive.h"
#include "frameless/engine.h"
#include "test_shaders.h"

namespace frameless {
namespace {

// The engine keeps a reference to its scene: a named one outlives every engine (these tests use
// synthetic shaders and never trace it).
const Scene kNoScene{};

using testing::camera_at;
using testing::test_config;

// Left half flat grey (zero variance), right half uniform noise 0.2..0.8 (never converges quickly:
// luminance sd 0.17 needs about 200 samples to reach the default tolerance).
SampleResult half_noisy_shader(const void*, const CameraBasis& b, float px, float, uint64_t seed) {
  SampleResult r;
  if (px < 0.5f * float(b.width)) {
    r.color = Vec3(0.5f);
  } else {
    Rng rng(seed);
    r.color = Vec3(0.2f + 0.6f * rng.next_float());
  }
  return r;
}

constexpr int kW = 32, kH = 32, kThreads = 2;

// A quarter of a sweep of real updates per tick: the tick-level bounds below follow from it.
EngineConfig adaptive_config(bool adaptive, uint32_t max_skips = 7) {
  EngineConfig c = test_config(kW, kH, kThreads, half_noisy_shader);
  c.deterministic = true;
  c.samples_per_tick = uint64_t(kW * kH) * 2 / 4;
  c.adaptive.enabled = adaptive;
  c.adaptive.max_skips = max_skips;
  c.update_log_capacity = 1 << 16;
  return c;
}

struct RunResult {
  std::vector<uint32_t> count;  // samples per pixel in the current epoch
  uint32_t max_gap_ticks = 0;   // largest gap between a pixel's updates (incl. run start and end)
};

RunResult run(const EngineConfig& c, int ticks) {
  Engine e(kNoScene, c, camera_at(0));
  for (int k = 0; k < ticks; ++k) {
    e.note_display_tick(uint32_t(k));
    e.advance(0.01);
  }
  RunResult r;
  std::vector<uint32_t> last(size_t(kW * kH), 0);
  for (int t = 0; t < e.thread_count(); ++t) {
    EXPECT_EQ(e.update_log(t).overflow, 0u);
    for (const UpdateRecord& rec : e.update_log(t).records) {
      r.max_gap_ticks = std::max(r.max_gap_ticks, rec.display_tick - last[rec.pixel]);
      last[rec.pixel] = rec.display_tick;
    }
  }
  for (uint32_t l : last) r.max_gap_ticks = std::max(r.max_gap_ticks, uint32_t(ticks - 1) - l);
  for (int y = 0; y < kH; ++y)
    for (int x = 0; x < kW; ++x) {
      PixelSnapshot p;
      EXPECT_TRUE(e.read_pixel(x, y, p));
      r.count.push_back(p.count);
    }
  return r;
}

double mean_count(const RunResult& r, bool noisy_half) {
  double s = 0;
  for (int y = 0; y < kH; ++y)
    for (int x = 0; x < kW; ++x)
      if ((x >= kW / 2) == noisy_half) s += r.count[size_t(y * kW + x)];
  return s / (kW * kH / 2);
}

TEST(Adaptive, ConvergedPixelsAreSkippedWithinTheRevisitBound) {
  constexpr int kTicks = 200;
  const RunResult plain = run(adaptive_config(false), kTicks);
  const RunResult adaptive = run(adaptive_config(true), kTicks);
  // Plain: every pixel gets the same share. Adaptive: the flat half converges after 4 updates and
  // is then rendered once per 8 sweeps, so the noisy half gets most of the samples.
  EXPECT_NEAR(mean_count(plain, false), mean_count(plain, true), 2.0);
  EXPECT_LT(mean_count(adaptive, false), 0.5 * mean_count(adaptive, true));
  EXPECT_GT(mean_count(adaptive, true), 1.5 * mean_count(plain, true));
  // No starvation: at most max_skips = 7 skips in a row, so a pixel is rendered at least once
  // per 8 sweeps of its thread; a tick holds at least a quarter sweep of visits, so the gap is
  // at most 4 * 8 + 1 ticks.
  EXPECT_LE(adaptive.max_gap_ticks, 4u * 8u + 1u);
  EXPECT_LE(plain.max_gap_ticks, 4u + 1u);
  for (uint32_t n : adaptive.count) EXPECT_GE(n, 8u);
}

TEST(Adaptive, TheRevisitBoundBites) {
  // With 255 skips allowed the flat half is rendered once per 256 sweeps: longer than the run,
  // so the gap check above would fail; it has power.
  const RunResult loose = run(adaptive_config(true, 255), 200);
  EXPECT_GT(loose.max_gap_ticks, 4u * 8u + 1u);
}

// After a camera change no pixel of an old epoch is skipped, so coverage reaches 100% within the
// plain engine's bound: pickup within `interval` visits plus one sweep (n_t visits). With a
// quarter sweep per tick and interval = ceil(1% of 512) = 6 visits, that is 5 ticks.
TEST(Adaptive, CameraChangeStillReachesEveryPixelWithinTheBound) {
  for (bool adaptive : {false, true}) {
    SCOPED_TRACE(adaptive);
    Engine e(kNoScene, adaptive_config(adaptive), camera_at(0));
    for (int k = 0; k < 120; ++k) e.advance(0.01);  // flat half converged and skipping
    const uint32_t epoch = e.publish_camera(camera_at(1));
    auto coverage = [&] {
      int n = 0;
      for (int y = 0; y < kH; ++y)
        for (int x = 0; x < kW; ++x) {
          PixelSnapshot p;
          EXPECT_TRUE(e.read_pixel(x, y, p));
          n += p.epoch == epoch;
        }
      return n;
    };
    for (int k = 0; k < 3; ++k) e.advance(0.01);
    EXPECT_LT(coverage(), kW * kH);  // three quarters of a sweep cannot reach every pixel
    for (int k = 0; k < 2; ++k) e.advance(0.01);
    EXPECT_EQ(coverage(), kW * kH);
  }
}

TEST(Adaptive, DeterministicRunsAreBitIdentical) {
  auto snapshot = [](const EngineConfig& c) {
    Engine e(kNoScene, c, camera_at(0));
    for (int k = 0; k < 80; ++k) {
      if (k == 50) e.publish_camera(camera_at(0.5f));
      e.advance(0.01);
    }
    std::vector<PixelSnapshot> out(size_t(kW * kH));
    for (int i = 0; i < kW * kH; ++i) EXPECT_TRUE(e.read_pixel(i % kW, i / kW, out[size_t(i)]));
    return out;
  };
  EngineConfig c = adaptive_config(true);
  c.update_log_capacity = 0;
  const auto a = snapshot(c), b = snapshot(c);
  for (size_t i = 0; i < a.size(); ++i) {
    ASSERT_EQ(std::memcmp(&a[i].mean, &b[i].mean, sizeof(Vec3)), 0);
    ASSERT_EQ(std::memcmp(&a[i].sample, &b[i].sample, sizeof(Vec3)), 0);
    ASSERT_EQ(std::memcmp(&a[i].variance, &b[i].variance, sizeof(float)), 0);
    ASSERT_EQ(a[i].count, b[i].count);
    ASSERT_EQ(a[i].seq, b[i].seq);
  }
}

// Variance tracking is off by default and then really skips the Welford M2 (variance stays 0);
// asking for it, or enabling adaptive sampling, turns it on.
TEST(Adaptive, VarianceIsTrackedOnlyWhenSomethingReadsIt) {
  auto variance_of = [](const EngineConfig& c) {
    Engine e(kNoScene, c, camera_at(0));
    for (int k = 0; k < 20; ++k) e.advance(0.01);
    PixelSnapshot p;
    EXPECT_TRUE(e.read_pixel(kW - 1, 3, p));  // a noisy pixel
    return p.variance;
  };
  EngineConfig c = adaptive_config(false);
  EXPECT_FALSE(c.track_variance);
  EXPECT_FALSE(tracks_variance(c));
  EXPECT_EQ(variance_of(c), 0.0f);
  c.track_variance = true;
  EXPECT_GT(variance_of(c), 0.01f);
  c.track_variance = false;
  c.adaptive.enabled = true;
  EXPECT_TRUE(tracks_variance(c));
  EXPECT_GT(variance_of(c), 0.01f);
}

// The decision alone: a converged pixel visited 1000 times is skipped at most max_skips times in
// a row; a pixel of another epoch or with too few samples is never skipped.
TEST(Adaptive, SkipDecisionBoundsConsecutiveSkips) {
  AdaptiveConfig a;
  a.enabled = true;
  PixelState p;
  p.epoch.store(3);
  p.count.store(100);
  for (int c = 0; c < 3; ++c) p.mean[c].store(0.5);
  p.m2.store(0.0);
  uint8_t run_length = 0;
  int longest = 0, current = 0, skips = 0;
  for (int v = 0; v < 1000; ++v) {
    if (adaptive_skip(a, p, 3, run_length)) {
      ++skips;
      longest = std::max(longest, ++current);
    } else {
      current = 0;
    }
  }
  EXPECT_EQ(longest, int(a.max_skips));
  EXPECT_EQ(skips, 1000 / int(a.max_skips + 1) * int(a.max_skips));
  run_length = 0;
  EXPECT_FALSE(adaptive_skip(a, p, 4, run_length));  // newer camera: render
  p.count.store(a.min_samples - 1);
  EXPECT_FALSE(adaptive_skip(a, p, 3, run_length));  // too few samples: render
  p.count.store(100);
  p.m2.store(99.0 * 100.0);  // standard error 1 >> tolerance
  EXPECT_FALSE(adaptive_skip(a, p, 3, run_length));
  EXPECT_FALSE(converged(a, 100, 0.5, std::numeric_limits<double>::quiet_NaN()));
}

// Wall-clock threads with adaptive sampling (the path TSan checks): every pixel is reached, the
// flat half ends up with fewer samples, nothing is dropped. Runs until every thread has swept
// its pixels 60 times (no timing assert; the cap only stops a hang).
TEST(Adaptive, WallClockThreadsSkipAndCoverEveryPixel) {
  EngineConfig c = adaptive_config(true);
  c.deterministic = false;
  c.update_log_capacity = 0;
  Engine e(kNoScene, c, camera_at(0));
  // Every thread must have walked its list 60 times (visits, skipped ones included): on a loaded
  // machine one thread may run long before the other is scheduled.
  auto swept = [&] {
    const EngineStats st = e.stats();
    for (const ThreadStats& t : st.threads)
      if (t.updates < 60 * t.pixels) return false;
    return true;
  };
  e.start();
  for (int k = 0; k < 60000 && !swept(); ++k) std::this_thread::sleep_for(std::chrono::milliseconds(1));
  e.stop();
  ASSERT_FALSE(e.error());
  ASSERT_TRUE(swept());
  EXPECT_EQ(e.stats().dropped, 0u);
  // Per thread (threads may run very unequal numbers of sweeps S): a flat pixel reaches
  // min_samples = 8 in 4 visits, then is rendered at most once per 8 visits, so it holds at most
  // 8 + 2 (ceil(S) - 4) / 8 + 2 <= 11 + S / 4 samples where plain sampling would give 2 S.
  const EngineStats st = e.stats();
  for (int t = 0; t < e.thread_count(); ++t) {
    SCOPED_TRACE(t);
    const double sweeps = double(st.threads[size_t(t)].updates) / double(st.threads[size_t(t)].pixels);
    double flat_sum = 0, noisy_sum = 0;
    int flat_n = 0, noisy_n = 0;
    for (uint32_t idx : e.partition().pixels[size_t(t)]) {
      PixelSnapshot p;
      ASSERT_TRUE(e.read_pixel(int(idx) % kW, int(idx) / kW, p));
      EXPECT_EQ(p.epoch, 1u);  // every pixel reached
      if (int(idx) % kW < kW / 2) {
        EXPECT_LE(p.count, 11.0 + sweeps / 4);
        flat_sum += p.count, ++flat_n;
      } else {
        noisy_sum += p.count, ++noisy_n;
      }
    }
    ASSERT_TRUE(flat_n > 0 && noisy_n > 0);
    EXPECT_LT(flat_sum / flat_n, noisy_sum / noisy_n);
  }
}

TEST(Adaptive, InvalidSettingsAreRejected) {
  EngineConfig c;
  c.adaptive.max_skips = 0;
  EXPECT_EQ(validate(c), "adaptive.max_skips: must be 1..255");
  c.adaptive.max_skips = 7;
  c.adaptive.rel_error = -1.0f;
  EXPECT_EQ(validate(c), "adaptive.rel_error: must be >= 0");
}

}  // namespace
}  // namespace frameless
