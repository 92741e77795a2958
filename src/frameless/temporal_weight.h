// One temporal rule for a pixel's history, as Adaptive Frameless Rendering reconstructs: where a
// new sample agrees with the pixel (within its noise) a long history, where it disagrees (motion)
// a short one. The render threads use it for the running statistics of pixels under moving
// objects, the display for its blend weight; only what "a long history" means differs.
#pragma once
#include <algorithm>
#include <cmath>

namespace frameless {

// How far a sample's luminance is from the pixel's reference (its running mean, or what the
// display shows), given the pixel's luminance standard deviation: 0 within the tolerance (2 sigma
// plus 5 % of the level plus 0.01), rising linearly to 1 at three times the tolerance. NaN: 0.
inline float disagreement(float sample_lum, float reference_lum, float sigma) {
  const float tolerance =
      2.0f * sigma + 0.05f * std::max(std::fabs(sample_lum), std::fabs(reference_lum)) + 0.01f;
  const float t = (std::fabs(sample_lum - reference_lum) - tolerance) / (2.0f * tolerance);
  return t > 0.0f ? std::min(t, 1.0f) : 0.0f;  // also 0 for NaN
}

// The new sample's weight: `long_weight` (a long history) where it agrees, rising to 1 (only the
// new sample) as the disagreement goes to 1.
inline float temporal_weight(float long_weight, float disagreement) {
  return long_weight + (1.0f - long_weight) * disagreement;
}

// Running statistics: the samples' history that a weight leaves (a mean over n + 1 samples gives
// the new one weight 1 / (n + 1)), at most `count`. 0: start again from the new sample.
inline unsigned history_for_weight(float weight, unsigned count) {
  if (!(weight < 1.0f)) return 0u;
  const float n = 1.0f / std::max(weight, 1e-6f) - 1.0f;
  return std::min(count, unsigned(std::lround(n)));
}

}  // namespace frameless
