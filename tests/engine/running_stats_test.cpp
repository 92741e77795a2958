// Running statistics: Welford in double stays within 1e-6 relative for 1e8 samples of mean 1e4,
// sd about 1, where the naive one-pass formula fails.
#include "frameless/running_stats.h"

#include <gtest/gtest.h>

#include <cmath>

#include "core/base/rng.h"

namespace frameless {
namespace {

// Samples 1e4 + k / 1024 with integer k uniform in [-1774, 1774] (sd about 1): the exact mean and
// variance follow from integer sums.
struct Exact {
  long double mean, variance;
};

template <class Add>
Exact feed(uint64_t n, Add add) {
  Rng rng(2024);
  __int128 sum_k = 0, sum_k2 = 0;
  for (uint64_t i = 0; i < n; ++i) {
    const int64_t k = int64_t((uint64_t(rng.next_u32()) * 3549u) >> 32) - 1774;
    sum_k += k;
    sum_k2 += k * k;
    add(1e4 + double(k) / 1024.0);
  }
  const long double nn = (long double)n;
  const long double mk = (long double)sum_k / nn;
  const long double var_k = ((long double)sum_k2 - (long double)sum_k * mk) / (nn - 1);
  return {1e4L + mk / 1024.0L, var_k / (1024.0L * 1024.0L)};
}

uint64_t sample_count() { return std::getenv("FRAMELESS_SHORT_STATS") ? 10'000'000 : 100'000'000; }

TEST(RunningStats, WelfordMeetsOneInAMillionOn1e8Samples) {
  RunningStats s;
  const Exact exact = feed(sample_count(), [&](double x) { s.add(x); });
  EXPECT_LT(std::fabs((long double)s.mean - exact.mean) / exact.mean, 1e-6L);
  EXPECT_LT(std::fabs((long double)s.variance() - exact.variance) / exact.variance, 1e-6L);
  EXPECT_NEAR(double(exact.variance), 1.0, 0.01);
}

TEST(RunningStats, NaiveOnePassFormulaFailsTheSameCheck) {
  // sum x^2 - (sum x)^2 / n cancels 1e16-sized terms: double cannot keep 1e-6 of a variance of 1.
  double sum = 0.0, sum2 = 0.0;
  uint64_t n = 0;
  const Exact exact = feed(sample_count(), [&](double x) {
    sum += x;
    sum2 += x * x;
    ++n;
  });
  const double naive = (sum2 - sum * sum / double(n)) / double(n - 1);
  EXPECT_GT(std::fabs((long double)naive - exact.variance) / exact.variance, 1e-6L);
}

TEST(RunningStats, SmallCases) {
  RunningStats s;
  EXPECT_EQ(s.variance(), 0.0);
  s.add(2.0);
  EXPECT_EQ(s.mean, 2.0);
  EXPECT_EQ(s.variance(), 0.0);
  s.add(4.0);
  EXPECT_EQ(s.mean, 3.0);
  EXPECT_EQ(s.variance(), 2.0);
}

}  // namespace
}  // namespace frameless
