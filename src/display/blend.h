// Exponential-decay blending of new samples into the displayed image; display thread (pure math).
#pragma once
#include <algorithm>
#include <cmath>
#include <cstdint>

#include "core/base/types.h"
#include "frameless/pixel_state.h"
#include "frameless/temporal_weight.h"

namespace frameless {

struct BlendConfig {
  float alpha = 0.5f;        // weight of a new sample: displayed <- displayed (1 - a) + sample a
  bool time_decay = false;   // a = 1 - exp(-dt / decay_seconds), dt = time since the pixel's last blend
  float decay_seconds = 0.05f;  // time constant of the time-based decay
  bool converge = true;      // still camera: show the running mean once it beats the blend
  // Per-pixel temporal weight (as Adaptive Frameless Rendering reconstructs): where a new sample
  // agrees with what the pixel shows (within its noise), a long history (alpha / 2: sharper);
  // where it disagrees (motion), a short one (up to 1: fresh).
  bool temporal = false;
  // Frameless mode: when the camera changes, move what is shown to where it now belongs (the
  // render cache; display/reproject.h) instead of showing the old view until re-rendered.
  bool reproject = false;
  // Most of one core the display may spend reprojecting, averaged over time (0: no limit). A
  // camera change that would exceed it merges into the next one, as when the display falls
  // behind. Deterministic runs ignore it (their steps must not depend on the clock).
  float reproject_budget = 0.0f;  // default: unlimited (on 2 cores the error under motion is far lower)
  // Edge-avoiding a-trous filter of the shown image, guided by each pixel's normal, position and
  // albedo (display/denoise.h): the display's own state stays unfiltered.
  bool denoise = false;
  int denoise_iterations = 3;  // 1..8: the filter reaches 2^iterations pixels
  // igi: OpenRT's discontinuity buffer (display/discontinuity_buffer.h) on the shown image, over
  // the interleaving pattern's n x n window; nothing to do for the other integrators.
  bool discontinuity = true;
};

// displayed (1 - alpha) + sample alpha, per channel.
inline Vec3 blend(const Vec3& displayed, const Vec3& sample, float alpha) {
  return displayed + alpha * (sample - displayed);
}

// Weight of a new sample under time-based decay after `dt` seconds (0 <= result <= 1).
float decay_alpha(float dt, float decay_seconds);

// The temporal weight of a sample (frameless/temporal_weight.h, the rule the render threads use
// for pixels under moving objects): `alpha` halved where the sample and the shown colour agree
// within the pixel's noise, rising to 1 where they clearly differ.
inline float temporal_alpha(float alpha, const Vec3& shown, const PixelSnapshot& u) {
  auto lum = [](const Vec3& c) { return 0.2126f * c.x + 0.7152f * c.y + 0.0722f * c.z; };
  const float sigma = u.variance > 0.0f ? std::sqrt(u.variance) : 0.0f;
  return temporal_weight(0.5f * alpha, disagreement(lum(u.sample), lum(shown), sigma));
}

// Samples after which a pixel's running mean has lower variance than the exponential blend
// (whose variance is a / (2 - a) of one sample's): n >= (2 - a) / a.
uint32_t converge_count(float alpha);

// A BlendConfig resolved once per tick, so the per-pixel blend does no divisions or calls.
struct BlendRule {
  explicit BlendRule(const BlendConfig& c) : config(c), converge_after(converge_count(c.alpha)) {}
  BlendConfig config;
  uint32_t converge_after;  // converge_count(config.alpha)
};

// New displayed colour of one pixel. `previous`: displayed colour, `previous_epoch`/`previous_time`:
// its layers (epoch 0 = never shown). Conventional frames are shown as they are (their running
// mean). The result is always finite: a non-finite input keeps `previous` and sets *rejected.
inline Vec3 blend_pixel(const BlendRule& rule, bool conventional, const Vec3& previous,
                        uint32_t previous_epoch, float previous_time, const PixelSnapshot& u,
                        bool* rejected) {
  const BlendConfig& config = rule.config;
  Vec3 result;
  if (conventional || previous_epoch == 0) {
    // A completed frame, or a pixel shown for the first time: take it whole.
    result = conventional ? u.mean : u.sample;
  } else if (config.converge && u.epoch == previous_epoch && u.count >= rule.converge_after) {
    // Camera unchanged and the running mean now beats the blend: a still image sharpens.
    result = u.mean;
  } else {
    float a = config.time_decay ? decay_alpha(u.time - previous_time, config.decay_seconds)
                                : config.alpha;
    if (config.temporal) a = temporal_alpha(a, previous, u);
    result = blend(previous, u.sample, a);
  }
  const bool bad = !is_finite(result);
  if (rejected) *rejected = bad;
  return bad ? (is_finite(previous) ? previous : Vec3(0.0f)) : result;
}

inline Vec3 blend_pixel(const BlendConfig& config, bool conventional, const Vec3& previous,
                        uint32_t previous_epoch, float previous_time, const PixelSnapshot& update,
                        bool* rejected) {
  return blend_pixel(BlendRule(config), conventional, previous, previous_epoch, previous_time,
                     update, rejected);
}

}  // namespace frameless
