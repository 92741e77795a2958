// Numerically stable running mean and variance (Welford 1962, in double); any thread (pure).
#pragma once
#include <cstdint>

namespace frameless {

// One Welford step: after n samples (n counts the new one) `mean` is their mean and `m2` the sum
// of squared deviations from it. Doubles keep 1e8 samples of mean 1e4, sd 1 within 1e-7 relative.
inline void welford_update(double& mean, double& m2, uint64_t n, double x) {
  const double delta = x - mean;
  mean += delta / double(n);
  m2 += delta * (x - mean);
}

// Scalar running statistics (tests, benchmarks and the per-pixel state use the same step).
struct RunningStats {
  uint64_t count = 0;  // samples seen
  double mean = 0.0;   // their mean
  double m2 = 0.0;     // sum of squared deviations from the mean

  void add(double x) { welford_update(mean, m2, ++count, x); }
  // Unbiased sample variance (0 with fewer than two samples).
  double variance() const { return count > 1 ? m2 / double(count - 1) : 0.0; }
};

}  // namespace frameless
