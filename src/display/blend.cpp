// Exponential-decay blending with a running-mean takeover for still pixels.
#include "display/blend.h"

#include <cmath>

namespace frameless {

float decay_alpha(float dt, float decay_seconds) {
  if (!(dt > 0.0f)) return 0.0f;
  if (!(decay_seconds > 0.0f)) return 1.0f;
  return 1.0f - std::exp(-dt / decay_seconds);
}

uint32_t converge_count(float alpha) {
  if (!(alpha > 0.0f)) return 0xffffffffu;
  if (alpha >= 1.0f) return 1;
  return uint32_t(std::ceil((2.0f - alpha) / alpha));
}

Vec3 blend_pixel(const BlendConfig& config, bool conventional, const Vec3& previous,
                 uint32_t previous_epoch, float previous_time, const PixelSnapshot& u,
                 bool* rejected) {
  Vec3 result;
  if (conventional || previous_epoch == 0) {
    // A completed frame, or a pixel shown for the first time: take it whole.
    result = conventional ? u.mean : u.sample;
  } else if (config.converge && u.epoch == previous_epoch && u.count >= converge_count(config.alpha)) {
    // Camera unchanged and the running mean now beats the blend: a still image sharpens.
    result = u.mean;
  } else {
    const float a = config.time_decay ? decay_alpha(u.time - previous_time, config.decay_seconds)
                                      : config.alpha;
    result = blend(previous, u.sample, a);
  }
  const bool bad = !is_finite(result);
  if (rejected) *rejected = bad;
  return bad ? (is_finite(previous) ? previous : Vec3(0.0f)) : result;
}

}  // namespace frameless
