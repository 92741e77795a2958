// Gamma tail (Numerical-Recipes style series / Lentz continued fraction), Bluestein DFT, Moran's I.
#include "frameless/stats_math.h"

#include <algorithm>
#include <cmath>
#include <memory>
#include <numbers>

namespace frameless {
namespace {

constexpr double kEps = 1e-15;
constexpr int kMaxIter = 100000;

// P(a, x) by its power series; converges fast for x < a + 1.
double gamma_p_series(double a, double x) {
  double term = 1.0 / a, sum = term;
  for (int n = 1; n < kMaxIter; ++n) {
    term *= x / (a + n);
    sum += term;
    if (std::fabs(term) < std::fabs(sum) * kEps) break;
  }
  return sum * std::exp(-x + a * std::log(x) - std::lgamma(a));
}

// Q(a, x) by its continued fraction (modified Lentz); converges fast for x >= a + 1.
double gamma_q_fraction(double a, double x) {
  constexpr double tiny = 1e-300;
  double b = x + 1.0 - a, c = 1.0 / tiny, d = 1.0 / b, h = d;
  for (int i = 1; i < kMaxIter; ++i) {
    const double an = -i * (i - a);
    b += 2.0;
    d = an * d + b;
    if (std::fabs(d) < tiny) d = tiny;
    c = b + an / c;
    if (std::fabs(c) < tiny) c = tiny;
    d = 1.0 / d;
    const double delta = d * c;
    h *= delta;
    if (std::fabs(delta - 1.0) < kEps) break;
  }
  return std::exp(-x + a * std::log(x) - std::lgamma(a)) * h;
}

bool is_pow2(size_t n) { return n && !(n & (n - 1)); }

// Iterative radix-2 Cooley-Tukey, n a power of two.
void fft_pow2(std::vector<std::complex<double>>& a, bool inverse) {
  const size_t n = a.size();
  for (size_t i = 1, j = 0; i < n; ++i) {
    size_t bit = n >> 1;
    for (; j & bit; bit >>= 1) j ^= bit;
    j ^= bit;
    if (i < j) std::swap(a[i], a[j]);
  }
  for (size_t len = 2; len <= n; len <<= 1) {
    const double ang = 2.0 * std::numbers::pi / double(len) * (inverse ? 1.0 : -1.0);
    const std::complex<double> wl(std::cos(ang), std::sin(ang));
    for (size_t i = 0; i < n; i += len) {
      std::complex<double> w(1.0);
      for (size_t k = 0; k < len / 2; ++k) {
        // Twiddles recomputed every 64 steps keep the rounding error of the recurrence small.
        if ((k & 63) == 0) {
          const double t = ang * double(k);
          w = {std::cos(t), std::sin(t)};
        }
        const auto u = a[i + k], v = a[i + k + len / 2] * w;
        a[i + k] = u + v;
        a[i + k + len / 2] = u - v;
        w *= wl;
      }
    }
  }
}

// Bluestein: a DFT of any length as a convolution with a chirp, done with power-of-two FFTs.
// The chirp and its transform depend only on the length, so one plan serves every line.
struct BluesteinPlan {
  size_t n = 0, m = 1;
  std::vector<std::complex<double>> chirp, kernel;  // kernel: FFT of the conjugate chirp
  std::vector<std::complex<double>> work;

  BluesteinPlan(size_t len, bool inverse) : n(len) {
    while (m < 2 * n - 1) m <<= 1;
    const double sign = inverse ? 1.0 : -1.0;
    chirp.resize(n);
    for (size_t k = 0; k < n; ++k) {
      // k^2 mod 2n keeps the angle argument small and exact.
      const uint64_t k2 = (uint64_t(k) * uint64_t(k)) % (2 * uint64_t(n));
      const double ang = sign * std::numbers::pi * double(k2) / double(n);
      chirp[k] = {std::cos(ang), std::sin(ang)};
    }
    kernel.assign(m, 0.0);
    kernel[0] = std::conj(chirp[0]);
    for (size_t k = 1; k < n; ++k) kernel[k] = kernel[m - k] = std::conj(chirp[k]);
    fft_pow2(kernel, false);
    work.resize(m);
  }

