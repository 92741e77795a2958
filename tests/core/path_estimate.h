// Monte Carlo estimates of the path tracer along one ray for the statistical tests: mean and
// standard error of channel x over n paths, each with its own random stream (test thread).
#pragma once
#include <algorithm>
#include <cmath>

#include "core/base/rng.h"
#include "core/shading/path_tracer.h"

namespace frameless::testing {

inline Ray make_ray(const Vec3& org, const Vec3& dir) {
  Ray r;
  r.org = org;
  r.dir = glm::normalize(dir);
  return r;
}

struct Estimate {
  double mean = 0.0, se = 0.0;
};

// Streams (seed, i): estimates with different seeds share no random numbers.
inline Estimate estimate(const Scene& s, const Ray& ray, int n, uint64_t seed, const PathOptions& o = {}) {
  double sum = 0.0, sum2 = 0.0;
  for (int i = 0; i < n; ++i) {
    const double v = trace_path(s, ray, mix64(seed << 32 | uint64_t(i)), nullptr, nullptr, nullptr,
                                nullptr, nullptr, o).x;
    sum += v;
    sum2 += v * v;
  }
  Estimate e;
  e.mean = sum / n;
  e.se = std::sqrt(std::max(0.0, sum2 / n - e.mean * e.mean) / n);
  return e;
}

}  // namespace frameless::testing
