// Internals of the in-place sphere BVH builder (bvh_build_spheres.h) shared by
// bvh_build_spheres_split.cpp (binned SAH splits, in-place partition, range bounds),
// bvh_build_spheres_order.cpp (splits by centre order: exact SAH of small ranges, object medians)
// and bvh_build_spheres.cpp (node blocks, subtree tasks, assembly, the entry point).
#pragma once
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <functional>
#include <utility>

#if defined(__SSE2__)
#include <immintrin.h>
#endif

#include "core/accel.h"
#include "core/bvh_build.h"
#include "core/geometry.h"

namespace frameless::sphere_bvh {

// Past this node level splits become object medians (as in build_bvh8), bounding the depth.
constexpr int kSahDepthLimit = 32;
constexpr int kMaxBins = 64;
// With an executor, top splits of at least kParallelBinMin spheres bin in parallel chunks of
// kBinChunk spheres.
constexpr uint32_t kParallelBinMin = 1u << 18;
constexpr uint32_t kBinChunk = 1u << 16;
// Ranges up to this size are split by exact SAH over sorted centres instead of bins.
constexpr uint32_t kSmallSplit = 32;

using ParallelFor = std::function<void(size_t, const std::function<void(size_t)>&)>;

struct Box {
  Vec3 lo{kInfinity};
  Vec3 hi{-kInfinity};
  void grow(const Vec3& l, const Vec3& h) {
    lo = glm::min(lo, l);
    hi = glm::max(hi, h);
  }
  void grow(const Vec3& p) { grow(p, p); }
  void grow(const Box& b) { grow(b.lo, b.hi); }
  float half_area() const {
    const Vec3 d = hi - lo;
    if (!(d.x >= 0.0f && d.y >= 0.0f && d.z >= 0.0f)) return 0.0f;
    return d.x * d.y + d.y * d.z + d.z * d.x;
  }
};

// Four floats (x, y, z and a spare lane) for the per-sphere work of binning and partitioning:
// SSE where there is SSE, plain floats otherwise, with the same results (min/max return their
// second operand when unordered, as minps/maxps do).
#if defined(__SSE2__)
struct F4 {
  __m128 v;
};
inline F4 load4(const float* p) { return {_mm_loadu_ps(p)}; }
inline F4 splat4(float x) { return {_mm_set1_ps(x)}; }
inline F4 operator+(F4 a, F4 b) { return {_mm_add_ps(a.v, b.v)}; }
inline F4 operator-(F4 a, F4 b) { return {_mm_sub_ps(a.v, b.v)}; }
inline F4 min4(F4 a, F4 b) { return {_mm_min_ps(a.v, b.v)}; }
inline F4 max4(F4 a, F4 b) { return {_mm_max_ps(a.v, b.v)}; }
inline F4 abs_w4(F4 a) {  // |a.w| in every lane
  const __m128 w = _mm_shuffle_ps(a.v, a.v, _MM_SHUFFLE(3, 3, 3, 3));
  return {_mm_andnot_ps(_mm_set1_ps(-0.0f), w)};
}
inline bool xyz_zero4(F4 a) {
  return (_mm_movemask_ps(_mm_cmpeq_ps(a.v, _mm_setzero_ps())) & 7) == 7;
}
inline void store4(float* p, F4 a) { _mm_storeu_ps(p, a.v); }
// Bin of each lane: (c - lo) * scale clamped to [0, kmax] (NaN to 0), truncated.
inline void bin4(F4 c, F4 lo, F4 scale, float kmax, int* out) {
  const __m128 k = _mm_mul_ps(_mm_sub_ps(c.v, lo.v), scale.v);
  const __m128 kc = _mm_min_ps(_mm_max_ps(k, _mm_setzero_ps()), _mm_set1_ps(kmax));
  _mm_storeu_si128(reinterpret_cast<__m128i*>(out), _mm_cvttps_epi32(kc));
}
#else
struct F4 {
  float v[4];
};
inline F4 load4(const float* p) { return {{p[0], p[1], p[2], p[3]}}; }
inline F4 splat4(float x) { return {{x, x, x, x}}; }
#define FRAMELESS_F4_OP(name, expr)                                   \
  inline F4 name(F4 a, F4 b) {                                        \
    F4 r;                                                             \
    for (int i = 0; i < 4; ++i) r.v[i] = expr;                        \
    return r;                                                         \
  }
FRAMELESS_F4_OP(operator+, a.v[i] + b.v[i])
FRAMELESS_F4_OP(operator-, a.v[i] - b.v[i])
FRAMELESS_F4_OP(min4, a.v[i] < b.v[i] ? a.v[i] : b.v[i])
FRAMELESS_F4_OP(max4, a.v[i] > b.v[i] ? a.v[i] : b.v[i])
#undef FRAMELESS_F4_OP
inline F4 abs_w4(F4 a) { return splat4(std::abs(a.v[3])); }
inline bool xyz_zero4(F4 a) { return a.v[0] == 0.0f && a.v[1] == 0.0f && a.v[2] == 0.0f; }
inline void store4(float* p, F4 a) {
  for (int i = 0; i < 4; ++i) p[i] = a.v[i];
}
inline void bin4(F4 c, F4 lo, F4 scale, float kmax, int* out) {
  for (int i = 0; i < 4; ++i) {
    float k = (c.v[i] - lo.v[i]) * scale.v[i];
    k = k > 0.0f ? k : 0.0f;
    out[i] = int(k < kmax ? k : kmax);
  }
}
#endif

static_assert(sizeof(Sphere) == 4 * sizeof(float), "Sphere must be x, y, z, radius");

// Bounds of one sphere, as Accel::build makes them for build_bvh8: centre +- |radius|, or a point
// at the origin when any bound is not finite (x - x is 0 exactly for finite x).
inline void sphere_box(const Sphere& s, F4& lo, F4& hi) {
  float xyzr[4];
  std::memcpy(xyzr, &s, sizeof xyzr);  // one 16-byte load
  const F4 v = load4(xyzr);
  const F4 r = abs_w4(v);
  lo = v - r;
  hi = v + r;
  if (!xyz_zero4((lo - lo) + (hi - hi))) lo = hi = splat4(0.0f);
}

inline F4 f4(const Vec3& v) {
  const float f[4] = {v.x, v.y, v.z, 0.0f};
  return load4(f);
}

inline Vec3 xyz(F4 a) {
  float f[4];
  store4(f, a);
  return Vec3(f[0], f[1], f[2]);
}

// Running bounds in F4 form.
struct Box4 {
  F4 lo = splat4(kInfinity), hi = splat4(-kInfinity);
  void grow(F4 l, F4 h) {
    lo = min4(lo, l);
    hi = max4(hi, h);
  }
  Box box() const {
    Box b;
    b.lo = xyz(lo);
    b.hi = xyz(hi);
    return b;
  }
  float half_area() const { return box().half_area(); }
};

struct Range {
  uint32_t begin = 0, end = 0;
  Box box;   // bounds of the spheres
  Box cbox;  // bounds of the doubled centres lo + hi (what the bins are laid over)
  uint32_t count() const { return end - begin; }
};

class NodeArena;  // bvh_build_spheres.cpp
struct BinSet;    // bvh_build_spheres_split.cpp

// Splits ranges of the sphere (and material) arrays in place and builds subtrees from them.
class Builder {
 public:
  // pf: executor for chunked binning of large ranges (top of the tree only), or null.
  Builder(Sphere* spheres, uint16_t* materials, const AccelConfig& config, const ParallelFor* pf)
      : s_(spheres),
        m_(materials),
        max_leaf_(uint32_t(std::clamp(config.max_leaf_size, 1, kMaxLeafSize))),
        bins_(std::clamp(config.sah_bins, 2, kMaxBins)),
        pf_(pf) {}

