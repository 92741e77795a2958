// The one temporal rule (frameless/temporal_weight.h) that the display's blend weight and the
// render threads' statistics under moving objects share: agreement keeps a long history, clear
// disagreement none, and the two ends reproduce the statistics' cap and restart.
#include "frameless/temporal_weight.h"

#include <gtest/gtest.h>

#include <cmath>

namespace frameless {
namespace {

TEST(TemporalWeight, DisagreementRampsFromTheNoiseToThreeTimesIt) {
  // sigma 0.1 at a level of 1: a sample s above it has the tolerance 0.21 + 0.05 s, so s = 1.2 is
  // within it, s = 1.578 halfway up the ramp and s = 1.918 at its top.
  const float sigma = 0.1f, level = 1.0f;
  EXPECT_EQ(disagreement(1.2f, level, sigma), 0.0f);
  EXPECT_EQ(disagreement(level, level, sigma), 0.0f);
  EXPECT_NEAR(disagreement(1.578f, level, sigma), 0.5f, 0.01f);
  EXPECT_EQ(disagreement(1.93f, level, sigma), 1.0f);
  EXPECT_EQ(disagreement(level - 0.9f, level, sigma), 1.0f);  // either side of the reference
  EXPECT_EQ(disagreement(1.2f, level, 0.0f) > 0.0f, true);     // less noise, less tolerance
  float previous = 0.0f;  // monotone in the distance
  for (float d = 0.0f; d < 2.0f; d += 0.01f) {
    const float t = disagreement(level + d, level, sigma);
    EXPECT_GE(t, previous);
    previous = t;
  }
  EXPECT_EQ(disagreement(std::nanf(""), level, sigma), 0.0f);
}

TEST(TemporalWeight, EndsAreTheCapAndTheRestart) {
  for (unsigned window : {1u, 3u, 7u, 31u}) {
    const float long_weight = 1.0f / float(window + 1);
    // Agreement: the history is the window (the statistics' motion_history cap).
    EXPECT_EQ(history_for_weight(temporal_weight(long_weight, 0.0f), 1000u), window);
    EXPECT_EQ(history_for_weight(temporal_weight(long_weight, 0.0f), 2u), std::min(2u, window));
    // Clear disagreement: no history (the statistics restart at the new sample).
    EXPECT_EQ(history_for_weight(temporal_weight(long_weight, 1.0f), 1000u), 0u);
  }
  // In between, the history shortens as the disagreement grows.
  unsigned previous = 1000u;
  for (float t = 0.0f; t <= 1.0f; t += 0.05f) {
    const unsigned h = history_for_weight(temporal_weight(1.0f / 32.0f, t), 1000u);
    EXPECT_LE(h, previous);
    previous = h;
  }
  const unsigned mid = history_for_weight(temporal_weight(1.0f / 32.0f, 0.1f), 1000u);
  EXPECT_GT(mid, 0u);
  EXPECT_LT(mid, 31u);
  // The display's weight (alpha / 2 for a long history) follows the same curve.
  EXPECT_FLOAT_EQ(temporal_weight(0.25f, 0.0f), 0.25f);
  EXPECT_FLOAT_EQ(temporal_weight(0.25f, 0.5f), 0.625f);
  EXPECT_FLOAT_EQ(temporal_weight(0.25f, 1.0f), 1.0f);
}

}  // namespace
}  // namespace frameless
