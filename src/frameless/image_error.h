// Error metrics between linear RGB images (displayed image against a converged reference):
// RMSE and relative MSE; any thread (pure functions).
#pragma once
#include <cstddef>
#include <vector>

namespace frameless {

// Errors of one image against a reference. Both are 3 floats per pixel (linear RGB), same size.
struct ImageError {
  double mse = 0;   // mean over pixels and channels of (image - reference)^2
  double rmse = 0;  // sqrt(mse)
  double rel_mse =
      0;  // mean over pixels and channels of (image - reference)^2 / (reference^2 + eps)
  size_t pixels = 0;  // pixels compared
};

// Offset in the denominator of the relative MSE (Rousselle et al. 2011 use 0.01): keeps
// near-black reference pixels from dominating.
inline constexpr double kRelMseEpsilon = 0.01;

// Compares `pixels` RGB pixels; non-finite image values count as an error of 1e3 per channel
// (a displayed image is always finite; this keeps a broken input visible rather than NaN).
ImageError image_error(const float* image, const float* reference, size_t pixels,
                       double rel_epsilon = kRelMseEpsilon);
// Same for vectors; returns a default ImageError (pixels = 0) when the sizes differ or are not
// a multiple of 3.
ImageError image_error(const std::vector<float>& image, const std::vector<float>& reference,
                       double rel_epsilon = kRelMseEpsilon);

// Variance of the mean of two independent half-renders a and b of the same pixels, estimated from
// their difference: mean over pixels and channels of (a - b)^2 / 4. This is the MSE a noisy
// reference (a + b) / 2 adds to every comparison against it (its "noise floor").
double half_difference_mse(const std::vector<float>& a, const std::vector<float>& b);

// MSE with a reference's own noise floor taken out: max(0, mse - floor_mse). RMSE = its sqrt.
double debiased_mse(double mse, double floor_mse);

}  // namespace frameless
