// Numerical-stability stress of the accumulators: many samples into one pixel's running mean and
// variance (RunningStats and the engine's PixelState) and through the display's exponential blend,
// against compensated (Kahan, long double) references; FTZ/DAZ inside every kind of render thread
// and no denormals in the blend. 1e7 samples by default, 1e9 with FRAMELESS_LONG_TESTS=1.
#include <gtest/gtest.h>
#include <xmmintrin.h>

#include <atomic>
#include <cmath>
#include <cstdlib>
#include <thread>

#include "core/base/rng.h"
#include "display/blend.h"
#include "frameless/engine.h"
#include "frameless/running_stats.h"
#include "frameless/tile_render.h"
#include "test_shaders.h"

namespace frameless {
namespace {

// The engine keeps a reference to its scene: a named one outlives every engine (these tests use
// synthetic shaders and never trace it).
const Scene kNoScene{};

bool long_tests() {
  const char* v = std::getenv("FRAMELESS_LONG_TESTS");
  return v && std::string(v) == "1";
}
uint64_t stress_samples() { return long_tests() ? 1'000'000'000ull : 10'000'000ull; }

// Kahan-compensated running sums in long double: the reference.
struct KahanSum {
  long double sum = 0, c = 0;
  void add(long double x) {
    const long double y = x - c;
    const long double t = sum + y;
    c = (t - sum) - y;
    sum = t;
  }
};

// Reference mean and variance of a stream, from compensated sums of x and (x - shift)^2.
struct Reference {
  KahanSum s1, s2;
  long double shift = 0;
  uint64_t n = 0;
  void add(double x) {
    if (n++ == 0) shift = x;
    const long double d = (long double)x - shift;
    s1.add(d);
    s2.add(d * d);
  }
  long double mean() const { return shift + s1.sum / n; }
  long double variance() const {
    const long double m = s1.sum / n;
    return (s2.sum - n * m * m) / (n - 1);
  }
};

// Radiance-like samples: float, mean 0.5 (or 1e4 + noise for the hard case), never denormal.
float sample_value(Rng& rng, float offset) { return offset + rng.next_float(); }

// Welford in double over N samples. Bounds (documented in docs/adaptive.md): the mean's error
// is a random walk of N roundings of half an ulp, about sqrt(N) 2^-53 |mean| (4e-12 at 1e9); we
// assert 1e-9 relative. The variance is assert to 1e-6 relative, including a mean of 1e4 with
// sd 0.29, where the naive sum of squares loses every digit.
TEST(StabilityStress, RunningStatsAgreeWithACompensatedReference) {
  for (float offset : {0.0f, 1e4f}) {
    SCOPED_TRACE(offset);
    Rng rng(42);
    RunningStats w;
    Reference ref;
    const uint64_t n = stress_samples();
    for (uint64_t i = 0; i < n; ++i) {
      const float x = sample_value(rng, offset);
      w.add(x);
      ref.add(x);
    }
    ASSERT_TRUE(std::isfinite(w.mean) && std::isfinite(w.m2));
    std::printf("Welford, %llu samples, offset %g: mean rel err %.3Le, variance rel err %.3Le\n",
                (unsigned long long)n, double(offset),
                std::fabs((long double)w.mean - ref.mean()) / ref.mean(),
                std::fabs((long double)w.variance() - ref.variance()) / ref.variance());
    EXPECT_LT(std::fabs((long double)w.mean - ref.mean()) / ref.mean(), 1e-9L);
    EXPECT_LT(std::fabs((long double)w.variance() - ref.variance()) / ref.variance(), 1e-6L);
  }
}

// The engine's own per-pixel path (1x1 image, one thread, one sample per update): the shader
// feeds the reference with every value it returns, the published PixelState must match it.
// The snapshot rounds the double mean to float, so the bound is float rounding: 1e-7 relative.
struct FeedContext {
  mutable Reference ref;
};
SampleResult feeding_shader(const void* ctx, const CameraBasis&, float, float, uint64_t seed) {
  Rng rng(seed);
  SampleResult r;
  r.color = Vec3(0.25f + 0.5f * rng.next_float());
  static_cast<const FeedContext*>(ctx)->ref.add(0.2126 * r.color.x + 0.7152 * r.color.y +
                                                0.0722 * r.color.z);
  return r;
}

TEST(StabilityStress, PixelStateAgreesWithACompensatedReference) {
  FeedContext ctx;
  EngineConfig c = testing::test_config(1, 1, 1, feeding_shader);
  c.shader.context = &ctx;
  c.jitter = false;
  c.deterministic = true;
  c.track_variance = true;
  const uint64_t n = long_tests() ? 1'000'000'000ull : 1'000'000ull;
  c.samples_per_tick = n / 100;
  Engine e(kNoScene, c, testing::camera_at(0));
  for (int k = 0; k < 100; ++k) e.advance(0.01);
  PixelSnapshot p;
  ASSERT_TRUE(e.read_pixel(0, 0, p));
  ASSERT_EQ(p.count, n);
  EXPECT_EQ(e.stats().dropped, 0u);
  ASSERT_TRUE(is_finite(p.mean) && std::isfinite(p.variance));
  std::printf("PixelState, %llu samples: mean rel err %.3e, variance rel err %.3e\n",
              (unsigned long long)n, std::fabs(p.mean.x - (double)ctx.ref.mean()) / (double)ctx.ref.mean(),
              std::fabs(p.variance - (double)ctx.ref.variance()) / (double)ctx.ref.variance());
  EXPECT_LT(std::fabs(p.mean.x - (double)ctx.ref.mean()) / (double)ctx.ref.mean(), 1e-7);
  EXPECT_LT(std::fabs(p.variance - (double)ctx.ref.variance()) / (double)ctx.ref.variance(), 1e-6);
}

// Exponential blend in float against the same recurrence in long double. Each float step rounds
// by at most about 2 ulps and the recurrence contracts by (1 - a) per step, so the error stays
// below 4 ulp(max |x|) / a at every step, however many samples: asserted for a = 0.5 and 1/64.
TEST(StabilityStress, ExponentialBlendErrorStaysBounded) {
  for (float alpha : {0.5f, 1.0f / 64}) {
    SCOPED_TRACE(alpha);
    Rng rng(7);
    float shown = 0.0f;
    long double exact = 0.0L;
    double worst = 0;
    const uint64_t n = stress_samples();
    for (uint64_t i = 0; i < n; ++i) {
      const float s = 4.0f * rng.next_float();
      shown = blend(Vec3(shown), Vec3(s), alpha).x;
      exact += (long double)alpha * ((long double)s - exact);
      worst = std::max(worst, double(std::fabs((long double)shown - exact)));
    }
    ASSERT_TRUE(std::isfinite(shown));
    std::printf("blend a=%g, %llu samples: worst abs err %.3e (bound %.3e)\n", double(alpha),
                (unsigned long long)n, worst, 4.0 * 4.0 * 0x1.0p-23 / alpha);
    EXPECT_LT(worst, 4.0 * 4.0 * 0x1.0p-23 / alpha);
  }
}

// A pixel fading to black decays through the subnormal range: with FTZ/DAZ (render threads) it
// jumps from the smallest normal to exactly 0; without, it lingers in subnormals (the test bites).
int subnormal_steps(bool ftz) {
  int subnormal = 0;
  std::thread t([&] {
    // A new thread inherits its creator's mode: set both ways, whatever ran before.
    if (ftz)
      enable_flush_to_zero();
    else
      _mm_setcsr(_mm_getcsr() & ~0x8040u);  // FTZ (bit 15) and DAZ (bit 6) off
    float shown = 1.0f;
    for (int i = 0; i < 4000; ++i) {
      shown = blend(Vec3(shown), Vec3(0.0f), 0.05f).x;
      subnormal += std::fpclassify(shown) == FP_SUBNORMAL;
      if (!std::isfinite(shown)) subnormal += 1000000;
    }
  });
  t.join();
  return subnormal;
}

TEST(StabilityStress, FlushToZeroKeepsTheBlendOutOfSubnormals) {
  EXPECT_EQ(subnormal_steps(true), 0);
  EXPECT_GT(subnormal_steps(false), 0);
}

// Every kind of render thread runs with FTZ (MXCSR bit 15) and DAZ (bit 6) set: the shader
// records the MXCSR it sees.
struct CsrContext {
  mutable std::atomic<uint32_t> seen_and{0xffffffffu};
  mutable std::atomic<uint32_t> calls{0};
};
SampleResult csr_shader(const void* ctx, const CameraBasis&, float, float, uint64_t) {
  const auto* c = static_cast<const CsrContext*>(ctx);
  c->seen_and.fetch_and(_mm_getcsr(), std::memory_order_relaxed);
  c->calls.fetch_add(1, std::memory_order_relaxed);
  SampleResult r;
  r.color = Vec3(0.5f);
  return r;
}

TEST(StabilityStress, RenderThreadsRunWithFlushToZeroAndDenormalsAreZero) {
  constexpr uint32_t kFtzDaz = 0x8000u | 0x0040u;
  for (int variant = 0; variant < 3; ++variant) {
    SCOPED_TRACE(variant);
    CsrContext ctx;
    EngineConfig c = testing::test_config(16, 16, 2, csr_shader);
    c.shader.context = &ctx;
    c.deterministic = variant == 0;                       // worker pool
    if (variant == 2) c.mode = RenderMode::conventional;  // job threads
    Engine e(kNoScene, c, testing::camera_at(0));
    if (c.deterministic) {
      for (int k = 0; k < 4; ++k) e.advance(0.01);
    } else {
      e.start();
      while (ctx.calls.load() < 2000) std::this_thread::yield();
      e.stop();
    }
    ASSERT_GT(ctx.calls.load(), 0u);
    EXPECT_EQ(ctx.seen_and.load() & kFtzDaz, kFtzDaz);
  }
}

}  // namespace
}  // namespace frameless
