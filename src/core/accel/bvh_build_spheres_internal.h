// Internals of the in-place sphere BVH builder (bvh_build_spheres.h): the sphere and material
// arrays as the shared binned-SAH splitter (bvh_build_split.h) sees them. The object median
// (quickselect by centre) is in bvh_build_spheres_order.cpp; node blocks, the top of the tree,
// subtree tasks and the assembly in bvh_build_spheres.cpp.
#pragma once
#include <cstdint>
#include <cstring>
#include <utility>

#include "core/accel/bvh_build_split.h"
#include "core/geometry/geometry.h"

namespace frameless::sphere_bvh {

using namespace bvh_split;

static_assert(sizeof(Sphere) == 4 * sizeof(float), "Sphere must be x, y, z, radius");

// Bounds of one sphere, as Accel::build makes them for build_bvh8: centre +- |radius|, or a point
// at the origin when any bound is not finite (x - x is 0 exactly for finite x). The w lanes hold
// radius -+ |radius| (never read). Without kChecked the bounds must be finite.
template <bool kChecked = true>
inline void sphere_box(const Sphere& s, F4& lo, F4& hi) {
  float xyzr[4];
  std::memcpy(xyzr, &s, sizeof xyzr);  // one 16-byte load
  const F4 v = load4(xyzr);
  const F4 r = abs_w4(v);
  lo = v - r;
  hi = v + r;
  if (kChecked && !xyz_zero4((lo - lo) + (hi - hi))) lo = hi = splat4(0.0f);
}

// Whether every sphere of [begin, end) has finite bounds.
inline bool finite_boxes(const Sphere* s, uint32_t begin, uint32_t end) {
  bool all = true;
  for (uint32_t i = begin; i < end; ++i) {
    F4 lo, hi;
    sphere_box<false>(s[i], lo, hi);
    all &= xyz_zero4((lo - lo) + (hi - hi));
  }
  return all;
}

// Spheres (and their materials, when m is not null) split in place. kChecked: some sphere's
// bounds may not be finite (they become a point at the origin); false once all are known finite,
// which gives the same bounds with less work.
template <bool kChecked>
struct SpherePrims {
  Sphere* s;
  uint16_t* m;
  static constexpr bool kMayMix = false;

  void box(uint32_t i, F4& lo, F4& hi) const { sphere_box<kChecked>(s[i], lo, hi); }
  void swap(uint32_t i, uint32_t j) const {
    std::swap(s[i], s[j]);
    if (m) std::swap(m[i], m[j]);
  }
  void reorder(uint32_t begin, uint32_t n, const uint8_t* order) const {
    Sphere ts[kSmallSplit];
    uint16_t tm[kSmallSplit];
    for (uint32_t i = 0; i < n; ++i) {
      ts[i] = s[begin + order[i]];
      if (m) tm[i] = m[begin + order[i]];
    }
    for (uint32_t i = 0; i < n; ++i) {
      s[begin + i] = ts[i];
      if (m) m[begin + i] = tm[i];
    }
  }
  void select(uint32_t begin, uint32_t end, uint32_t k, int axis) const;  // _order.cpp
  bool homogeneous(uint32_t, uint32_t) const { return true; }
  uint32_t split_kinds(uint32_t begin, uint32_t end) const { return begin + (end - begin) / 2; }
};

}  // namespace frameless::sphere_bvh
