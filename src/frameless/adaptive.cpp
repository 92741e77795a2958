// Range checks of the adaptive-sampling settings (the decision itself is inline in adaptive.h).
#include "frameless/adaptive.h"

#include <cmath>

namespace frameless {

std::string validate(const AdaptiveConfig& a) {
  if (a.max_skips < 1 || a.max_skips > 255) return "adaptive.max_skips: must be 1..255";
  if (!(std::isfinite(a.rel_error) && a.rel_error >= 0.0f)) return "adaptive.rel_error: must be >= 0";
  if (!(std::isfinite(a.abs_error) && a.abs_error >= 0.0f)) return "adaptive.abs_error: must be >= 0";
  return "";
}

}  // namespace frameless
