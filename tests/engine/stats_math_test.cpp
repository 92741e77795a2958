// Tests of the statistics' numerical building blocks: gamma tail, chi-square, DFT, Moran's I.
#include "frameless/stats_math.h"

#include <cmath>
#include <complex>
#include <numbers>
#include <vector>

#include <gtest/gtest.h>

#include "core/base/rng.h"

namespace frameless {
namespace {

TEST(StatsMath, GammaTailMatchesClosedForms) {
  // Q(1, x) = exp(-x); Q(1/2, x) = erfc(sqrt(x)); Q(2, x) = (1 + x) exp(-x).
  for (double x : {0.0, 0.1, 1.0, 3.0, 10.0, 40.0}) {
    EXPECT_NEAR(gamma_q(1.0, x), std::exp(-x), 1e-12 + 1e-10 * std::exp(-x)) << x;
    EXPECT_NEAR(gamma_q(0.5, x), std::erfc(std::sqrt(x)), 1e-12) << x;
    EXPECT_NEAR(gamma_q(2.0, x), (1 + x) * std::exp(-x), 1e-12) << x;
    EXPECT_NEAR(gamma_p(2.0, x) + gamma_q(2.0, x), 1.0, 1e-12) << x;
  }
}

TEST(StatsMath, ChiSquareQuantiles) {
  // Table values: chi2(1) 95% = 3.841459, chi2(10) 99.9% = 29.588, chi2(1000) median ~ 999.33.
  EXPECT_NEAR(chi_square_sf(3.841459, 1), 0.05, 1e-6);
  EXPECT_NEAR(chi_square_sf(29.588298, 10), 0.001, 1e-6);
  EXPECT_NEAR(chi_square_sf(999.3333, 1000), 0.5, 1e-3);
  // Large dof (a 333 x 777 image has 258740): the p-value stays finite and monotone.
  const double dof = 258740;
  EXPECT_GT(chi_square_sf(dof, dof), 0.4);
  EXPECT_LT(chi_square_sf(dof * 1.1, dof), 1e-200);  // z ~ 35
}

TEST(StatsMath, ChiSquareEqualRatesBites) {
  // Equal counts: chi2 = 0, p = 1. One doubled region of 10% of the cells: rejected at alpha 0.001.
  std::vector<uint32_t> even(1000, 20);
  EXPECT_EQ(chi_square_equal_rates(even).chi2, 0.0);
  EXPECT_EQ(chi_square_equal_rates(even).p_value, 1.0);
  std::vector<uint32_t> skewed = even;
  for (size_t i = 0; i < 100; ++i) skewed[i] = 40;
  EXPECT_LT(chi_square_equal_rates(skewed).p_value, 1e-3);
  // Poisson counts with equal rates (seed 7) pass at alpha 0.001.
  Rng rng(7);
  std::vector<uint32_t> poisson(1000, 0);
  for (int k = 0; k < 20000; ++k) ++poisson[(uint64_t(rng.next_u32()) * 1000) >> 32];
  EXPECT_GT(chi_square_equal_rates(poisson).p_value, 1e-3);
}

std::vector<std::complex<double>> naive_dft(const std::vector<std::complex<double>>& a) {
  const size_t n = a.size();
  std::vector<std::complex<double>> out(n);
  for (size_t k = 0; k < n; ++k)
    for (size_t j = 0; j < n; ++j)
      out[k] += a[j] * std::polar(1.0, -2.0 * std::numbers::pi * double((j * k) % n) / double(n));
  return out;
}

TEST(StatsMath, DftMatchesDirectSumForAnyLength) {
  Rng rng(3);
  for (size_t n : {1u, 2u, 7u, 12u, 16u, 111u, 259u}) {
    std::vector<std::complex<double>> a(n);
    for (auto& v : a) v = {rng.next_float() - 0.5, rng.next_float() - 0.5};
    const auto ref = naive_dft(a);
    auto got = a;
    dft(got);
    for (size_t k = 0; k < n; ++k) EXPECT_LT(std::abs(got[k] - ref[k]), 1e-9) << n << " " << k;
    dft(got, true);  // inverse without scaling: n * a
    for (size_t k = 0; k < n; ++k) EXPECT_LT(std::abs(got[k] / double(n) - a[k]), 1e-9) << n;
  }
}

TEST(StatsMath, Dft2dOfAPlaneWaveIsOneSpike) {
  const int w = 12, h = 7;
  std::vector<std::complex<double>> a(size_t(w * h));
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x)
      a[size_t(y * w + x)] = std::polar(1.0, 2 * std::numbers::pi * (3.0 * x / w + 2.0 * y / h));
  dft_2d(a, w, h);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x)
      EXPECT_NEAR(std::abs(a[size_t(y * w + x)]), (x == 3 && y == 2) ? double(w * h) : 0.0, 1e-9);
}

TEST(StatsMath, MoransIOnKnownFields) {
  const int w = 20, h = 15;
  std::vector<double> checker(size_t(w * h)), halves(size_t(w * h)), noise(size_t(w * h));
  Rng rng(11);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      checker[size_t(y * w + x)] = (x + y) & 1;
      halves[size_t(y * w + x)] = x < w / 2;
      noise[size_t(y * w + x)] = rng.next_float() < 0.3f;
    }
  EXPECT_NEAR(morans_i(checker, w, h).i, -1.0, 1e-12);
  const MoransI hv = morans_i(halves, w, h);
  EXPECT_GT(hv.i, 0.9);
  EXPECT_GT(hv.z, 3.29);
  // Independent noise (seed 11): |z| < 3.29, i.e. not significant at two-sided alpha 0.001.
  const MoransI nz = morans_i(noise, w, h);
  EXPECT_NEAR(nz.expected, -1.0 / (w * h - 1), 1e-15);
  EXPECT_GT(nz.variance, 0.0);
  EXPECT_LT(std::fabs(nz.z), 3.29);
}

}  // namespace
}  // namespace frameless
