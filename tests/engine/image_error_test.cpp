// Tests of the image error metrics: RMSE, relative MSE, reference noise floor.
#include "frameless/image_error.h"

#include <gtest/gtest.h>

#include <cmath>
#include <random>

namespace frameless {
namespace {

TEST(ImageError, IdenticalImagesHaveZeroError) {
  std::vector<float> a = {0.1f, 0.2f, 0.3f, 1.0f, 2.0f, 3.0f};
  const ImageError e = image_error(a, a);
  EXPECT_EQ(e.pixels, 2u);
  EXPECT_EQ(e.mse, 0.0);
  EXPECT_EQ(e.rmse, 0.0);
  EXPECT_EQ(e.rel_mse, 0.0);
}

TEST(ImageError, RmseAndRelMseMatchHandComputation) {
  // One pixel off by (0.3, 0, 0.6) against reference (1, 0, 2).
  const std::vector<float> ref = {1.0f, 0.0f, 2.0f};
  const std::vector<float> img = {1.3f, 0.0f, 1.4f};
  const ImageError e = image_error(img, ref);
  const double mse = (0.09 + 0.0 + 0.36) / 3.0;
  EXPECT_NEAR(e.mse, mse, 1e-7);
  EXPECT_NEAR(e.rmse, std::sqrt(mse), 1e-7);
  const double rel = (0.09 / (1.0 + 0.01) + 0.0 + 0.36 / (4.0 + 0.01)) / 3.0;
  EXPECT_NEAR(e.rel_mse, rel, 1e-7);
}

TEST(ImageError, RelativeMseWeighsDarkPixelsMore) {
  // The same absolute error costs more relative error where the reference is dark.
  const std::vector<float> dark = {0.1f, 0.1f, 0.1f}, bright = {10.0f, 10.0f, 10.0f};
  const std::vector<float> dark_off = {0.2f, 0.2f, 0.2f}, bright_off = {10.1f, 10.1f, 10.1f};
  const ImageError d = image_error(dark_off, dark), b = image_error(bright_off, bright);
  EXPECT_NEAR(d.rmse, b.rmse, 1e-5);
  EXPECT_GT(d.rel_mse, 100 * b.rel_mse);
}

TEST(ImageError, MismatchedSizesGiveNoPixels) {
  EXPECT_EQ(image_error(std::vector<float>(6), std::vector<float>(3)).pixels, 0u);
  EXPECT_EQ(image_error(std::vector<float>(4), std::vector<float>(4)).pixels, 0u);
}

TEST(ImageError, NonFiniteValuesAreLargeNotNaN) {
  const std::vector<float> ref = {0.5f, 0.5f, 0.5f};
  const std::vector<float> img = {NAN, 0.5f, INFINITY};
  const ImageError e = image_error(img, ref);
  EXPECT_TRUE(std::isfinite(e.rmse));
  EXPECT_GT(e.rmse, 100.0);
}

TEST(ImageError, HalfDifferenceEstimatesTheReferenceNoise) {
  // Truth t; two independent halves with noise sd s each: the mean's MSE against t is s^2 / 2,
  // and the half-difference estimate must recover it.
  std::mt19937 rng(7);
  std::normal_distribution<float> noise(0.0f, 0.2f);
  const size_t n = 3 * 200000;
  std::vector<float> truth(n), a(n), b(n), mean(n);
  for (size_t i = 0; i < n; ++i) {
    truth[i] = 0.5f + 0.001f * float(i % 97);
    a[i] = truth[i] + noise(rng);
    b[i] = truth[i] + noise(rng);
    mean[i] = 0.5f * (a[i] + b[i]);
  }
  const double floor_mse = half_difference_mse(a, b);
  const double actual = image_error(mean, truth).mse;
  EXPECT_NEAR(floor_mse, 0.02, 0.001);  // 0.2^2 / 2
  EXPECT_NEAR(floor_mse, actual, 0.001);
  // A noisy displayed image d compared against the noisy reference: its error against the truth
  // is recovered by taking the floor out.
  std::vector<float> d(n);
  for (size_t i = 0; i < n; ++i) d[i] = truth[i] + 0.5f * noise(rng);
  const double against_ref = image_error(d, mean).mse, against_truth = image_error(d, truth).mse;
  EXPECT_GT(against_ref, against_truth * 1.5);
  EXPECT_NEAR(debiased_mse(against_ref, floor_mse), against_truth, 0.002);
  EXPECT_EQ(debiased_mse(0.01, 0.02), 0.0);
}

}  // namespace
}  // namespace frameless
