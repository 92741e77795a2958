// Exponential-decay blending of new samples into the displayed image; display thread (pure math).
#pragma once
#include <cstdint>

#include "core/types.h"
#include "frameless/pixel_state.h"

namespace frameless {

struct BlendConfig {
  float alpha = 0.5f;        // weight of a new sample: displayed <- displayed (1 - a) + sample a
  bool time_decay = false;   // a = 1 - exp(-dt / decay_seconds), dt = time since the pixel's last blend
  float decay_seconds = 0.05f;  // time constant of the time-based decay
  bool converge = true;      // still camera: show the running mean once it beats the blend
};

// displayed (1 - alpha) + sample alpha, per channel.
inline Vec3 blend(const Vec3& displayed, const Vec3& sample, float alpha) {
  return displayed + alpha * (sample - displayed);
}

// Weight of a new sample under time-based decay after `dt` seconds (0 <= result <= 1).
float decay_alpha(float dt, float decay_seconds);

// Samples after which a pixel's running mean has lower variance than the exponential blend
// (whose variance is a / (2 - a) of one sample's): n >= (2 - a) / a.
uint32_t converge_count(float alpha);

// New displayed colour of one pixel. `previous`: displayed colour, `previous_epoch`/`previous_time`:
// its layers (epoch 0 = never shown). Conventional frames are shown as they are (their running
// mean). The result is always finite: a non-finite input keeps `previous` and sets *rejected.
Vec3 blend_pixel(const BlendConfig& config, bool conventional, const Vec3& previous,
                 uint32_t previous_epoch, float previous_time, const PixelSnapshot& update,
                 bool* rejected);

}  // namespace frameless
