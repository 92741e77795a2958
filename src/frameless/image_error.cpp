// Image error metrics (RMSE, relative MSE, reference noise floor).
#include "frameless/image_error.h"

#include <algorithm>
#include <cmath>

namespace frameless {

ImageError image_error(const float* image, const float* reference, size_t pixels,
                       double rel_epsilon) {
  ImageError e;
  e.pixels = pixels;
  if (pixels == 0) return e;
  double sum_sq = 0, sum_rel = 0;
  const size_t n = pixels * 3;
  for (size_t i = 0; i < n; ++i) {
    const double r = reference[i];
    double d = double(image[i]) - r;
    if (!std::isfinite(d)) d = 1e3;
    const double d2 = d * d;
    sum_sq += d2;
    sum_rel += d2 / (r * r + rel_epsilon);
  }
  e.mse = sum_sq / double(n);
  e.rmse = std::sqrt(e.mse);
  e.rel_mse = sum_rel / double(n);
  return e;
}

ImageError image_error(const std::vector<float>& image, const std::vector<float>& reference,
                       double rel_epsilon) {
  if (image.size() != reference.size() || image.size() % 3 != 0) return {};
  return image_error(image.data(), reference.data(), image.size() / 3, rel_epsilon);
}

double half_difference_mse(const std::vector<float>& a, const std::vector<float>& b) {
  if (a.size() != b.size() || a.empty()) return 0.0;
  double sum = 0;
  for (size_t i = 0; i < a.size(); ++i) {
    const double d = double(a[i]) - double(b[i]);
    if (std::isfinite(d)) sum += d * d;
  }
  return sum / double(a.size()) / 4.0;
}

double debiased_mse(double mse, double floor_mse) { return std::max(0.0, mse - floor_mse); }

}  // namespace frameless
