// The object median of the in-place sphere BVH builder (bvh_build_spheres_internal.h), used past
// the SAH depth limit and when binning finds no split: quickselect by centre.
#include <algorithm>
#include <cstdint>

#include "core/accel/bvh_build_spheres_internal.h"

namespace frameless::sphere_bvh {

// Reorders [begin, end) so that position k holds the sphere whose doubled centre on `axis`
// would be there after sorting, with no larger one before it and no smaller one after it.
// Three-way quickselect (runs of equal keys end it at once), pivot the median of three
// positions drawn from a fixed hash of the range (no sorted-input worst case).
template <bool kChecked>
void SpherePrims<kChecked>::select(uint32_t begin, uint32_t end, uint32_t k, int axis) const {
  auto key = [&](uint32_t i) {
    F4 lo, hi;
    sphere_box<kChecked>(s[i], lo, hi);
    return xyz(lo + hi)[axis];
  };
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

template struct SpherePrims<true>;
template struct SpherePrims<false>;

}  // namespace frameless::sphere_bvh