  bool leaf_ok(const Range& r) const { return r.count() <= max_leaf_; }

  // Bounds and centre bounds of [begin, end), in parallel chunks when allowed.
  Range make_range(uint32_t begin, uint32_t end) const;

  // Splits a node's range into at most eight children (same policy as build_bvh8): the largest
  // child that cannot be a leaf is split first; free slots then go to splitting leaves.
  int collect_children(const Range& r, int level, Range* ch);

  // Builds the subtree of r (not a leaf) into arena; returns its node index there.
  uint32_t build(NodeArena& arena, const Range& r, int level);

  int depth = 0;
  size_t leaves = 0;

 private:
  void swap(uint32_t i, uint32_t j) const {
    std::swap(s_[i], s_[j]);
    if (m_) std::swap(m_[i], m_[j]);
  }

  // bvh_build_spheres_split.cpp
  void bounds_of(uint32_t begin, uint32_t end, Range& r) const;
  void finish(const Range& r, uint32_t mid, Range& left, Range& right) const;
  void bin(uint32_t begin, uint32_t end, const Box& cb, const float* scale, BinSet& out) const;
  void split(const Range& r, int level, Range& left, Range& right);
  // bvh_build_spheres_order.cpp
  static Vec3 centre2(const Sphere& s);
  void select(uint32_t begin, uint32_t end, uint32_t k, int axis) const;
  void split_small(const Range& r, int level, int axis, Range& left, Range& right) const;

  Sphere* s_;
  uint16_t* m_;
  uint32_t max_leaf_;
  int bins_;
  const ParallelFor* pf_;
};

}  // namespace frameless::sphere_bvh
