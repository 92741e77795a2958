// The BVH walk's slab test in Embree's fused form, one multiply-subtract a plane instead of a
// subtraction and a multiplication, kept conservative: no box a watertight hit lies in is ever
// culled. Single-ray walks (accel.cpp); any thread.
#pragma once
#include <cmath>
#include <cstdint>

#include "core/accel/accel_impl.h"

#if defined(__AVX2__)
#include <immintrin.h>
#endif

namespace frameless {

// Why the form is conservative (u = 2^-24, t* the exact distance (b - o) / d to plane b):
// entry = fl(b * inv - X_near) with X_near = fl(fl(o * inv) + E_near) and E_near at least
// 3.99 u |o| |inv|, which exceeds the rounding of o * inv and of the addition, so the operand
// rounded is at most (b - o) * inv and the entry at most fl((b - o) * inv) <= t* (1 + u)^2 for
// t* >= 0 (a negative entry lies below tmin >= 0). The exit, from inv_far = fl(inv * kRobustFar)
// and X_far = fl(fl(o * inv_far) - E_far), is at least t* (1 + 4.9 u) likewise. An exact entry at
// most the exact exit thus gives a computed entry at most the computed exit, as Ize's form does
// (robust_far.h). E also carries an absolute floor of 2^-100 (in the scene's units), which covers
// what flushing denormals to zero (FTZ, DAZ) changes. The derivation: benchmarks.md, section 32.
inline constexpr float kFusedSlack = 4.0f * 0x1p-24f;
inline constexpr float kFusedFloor = 0x1p-100f;

// Whether the fused form applies to the ray: every direction component within [2^-60, 2^20] in
// magnitude and every origin component within 2^60, so no constant overflows and the floor
// covers a flushed result; tmin >= 0. Others (axis-parallel rays among them, whose 0 * inf
// today's form reads as inside the slab) take intersect_children.
inline bool fused_slab_applies(const Ray& ray) {
  if (!(ray.tmin >= 0.0f)) return false;
  for (int a = 0; a < 3; ++a) {
    const float d = std::fabs(ray.dir[a]);
    if (!(d >= 0x1p-60f && d <= 0x1p20f && std::fabs(ray.org[a]) <= 0x1p60f)) return false;
  }
  return true;
}

#if defined(__AVX2__)
// One ray's constants of the fused test, broadcast, and the byte offsets of its entry and exit
// rows in Bvh8Node::bounds.
struct FusedSlab {
  __m256 inv[3], inv_far[3], x_near[3], x_far[3];
  uint32_t near_row[3], far_row[3];
};

inline FusedSlab make_fused_slab(const BoxRay& b) {
  FusedSlab s;
  for (int a = 0; a < 3; ++a) {
    const float slack = kFusedSlack * std::fabs(b.org[a]) + kFusedFloor;
    s.inv[a] = _mm256_set1_ps(b.inv[a]);
    s.inv_far[a] = _mm256_set1_ps(b.inv_far[a]);
    s.x_near[a] = _mm256_set1_ps(b.org[a] * b.inv[a] + slack * std::fabs(b.inv[a]));
    s.x_far[a] = _mm256_set1_ps(b.org[a] * b.inv_far[a] - slack * std::fabs(b.inv_far[a]));
    s.near_row[a] = uint32_t(b.near[a]) * uint32_t(sizeof(Bvh8Node::bounds[0]));
    s.far_row[a] = uint32_t(b.near[a] ^ 1) * uint32_t(sizeof(Bvh8Node::bounds[0]));
  }
  return s;
}

// intersect_children in the fused form: the mask of the children entered within [tmin, tmax] and
// their entry distances. Forced inline so a walk keeps the constants in registers.
[[gnu::always_inline]] inline uint32_t fused_children(const Bvh8Node& n, const FusedSlab& s,
                                                      float tmin, float tmax, float* dist) {
  const char* rows = reinterpret_cast<const char*>(n.bounds);
  const auto plane = [&](uint32_t row, __m256 inv, __m256 x) {
    return _mm256_fmsub_ps(_mm256_load_ps(reinterpret_cast<const float*>(rows + row)), inv, x);
  };
  const __m256 tn = _mm256_max_ps(
      _mm256_max_ps(plane(s.near_row[0], s.inv[0], s.x_near[0]),
                    plane(s.near_row[1], s.inv[1], s.x_near[1])),
      _mm256_max_ps(plane(s.near_row[2], s.inv[2], s.x_near[2]), _mm256_set1_ps(tmin)));
  const __m256 tf = _mm256_min_ps(
      _mm256_min_ps(plane(s.far_row[0], s.inv_far[0], s.x_far[0]),
                    plane(s.far_row[1], s.inv_far[1], s.x_far[1])),
      _mm256_min_ps(plane(s.far_row[2], s.inv_far[2], s.x_far[2]), _mm256_set1_ps(tmax)));
  _mm256_store_ps(dist, tn);
  return uint32_t(_mm256_movemask_ps(_mm256_cmp_ps(tn, tf, _CMP_LE_OQ)));
}
#endif

}  // namespace frameless
