// Splits of the in-place sphere BVH builder (bvh_build_spheres_internal.h) that order spheres by
// centre: exact SAH over sorted centres for small ranges, and the object median (quickselect)
// used past the SAH depth limit and when binning finds no split.
#include <algorithm>
#include <cstdint>

#include "core/bvh_build_spheres_internal.h"

namespace frameless::sphere_bvh {

Vec3 Builder::centre2(const Sphere& s) {
  F4 lo, hi;
  sphere_box(s, lo, hi);
  return xyz(lo + hi);
}

// Reorders [begin, end) so that position k holds the sphere whose doubled centre on `axis`
// would be there after sorting, with no larger one before it and no smaller one after it.
// Three-way quickselect (runs of equal keys end it at once), pivot the median of three
// positions drawn from a fixed hash of the range (no sorted-input worst case).
void Builder::select(uint32_t begin, uint32_t end, uint32_t k, int axis) const {
  auto key = [&](uint32_t i) { return centre2(s_[i])[axis]; };
  uint64_t h = (uint64_t(begin) << 32) ^ end ^ 0x9e3779b97f4a7c15ull;
  while (end - begin > 16) {
    const uint32_t n = end - begin;
    float p3[3];
    for (float& p : p3) {
      h ^= h >> 33;
      h *= 0xff51afd7ed558ccdull;
      h ^= h >> 29;
      p = key(begin + uint32_t(h % n));
    }
    const float pivot = std::max(std::min(p3[0], p3[1]), std::min(std::max(p3[0], p3[1]), p3[2]));
    uint32_t lt = begin, i = begin, gt = end;
    while (i < gt) {
      const float v = key(i);
      if (v < pivot) swap(lt++, i++);
      else if (v > pivot) swap(i, --gt);
      else ++i;
    }
    if (k < lt) end = lt;
    else if (k >= gt) begin = gt;
    else return;
  }
  for (uint32_t i = begin + 1; i < end; ++i)  // insertion sort of the last few
    for (uint32_t j = i; j > begin && key(j) < key(j - 1); --j) swap(j, j - 1);
}

// Exact SAH for a small range (n <= kSmallSplit, centres not all equal): every split between
// neighbours in centre order on every axis with an extent is costed; the range is then
// reordered along the best axis. Past the SAH depth limit: the median on the widest axis.
// Sorting is by rank (a stable counting of smaller keys: no data-dependent branches).
void Builder::split_small(const Range& r, int level, int axis, Range& left, Range& right) const {
  const uint32_t n = r.count();
  F4 lo[kSmallSplit], hi[kSmallSplit];
  alignas(32) float c[3][kSmallSplit];
  for (uint32_t i = 0; i < n; ++i) {
    sphere_box(s_[r.begin + i], lo[i], hi[i]);
    alignas(16) float f[4];
    store4(f, lo[i] + hi[i]);
    for (int a = 0; a < 3; ++a) c[a][i] = f[a];
  }
  uint8_t order[3][kSmallSplit];
  auto sort_axis = [&](int a) {
    const float* key = c[a];
    for (uint32_t i = 0; i < n; ++i) {
      const float ki = key[i];
      uint32_t rank = 0;
      for (uint32_t j = 0; j < n; ++j) rank += (key[j] < ki) | ((key[j] == ki) & (j < i));
      order[a][rank] = uint8_t(i);
    }
  };
  const Vec3 extent = r.cbox.hi - r.cbox.lo;
  float best_cost = kInfinity;
  int best_axis = -1;
  uint32_t best_i = 0;
  for (int a = 0; a < 3; ++a) {
    if (!(extent[a] > 0.0f) || (level > kSahDepthLimit && a != axis)) continue;
    sort_axis(a);
    if (level > kSahDepthLimit) {
      best_axis = a, best_i = n / 2;
      break;
    }
    const uint8_t* o = order[a];
    float right_area[kSmallSplit];
    Box4 acc;
    for (uint32_t i = n - 1; i > 0; --i) {
      acc.grow(lo[o[i]], hi[o[i]]);
      right_area[i] = acc.half_area();
    }
    acc = Box4();
    for (uint32_t i = 1; i < n; ++i) {
      acc.grow(lo[o[i - 1]], hi[o[i - 1]]);
      const float cost = acc.half_area() * float(i) + right_area[i] * float(n - i);
      if (cost < best_cost) best_cost = cost, best_axis = a, best_i = i;
    }
  }
  if (best_axis < 0) {  // no finite cost (overflowing boxes): median on the widest axis
    best_axis = axis;
    best_i = n / 2;
    sort_axis(axis);
  }
  const uint8_t* o = order[best_axis];
  Sphere tmp_s[kSmallSplit];
  uint16_t tmp_m[kSmallSplit];
  for (uint32_t i = 0; i < n; ++i) {
    tmp_s[i] = s_[r.begin + o[i]];
    if (m_) tmp_m[i] = m_[r.begin + o[i]];
  }
  Box4 box[2], cbox[2];
  for (uint32_t i = 0; i < n; ++i) {
    s_[r.begin + i] = tmp_s[i];
    if (m_) m_[r.begin + i] = tmp_m[i];
    const int side = i < best_i ? 0 : 1;
    box[side].grow(lo[o[i]], hi[o[i]]);
    const F4 ci = lo[o[i]] + hi[o[i]];
    cbox[side].grow(ci, ci);
  }
  left.begin = r.begin;
  left.end = right.begin = r.begin + best_i;
  right.end = r.end;
  left.box = box[0].box();
  left.cbox = cbox[0].box();
  right.box = box[1].box();
  right.cbox = cbox[1].box();
}

}  // namespace frameless::sphere_bvh