  void apply(std::complex<double>* a) {
    std::fill(work.begin(), work.end(), 0.0);
    for (size_t k = 0; k < n; ++k) work[k] = a[k] * chirp[k];
    fft_pow2(work, false);
    for (size_t k = 0; k < m; ++k) work[k] *= kernel[k];
    fft_pow2(work, true);
    for (size_t k = 0; k < n; ++k) a[k] = work[k] * chirp[k] / double(m);
  }
};

// Transforms many lines of one length.
class LineDft {
 public:
  LineDft(size_t n, bool inverse) : n_(n), inverse_(inverse) {
    if (n > 1 && !is_pow2(n)) plan_ = std::make_unique<BluesteinPlan>(n, inverse);
    buf_.resize(n);
  }
  void apply(std::complex<double>* a) {
    if (n_ <= 1) return;
    if (plan_) return plan_->apply(a);
    std::copy_n(a, n_, buf_.begin());
    fft_pow2(buf_, inverse_);
    std::copy_n(buf_.begin(), n_, a);
  }

 private:
  size_t n_;
  bool inverse_;
  std::unique_ptr<BluesteinPlan> plan_;
  std::vector<std::complex<double>> buf_;
};

}  // namespace

double gamma_q(double a, double x) {
  if (x <= 0.0) return 1.0;
  if (x < a + 1.0) return 1.0 - gamma_p_series(a, x);
  return gamma_q_fraction(a, x);
}

double gamma_p(double a, double x) {
  if (x <= 0.0) return 0.0;
  if (x < a + 1.0) return gamma_p_series(a, x);
  return 1.0 - gamma_q_fraction(a, x);
}

double chi_square_sf(double x, double dof) { return gamma_q(0.5 * dof, 0.5 * x); }

ChiSquareTest chi_square_equal_rates(const std::vector<uint32_t>& counts) {
  ChiSquareTest t;
  if (counts.size() < 2) return t;
  double total = 0;
  for (uint32_t c : counts) total += c;
  t.dof = double(counts.size() - 1);
  if (total == 0) return t;
  const double e = total / double(counts.size());
  for (uint32_t c : counts) t.chi2 += (c - e) * (c - e) / e;
  t.p_value = chi_square_sf(t.chi2, t.dof);
  return t;
}

void dft(std::vector<std::complex<double>>& a, bool inverse) {
  LineDft(a.size(), inverse).apply(a.data());
}

void dft_2d(std::vector<std::complex<double>>& a, int width, int height, bool inverse) {
  const size_t w = size_t(width), h = size_t(height);
  LineDft rows(w, inverse);
  for (size_t y = 0; y < h; ++y) rows.apply(a.data() + y * w);
  LineDft cols(h, inverse);
  std::vector<std::complex<double>> line(h);
  for (size_t x = 0; x < w; ++x) {
    for (size_t y = 0; y < h; ++y) line[y] = a[y * w + x];
    cols.apply(line.data());
    for (size_t y = 0; y < h; ++y) a[y * w + x] = line[y];
  }
}

MoransI morans_i(const std::vector<double>& field, int width, int height) {
  MoransI r;
  const size_t n = field.size();
  if (n < 4 || n != size_t(width) * size_t(height)) return r;
  const double dn = double(n);
  r.expected = -1.0 / (dn - 1.0);
  double mean = 0;
  for (double v : field) mean += v;
  mean /= dn;
  double m2 = 0, m4 = 0, cross = 0, s2 = 0;
  for (int y = 0; y < height; ++y)
    for (int x = 0; x < width; ++x) {
      const size_t i = size_t(y) * size_t(width) + size_t(x);
      const double z = field[i] - mean;
      m2 += z * z;
      m4 += z * z * z * z;
      // Each rook pair once (right and down); the symmetric weight matrix counts it twice.
      if (x + 1 < width) cross += 2.0 * z * (field[i + 1] - mean);
      if (y + 1 < height) cross += 2.0 * z * (field[i + size_t(width)] - mean);
      const int deg = (x > 0) + (x + 1 < width) + (y > 0) + (y + 1 < height);
      s2 += 4.0 * deg * deg;  // (row sum + column sum)^2 = (2 deg)^2
    }
  const double pairs = double(height) * (width - 1) + double(width) * (height - 1);
  const double s0 = 2.0 * pairs;  // sum of all weights
  const double s1 = 2.0 * s0;     // 1/2 sum (w_ij + w_ji)^2 for binary symmetric weights
  if (m2 <= 0 || s0 <= 0) return r;
  r.i = dn / s0 * cross / m2;
  const double b2 = dn * m4 / (m2 * m2);  // sample kurtosis
  const double num = dn * ((dn * dn - 3 * dn + 3) * s1 - dn * s2 + 3 * s0 * s0) -
                     b2 * ((dn * dn - dn) * s1 - 2 * dn * s2 + 6 * s0 * s0);
  const double den = (dn - 1) * (dn - 2) * (dn - 3) * s0 * s0;
  r.variance = num / den - r.expected * r.expected;
  r.z = r.variance > 0 ? (r.i - r.expected) / std::sqrt(r.variance) : 0.0;
  return r;
}

}  // namespace frameless
