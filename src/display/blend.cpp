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

}  // namespace frameless
