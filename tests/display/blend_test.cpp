// Blend arithmetic: exponential decay, time-based alpha, convergence takeover, non-finite guard.
#include "display/blend.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>

namespace frameless {
namespace {

PixelSnapshot update(Vec3 sample, Vec3 mean, uint32_t count, uint32_t epoch, float time) {
  PixelSnapshot s;
  s.sample = sample;
  s.mean = mean;
  s.count = count;
  s.epoch = epoch;
  s.time = time;
  return s;
}

TEST(Blend, ExponentialDecayArithmetic) {
  EXPECT_EQ(blend(Vec3(0.0f), Vec3(1.0f), 0.25f), Vec3(0.25f));
  EXPECT_EQ(blend(Vec3(2.0f), Vec3(2.0f), 0.7f), Vec3(2.0f));
  // n blends of a constant 1 into 0 leave 1 - (1 - a)^n.
  Vec3 d(0.0f);
  for (int n = 0; n < 10; ++n) d = blend(d, Vec3(1.0f), 0.3f);
  EXPECT_NEAR(d.x, 1.0 - std::pow(0.7, 10), 1e-6);
}

TEST(Blend, TimeBasedAlpha) {
  EXPECT_EQ(decay_alpha(0.0f, 0.05f), 0.0f);
  EXPECT_NEAR(decay_alpha(0.05f, 0.05f), 1.0 - std::exp(-1.0), 1e-6);
  EXPECT_NEAR(decay_alpha(10.0f, 0.05f), 1.0, 1e-6);
  EXPECT_EQ(decay_alpha(0.1f, 0.0f), 1.0f);
  EXPECT_EQ(decay_alpha(std::numeric_limits<float>::quiet_NaN(), 0.05f), 0.0f);
}

TEST(Blend, ConvergeCountMatchesVarianceOfTheBlend) {
  EXPECT_EQ(converge_count(1.0f), 1u);
  EXPECT_EQ(converge_count(0.5f), 3u);   // blend variance a/(2-a) = 1/3 of a sample's
  EXPECT_EQ(converge_count(0.1f), 19u);
}

TEST(Blend, PixelRules) {
  BlendConfig c;
  c.alpha = 0.5f;
  bool rej = true;
  // First time shown: the sample itself.
  EXPECT_EQ(blend_pixel(c, false, Vec3(9.0f), 0, 0, update(Vec3(1.0f), Vec3(1.0f), 2, 1, 0), &rej), Vec3(1.0f));
  EXPECT_FALSE(rej);
  // Moving camera (new epoch): blend.
  EXPECT_EQ(blend_pixel(c, false, Vec3(0.0f), 1, 0, update(Vec3(1.0f), Vec3(0.8f), 2, 2, 0), &rej), Vec3(0.5f));
  // Same epoch, converged: running mean.
  EXPECT_EQ(blend_pixel(c, false, Vec3(0.0f), 2, 0, update(Vec3(1.0f), Vec3(0.8f), 4, 2, 0), &rej), Vec3(0.8f));
  // Same epoch, too few samples: still the blend.
  EXPECT_EQ(blend_pixel(c, false, Vec3(0.0f), 2, 0, update(Vec3(1.0f), Vec3(0.8f), 2, 2, 0), &rej), Vec3(0.5f));
  // Conventional frames are shown whole.
  EXPECT_EQ(blend_pixel(c, true, Vec3(0.0f), 2, 0, update(Vec3(1.0f), Vec3(0.8f), 2, 3, 0), &rej), Vec3(0.8f));
  // Time decay: alpha from the time since the last blend.
  c.time_decay = true;
  c.decay_seconds = 1.0f;
  const Vec3 t = blend_pixel(c, false, Vec3(0.0f), 1, 1.0f, update(Vec3(1.0f), Vec3(1.0f), 1, 2, 2.0f), &rej);
  EXPECT_NEAR(t.x, 1.0 - std::exp(-1.0), 1e-6);
}

TEST(Blend, NonFiniteNeverReachesTheImage) {
  BlendConfig c;
  const float nan = std::numeric_limits<float>::quiet_NaN();
  for (float bad : {nan, kInfinity, -kInfinity}) {
    bool rej = false;
    const Vec3 v = blend_pixel(c, false, Vec3(0.25f), 1, 0, update(Vec3(bad, 0, 0), Vec3(0.0f), 1, 2, 0), &rej);
    EXPECT_TRUE(rej);
    EXPECT_EQ(v, Vec3(0.25f));
    // Even a corrupted previous value is not propagated.
    const Vec3 w = blend_pixel(c, false, Vec3(nan), 1, 0, update(Vec3(bad), Vec3(bad), 1, 2, 0), &rej);
    EXPECT_TRUE(is_finite(w));
  }
}

}  // namespace
}  // namespace frameless

namespace frameless {
namespace {

// Temporal weights: agreement within the noise keeps a long history, disagreement a short one.
TEST(TemporalBlend, AgreementHalvesAlphaDisagreementTakesTheSample) {
  PixelSnapshot u;
  u.variance = 0.0004f;  // sigma 0.02
  u.sample = Vec3(0.51f);
  EXPECT_FLOAT_EQ(temporal_alpha(0.5f, Vec3(0.5f), u), 0.25f);  // within 2 sigma + 5 %
  u.sample = Vec3(2.0f);
  EXPECT_FLOAT_EQ(temporal_alpha(0.5f, Vec3(0.5f), u), 1.0f);  // far outside: motion
  u.sample = Vec3(0.62f);  // in between: in between
  const float mid = temporal_alpha(0.5f, Vec3(0.5f), u);
  EXPECT_GT(mid, 0.25f);
  EXPECT_LT(mid, 1.0f);
  // A noisier pixel tolerates the same difference.
  u.variance = 0.01f;
  EXPECT_FLOAT_EQ(temporal_alpha(0.5f, Vec3(0.5f), u), 0.25f);
  // The blend uses it only when asked for; a still pixel still converges to its mean.
  BlendConfig c;
  c.temporal = true;
  u.variance = 0.0f;
  u.sample = Vec3(2.0f);
  u.epoch = 2;
  u.count = 1;
  bool bad = false;
  EXPECT_EQ(blend_pixel(c, false, Vec3(0.5f), 1, 0.0f, u, &bad), Vec3(2.0f));
  c.temporal = false;
  EXPECT_EQ(blend_pixel(c, false, Vec3(0.5f), 1, 0.0f, u, &bad), Vec3(1.25f));
}

}  // namespace
}  // namespace frameless
