// DisplayImage helpers.
#include "display/display_image.h"

#include <limits>

namespace frameless {

float DisplayImage::age(size_t i) const {
  if (i >= last_update.size() || last_update[i] < 0.0f) return std::numeric_limits<float>::infinity();
  return float(info.virtual_time) - last_update[i];
}

void DisplayImage::reset(int w, int h) {
  width = w;
  height = h;
  const size_t n = pixels();
  rgb.assign(3 * n, 0.0f);
  last_update.assign(n, -1.0f);
  sample_count.assign(n, 0);
  variance.assign(n, 0.0f);
  epoch.assign(n, 0);
  levels.assign(n, 0);
}

}  // namespace frameless
