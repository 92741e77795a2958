// The BVH builders' leaf policy and exact SAH over small ranges (both builders, through
// bvh_build_split.h): the split settings of a tree, primitives in centroid order on an axis, and
// whether a range is cheaper for rays as one leaf than split.
#pragma once
#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>

#if defined(__AVX2__)
#include <immintrin.h>
#endif

#include "core/accel/accel_types.h"
#include "core/accel/bvh_build_f4.h"
#include "core/accel/bvh_node.h"

namespace frameless::bvh_split {

using namespace bvh_f4;

// Ranges up to this size are split by exact SAH over sorted centroids instead of bins.
inline constexpr uint32_t kSmallSplit = 16;
inline constexpr uint32_t kSmallPad = 16;  // key arrays of small splits
static_assert(kSmallSplit <= kSmallPad, "small splits fit the key arrays");

// Trees over fewer primitives stay in the caches (at about 70 bytes a triangle, a few times a
// 2 MB L2), where a node visit costs about a primitive test and leaves stay small; bigger trees'
// visits are cache misses, and leaves grow where the exact SAH says they pay (benchmarks.md,
// section 38: the dragon's rays up to 22 % faster, a million spheres' 7-21 %, the soup's and the
// 11 M mesh's the same; leaves of 16 in every tree cost instanced plants up to 25 %).
inline constexpr size_t kCachedTreePrims = size_t(1) << 17;
// A node visit's cost in primitive tests in such trees: triangles (patches and mixed sets too)
// and spheres, whose test reads 16 bytes against a triangle's 36.
inline constexpr float kTriangleNodeCost = 3.0f;
inline constexpr float kSphereNodeCost = 8.0f;

// Bins per axis at most (AccelConfig::sah_bins is held to it).
inline constexpr int kMaxBins = 64;

struct SplitSettings {
  uint32_t max_leaf = 4;
  float node_cost = 4.0f;  // a node visit in primitive tests: leaves past it only where they pay
  int bins = 16;
};

// The settings of a tree over n primitives, a node visit costing node_cost tests where the tree
// outgrows the caches: there leaves of up to config.max_leaf_size where they pay; a smaller tree
// takes every range of up to config.cached_leaf_size as a leaf.
inline SplitSettings split_settings(const AccelConfig& config, size_t n, float node_cost) {
  SplitSettings s;
  const bool cached = n < kCachedTreePrims;
  s.max_leaf = uint32_t(std::clamp(cached ? config.cached_leaf_size : config.max_leaf_size, 1, kMaxLeafSize));
  s.node_cost = cached ? float(s.max_leaf) : node_cost;
  s.bins = std::clamp(config.sah_bins, 2, kMaxBins);
  return s;
}

// order[rank] = i for keys key[0, n) (padded with +inf to kSmallPad): a stable counting of
// smaller keys, no data-dependent branches.
inline void centroid_order(const float* key, uint32_t n, uint8_t* order) {
#if defined(__AVX2__)
  static_assert(kSmallPad == 16, "two AVX registers of keys");
  const __m256 k0 = _mm256_loadu_ps(key), k1 = _mm256_loadu_ps(key + 8);
  for (uint32_t i = 0; i < n; ++i) {
    const __m256 ki = _mm256_set1_ps(key[i]);
    const uint32_t lt = uint32_t(_mm256_movemask_ps(_mm256_cmp_ps(k0, ki, _CMP_LT_OQ))) |
                        uint32_t(_mm256_movemask_ps(_mm256_cmp_ps(k1, ki, _CMP_LT_OQ))) << 8;
    const uint32_t eq = uint32_t(_mm256_movemask_ps(_mm256_cmp_ps(k0, ki, _CMP_EQ_OQ))) |
                        uint32_t(_mm256_movemask_ps(_mm256_cmp_ps(k1, ki, _CMP_EQ_OQ))) << 8;
    order[__builtin_popcount(lt | (eq & ((1u << i) - 1u)))] = uint8_t(i);
  }
#else
  for (uint32_t i = 0; i < n; ++i) {
    const float ki = key[i];
    uint32_t rank = 0;
    for (uint32_t j = 0; j < n; ++j) rank += (key[j] < ki) | ((key[j] == ki) & (j < i));
    order[rank] = uint8_t(i);
  }
#endif
}

// The doubled centroids of boxes lo/hi[0, n) by axis, padded with +inf (never smaller than a
// key, never counted).
inline void centroid_keys(const F4* lo, const F4* hi, uint32_t n, float (*c)[kSmallPad]) {
  for (int a = 0; a < 3; ++a)
    for (uint32_t i = n; i < kSmallPad; ++i) c[a][i] = kInfinity;
  for (uint32_t i = 0; i < n; ++i) {
    alignas(16) float f[4];
    store4(f, lo[i] + hi[i]);
    for (int a = 0; a < 3; ++a) c[a][i] = f[a];
  }
}

// A small range's best exact SAH split, kept from the leaf decision for the split itself:
// the axis (-1: none kept), where it cuts, and the range's order along that axis.
struct SmallSplit {
  int8_t axis = -1;
  uint8_t pos = 0;
  uint8_t order[kSmallSplit];
};

// The best exact SAH split of boxes lo/hi[0, n) (2 <= n <= kSmallSplit) between neighbours in
// centroid order on the axes use[a]: its cost, with its axis, position and order in `split`; an
// infinite cost, `split` untouched, when no split has a finite one (overflowing boxes).
inline float best_small_split(const F4* lo, const F4* hi, uint32_t n, const bool use[3], SmallSplit& split) {
  alignas(32) float c[3][kSmallPad];
  centroid_keys(lo, hi, n, c);
  uint8_t order[3][kSmallSplit];
  for (int a = 0; a < 3; ++a) {
    if (use[a]) {
      centroid_order(c[a], n, order[a]);
    } else {  // read by the sweep, result unused
      for (uint32_t i = 0; i < n; ++i) order[a][i] = uint8_t(i);
    }
  }
  const SweepResult best = sweep3<kSmallSplit>(int(n), use, [&](int a, int k) {
    const uint8_t i = order[a][k];
    return SweepItem{lo[i], hi[i], 1u};
  });
  if (!(best.cost < kInfinity)) return kInfinity;
  split.axis = int8_t(best.axis);
  split.pos = uint8_t(best.pos);
  std::copy(order[best.axis], order[best.axis] + n, split.order);
  return best.cost;
}

// Whether n primitives (boxes lo/hi, 2 <= n <= kSmallSplit, their bounds' half area `area`) cost
// rays no more as one leaf than as a node over the best exact SAH split, a node visit costing
// `node_cost` primitive tests: n * area <= node_cost * area + SAH(best split). Leaves hold
// overlapping primitives (a dense surface: splitting halves neither the area nor the work) and
// split far-apart ones (a soup of small triangles: the children's boxes are mostly empty space).
// use[a]: the axes with a centroid extent. The split found (if any) goes to `best_split`.
inline bool leaf_beats_split(const F4* lo, const F4* hi, uint32_t n, float area, float node_cost,
                             const bool use[3], SmallSplit& best_split) {
  // No split costs less than the primitives' own boxes: overlapping ones need no sorting.
  float own = 0.0f;
  for (uint32_t i = 0; i < n; ++i) own += half_area4(lo[i], hi[i]);
  if (float(n) * area <= node_cost * area + own) return true;
  const float cost = best_small_split(lo, hi, n, use, best_split);
  // No split with a finite cost: nothing to gain.
  return !(cost < kInfinity) || float(n) * area <= node_cost * area + cost;
}

}  // namespace frameless::bvh_split
