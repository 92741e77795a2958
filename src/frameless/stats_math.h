// Numerical building blocks of the update statistics (issue 5): gamma tail, chi-square, 2-D DFT,
// Moran's I; pure functions, any thread.
#pragma once
#include <complex>
#include <cstdint>
#include <vector>

namespace frameless {

// Regularized upper incomplete gamma Q(a, x) = Gamma(a, x) / Gamma(a), a > 0, x >= 0
// (series for x < a + 1, continued fraction otherwise; relative accuracy ~1e-12).
double gamma_q(double a, double x);
// Regularized lower incomplete gamma P(a, x) = 1 - Q(a, x).
double gamma_p(double a, double x);

// Upper tail of the chi-square distribution with `dof` degrees of freedom: P(X >= x).
double chi_square_sf(double x, double dof);

// Pearson chi-square test of `counts` against equal expected rates.
struct ChiSquareTest {
  double chi2 = 0;     // sum (n_i - E)^2 / E
  double dof = 0;      // cells - 1
  double p_value = 1;  // P(X >= chi2) under equal rates
};
ChiSquareTest chi_square_equal_rates(const std::vector<uint32_t>& counts);

// In-place 1-D DFT of any length (radix-2 for powers of two, Bluestein otherwise).
// inverse: conjugate kernel, no 1/n scaling.
void dft(std::vector<std::complex<double>>& a, bool inverse = false);
// In-place 2-D DFT of a row-major width x height array.
void dft_2d(std::vector<std::complex<double>>& a, int width, int height, bool inverse = false);

// Global Moran's I of a row-major field with rook (4-neighbour, binary, symmetric) weights, with
// its expectation and variance under randomisation (Cliff & Ord 1981).
struct MoransI {
  double i = 0;         // the statistic (0 when the field is constant)
  double expected = 0;  // -1 / (n - 1)
  double variance = 0;  // under randomisation
  double z = 0;         // (i - expected) / sqrt(variance)
};
MoransI morans_i(const std::vector<double>& field, int width, int height);

}  // namespace frameless
