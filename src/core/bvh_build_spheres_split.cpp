// Binned-SAH splitting of the in-place sphere BVH builder (bvh_build_spheres_internal.h): range
// bounds (chunked in parallel at the top of the tree), binning, the SAH sweep and the in-place
// partition of spheres and materials that also gathers each side's centre bounds, and the choice
// of a node's up to eight children. Small ranges and object medians: bvh_build_spheres_order.cpp.
#include <algorithm>
#include <cmath>
#include <vector>

#include "core/bvh_build_spheres_internal.h"

namespace frameless::sphere_bvh {

// Per axis and bin: bounds (F4 form) and count of the spheres whose doubled centre falls there.
struct BinSet {
  F4 lo[3][kMaxBins], hi[3][kMaxBins];
  uint32_t count[3][kMaxBins];
  explicit BinSet(int k_bins) {
    for (int a = 0; a < 3; ++a)
      for (int k = 0; k < k_bins; ++k) {
        lo[a][k] = splat4(kInfinity);
        hi[a][k] = splat4(-kInfinity);
        count[a][k] = 0;
      }
  }
  void merge(const BinSet& o, int k_bins) {
    for (int a = 0; a < 3; ++a)
      for (int k = 0; k < k_bins; ++k) {
        lo[a][k] = min4(lo[a][k], o.lo[a][k]);
        hi[a][k] = max4(hi[a][k], o.hi[a][k]);
        count[a][k] += o.count[a][k];
      }
  }
  Box box(int a, int k) const {
    Box b;
    b.lo = xyz(lo[a][k]);
    b.hi = xyz(hi[a][k]);
    return b;
  }
};

Range Builder::make_range(uint32_t begin, uint32_t end) const {
  Range r;
  r.begin = begin;
  r.end = end;
  const uint32_t n = end - begin;
  if (pf_ && n >= kParallelBinMin) {
    const size_t chunks = (n + kBinChunk - 1) / kBinChunk;
    std::vector<Range> part(chunks);
    (*pf_)(chunks, [&](size_t c) {
      const uint32_t b = begin + uint32_t(c) * kBinChunk;
      bounds_of(b, std::min(end, b + kBinChunk), part[c]);
    });
    for (const Range& p : part) {
      r.box.grow(p.box);
      r.cbox.grow(p.cbox);
    }
  } else {
    bounds_of(begin, end, r);
  }
  return r;
}

int Builder::collect_children(const Range& r, int level, Range* ch) {
  int n = 1;
  ch[0] = r;
  while (n < kBvhWidth) {
    int best = -1;
    float best_area = -1.0f;
    for (int pass = 0; pass < 2 && best < 0; ++pass)
      for (int i = 0; i < n; ++i) {
        const bool want = pass == 0 ? !leaf_ok(ch[i]) : ch[i].count() > 1;
        if (want && ch[i].box.half_area() > best_area) best = i, best_area = ch[i].box.half_area();
      }
    if (best < 0) break;
    Range left, right;
    split(ch[best], level, left, right);
    ch[best] = left;
    ch[n++] = right;
  }
  return n;
}

void Builder::bounds_of(uint32_t begin, uint32_t end, Range& r) const {
  Box4 box, cbox;
  for (uint32_t i = begin; i < end; ++i) {
    F4 lo, hi;
    sphere_box(s_[i], lo, hi);
    box.grow(lo, hi);
    const F4 c = lo + hi;
    cbox.grow(c, c);
  }
  r.box = box.box();
  r.cbox = cbox.box();
}

void Builder::finish(const Range& r, uint32_t mid, Range& left, Range& right) const {
  left = make_range(r.begin, mid);
  right = make_range(mid, r.end);
}

void Builder::bin(uint32_t begin, uint32_t end, const Box& cb, const float* scale,
                  BinSet& out) const {
  const F4 cb_lo = f4(cb.lo);
  const F4 sc = f4(Vec3(scale[0], scale[1], scale[2]));
  const float kmax = float(bins_ - 1);
  for (uint32_t i = begin; i < end; ++i) {
    F4 lo, hi;
    sphere_box(s_[i], lo, hi);
    alignas(16) int k[4];
    bin4(lo + hi, cb_lo, sc, kmax, k);
    for (int a = 0; a < 3; ++a) {
      out.lo[a][k[a]] = min4(out.lo[a][k[a]], lo);
      out.hi[a][k[a]] = max4(out.hi[a][k[a]], hi);
      ++out.count[a][k[a]];
    }
  }
}

// Splits r (at least two spheres) into two non-empty ranges.
void Builder::split(const Range& r, int level, Range& left, Range& right) {
  const uint32_t n = r.count();
  const uint32_t mid = r.begin + n / 2;
  const Vec3 extent = r.cbox.hi - r.cbox.lo;
  const int axis =
      extent.x >= extent.y ? (extent.x >= extent.z ? 0 : 2) : (extent.y >= extent.z ? 1 : 2);
  if (!(extent[axis] > 0.0f) || !std::isfinite(extent[axis]))
    return finish(r, mid, left, right);  // all centres equal: any split is as good
  if (n <= kSmallSplit) return split_small(r, level, axis, left, right);
  if (level > kSahDepthLimit) {
    select(r.begin, r.end, mid, axis);
    return finish(r, mid, left, right);
  }
  const int k_bins = bins_;
  float scale[3];
  for (int a = 0; a < 3; ++a)
    scale[a] = extent[a] > 0.0f ? float(k_bins) * 0.99999f / extent[a] : 0.0f;
  BinSet bins(k_bins);
  if (pf_ && n >= kParallelBinMin) {
    const size_t chunks = (n + kBinChunk - 1) / kBinChunk;
    std::vector<BinSet> part(chunks, BinSet(k_bins));
    (*pf_)(chunks, [&](size_t c) {
      const uint32_t b = r.begin + uint32_t(c) * kBinChunk;
      bin(b, std::min(r.end, b + kBinChunk), r.cbox, scale, part[c]);
    });
    for (const BinSet& p : part) bins.merge(p, k_bins);
  } else {
    bin(r.begin, r.end, r.cbox, scale, bins);
  }
  // SAH sweep: cost of splitting between bins k-1 and k, for every axis.
  float best_cost = kInfinity;
  int best_axis = -1, best_k = 0;
  Box best_left, best_right;
  for (int a = 0; a < 3; ++a) {
    if (!(extent[a] > 0.0f)) continue;
    float right_cost[kMaxBins];
    Box right_box[kMaxBins];
    Box acc;
    uint32_t cnt = 0;
    for (int k = k_bins - 1; k > 0; --k) {
      acc.grow(bins.box(a, k));
      cnt += bins.count[a][k];
      right_cost[k] = cnt ? acc.half_area() * float(cnt) : kInfinity;
      right_box[k] = acc;
    }
    acc = Box();
    cnt = 0;
    for (int k = 1; k < k_bins; ++k) {
      acc.grow(bins.box(a, k - 1));
      cnt += bins.count[a][k - 1];
      if (cnt == 0 || cnt == n) continue;
      const float cost = acc.half_area() * float(cnt) + right_cost[k];
      if (cost < best_cost) {
        best_cost = cost, best_axis = a, best_k = k;
        best_left = acc, best_right = right_box[k];
      }
    }
  }
  if (best_axis < 0) {
    select(r.begin, r.end, mid, axis);
    return finish(r, mid, left, right);
  }
  // In-place partition of spheres and materials together; every sphere is classified once (by
  // the same bin computation as the binning), and its centre joins the centre bounds of its
  // side on the way.
  const F4 cb_lo = f4(r.cbox.lo);
  const F4 sc = f4(Vec3(scale[0], scale[1], scale[2]));
  const float kmax = float(k_bins - 1);
  Box4 side[2];  // centre bounds of the left (0) and right (1) part
  uint32_t m = r.begin;
  for (uint32_t i = r.begin; i < r.end; ++i) {  // branch-free Lomuto partition
    const Sphere si = s_[i];
    F4 lo, hi;
    sphere_box(si, lo, hi);
    const F4 c = lo + hi;
    alignas(16) int k[4];
    bin4(c, cb_lo, sc, kmax, k);
    const uint32_t l = k[best_axis] < best_k ? 1u : 0u;
    side[1 - l].grow(c, c);
    s_[i] = s_[m];
    s_[m] = si;
    if (m_) {
      const uint16_t mi = m_[i];
      m_[i] = m_[m];
      m_[m] = mi;
    }
    m += l;
  }
  const uint32_t i = m;
  Box4& lc = side[0];
  Box4& rc = side[1];
  left.begin = r.begin;
  left.end = i;
  left.box = best_left;
  left.cbox = lc.box();
  right.begin = i;
  right.end = r.end;
  right.box = best_right;
  right.cbox = rc.box();
}

}  // namespace frameless::sphere_bvh
