// The binned-SAH splits shared by both BVH builders (bvh_build.cpp over primitive references,
// bvh_build_spheres.cpp over spheres in place): range bounds, binning, the SAH sweep, the in-place
// partition, exact SAH for small ranges and the choice of a node's up to eight children.
//
// Speed: ranges are partitioned in place (Hoare: one swap per misplaced pair; by blocks without
// branches when the sides alternate, which gives the same result), and each partition gathers
// the centroid bounds of both sides on the way (no bounds pass per split); binning keeps
// each bin's box as one 8-float value (lo, -hi: one min per update) and deals neighbours to
// several bin sets, so neighbours falling into one bin do not wait on each other's update; the
// sweep costs the three axes side by side in SIMD lanes; ranges of at most kSmallSplit primitives
// are split by exact SAH over their sorted centroids (cheaper there than bins, and better); a
// node of at most eight primitives takes each as a one-primitive leaf without splitting (what
// the split policy gives anyway). Every step is deterministic and bins merge by exact min, max
// and sums, so chunked parallel binning gives the same bins, hence the same tree, as serial.
#pragma once
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <functional>
#include <vector>

#include "core/accel/bvh_build_f4.h"
#include "core/accel/bvh_build_small.h"
#include "core/base/parallel_for.h"
#include "core/accel/bvh_node.h"

namespace frameless::bvh_split {

using namespace bvh_f4;

// Past this node level splits become object medians, which bounds the tree depth (and so the
// traversal stack) even for adversarial primitive distributions.
inline constexpr int kSahDepthLimit = 32;
// With an executor, splits of at least kParallelBinMin primitives bin (and ranges get their
// bounds) in parallel chunks of kBinChunk.
inline constexpr uint32_t kParallelBinMin = 1u << 17;
inline constexpr uint32_t kBinChunk = 1u << 15;
// Both builders: a top part plus subtree tasks above kParallelMin primitives, executor or not.
inline constexpr uint32_t kParallelMin = 65536;
inline constexpr uint32_t kMinTask = 16384;  // the smallest task size limit
// Binning deals neighbours to kBinSets bin sets from kManyBinSets primitives on, to two from
// kTwoBinSets on.
inline constexpr int kBinSets = 8;
inline constexpr uint32_t kManyBinSets = 256;
inline constexpr uint32_t kTwoBinSets = 48;
// Partitions of at least kBlockMin primitives whose first kMixedSample change sides at least
// kMixedChanges times go by blocks of kBlock.
inline constexpr uint32_t kBlock = 64;
inline constexpr uint32_t kBlockMin = 512;
inline constexpr uint32_t kMixedSample = 64;
inline constexpr uint32_t kMixedChanges = 8;

struct Range {
  uint32_t begin = 0, end = 0;
  Box4 box;   // bounds of the primitives
  Box4 cbox;  // bounds of the doubled centroids lo + hi (what the bins are laid over)
  float area = 0.0f;
  bool leaf_ok = false;
  SmallSplit small;  // the best exact split, when the leaf decision found it
  uint32_t count() const { return end - begin; }
};

// Per axis and bin: bounds and count of the primitives whose doubled centroid falls there.
struct BinSet {
  Box8 box[3][kMaxBins];
  uint32_t count[3][kMaxBins];
  BinSet() = default;  // uninitialised: init() before use
  explicit BinSet(int k_bins) { init(k_bins); }
  void init(int k_bins) {
    for (int a = 0; a < 3; ++a)
      for (int k = 0; k < k_bins; ++k) {
        box[a][k] = empty8();
        count[a][k] = 0;
      }
  }
  void merge(const BinSet& o, int k_bins) {
    for (int a = 0; a < 3; ++a)
      for (int k = 0; k < k_bins; ++k) {
        box[a][k] = min8(box[a][k], o.box[a][k]);
        count[a][k] += o.count[a][k];
      }
  }
  void add(int a, int k, Box8 b) {
    box[a][k] = min8(box[a][k], b);
    ++count[a][k];
  }
};

inline void set_child_box(Bvh8Node& node, int i, const Box4& b) {
  alignas(16) float lo[4], hi[4];
  store4(lo, b.lo);
  store4(hi, b.hi);
  for (int a = 0; a < 3; ++a) {
    node.bounds[2 * a][i] = lo[a];
    node.bounds[2 * a + 1][i] = hi[a];
  }
}

// Prims is the primitive array being split, with:
//   void box(uint32_t i, F4& lo, F4& hi) const;  // bounds of primitive i (w lanes unused)
//   void swap(uint32_t i, uint32_t j) const;
//   // [begin, begin + n) becomes the old [begin + order[0]], [begin + order[1]], ...
//   void reorder(uint32_t begin, uint32_t n, const uint8_t* order) const;
//   // Position k of [begin, end) gets what sorting by doubled centroid on axis would put there,
//   // nothing larger before it, nothing smaller after it.
//   void select(uint32_t begin, uint32_t end, uint32_t k, int axis) const;
//   bool homogeneous(uint32_t begin, uint32_t end) const;  // one kind of primitive (leaves)
//   // A mixed range of at most max_leaf: reorder [begin, end) by kind and return where the first
//   // one's kind ends.
//   uint32_t split_kinds(uint32_t begin, uint32_t end) const;
//   static constexpr bool kMayMix;  // whether homogeneous() can ever be false
template <class Prims>
class Splitter {
 public:
  // pf: executor for chunked binning and bounds of large ranges (top of the tree only), or null.
  Splitter(const Prims& p, const SplitSettings& s, const ParallelFor* pf)
      : p_(p), s_(s), pf_(pf) {}

  void finish_range(Range& r) const {
    r.area = r.box.half_area();
    r.leaf_ok = r.count() <= s_.max_leaf && (!Prims::kMayMix || p_.homogeneous(r.begin, r.end)) && leaf_pays(r);
  }

  // Up to node_cost primitives a leaf always; more (up to max_leaf) where the exact SAH says a
  // split would not save rays a node visit's worth of tests (bvh_build_small.h).
  bool leaf_pays(Range& r) const {
    const uint32_t n = r.count();
    if (float(n) <= s_.node_cost || n > kSmallSplit) return true;
    F4 lo[kSmallSplit], hi[kSmallSplit];
    for (uint32_t i = 0; i < n; ++i) p_.box(r.begin + i, lo[i], hi[i]);
    bool use[3];
    const Vec3 extent = xyz(r.cbox.hi - r.cbox.lo);
    for (int a = 0; a < 3; ++a) use[a] = extent[a] > 0.0f;  // as split_small decides them
    return leaf_beats_split(lo, hi, n, r.area, s_.node_cost, use, r.small);
  }

  // Bounds and centroid bounds of [begin, end), in parallel chunks when allowed.
  Range make_range(uint32_t begin, uint32_t end) const {
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
      for (const Range& q : part) {
        r.box.grow(q.box);
        r.cbox.grow(q.cbox);
      }
    } else {
      bounds_of(begin, end, r);
    }
    finish_range(r);
    return r;
  }

  // Splits a node's range into at most eight children: the largest child that cannot be a
  // leaf is split first; free slots then go to splitting leaves (box tests are cheaper than
  // primitive tests, and the node exists anyway).
  int collect_children(const Range& r, int level, Range* ch) {
    const uint32_t n = r.count();
    if (n <= uint32_t(kBvhWidth) && (!Prims::kMayMix || p_.homogeneous(r.begin, r.end))) {
      // The policy below ends with one primitive per slot whatever the splits: take them as
      // they are.
      for (uint32_t i = 0; i < n; ++i) single(r.begin + i, ch[i]);
      return int(n);
    }
    int count = 1;
    ch[0] = r;
    while (count < kBvhWidth) {
      int best = -1;
      float best_area = -1.0f;
      for (int pass = 0; pass < 2 && best < 0; ++pass)
        for (int i = 0; i < count; ++i) {
          const bool want = pass == 0 ? !ch[i].leaf_ok : ch[i].count() > 1;
          if (want && ch[i].area > best_area) best = i, best_area = ch[i].area;
        }
      if (best < 0) break;
      Range left, right;
      split(ch[best], level, left, right);
      ch[best] = left;
      ch[count++] = right;
    }
    return count;
  }

 private:
  void single(uint32_t i, Range& c) const {
    F4 lo, hi;
    p_.box(i, lo, hi);
    c.begin = i;
    c.end = i + 1;
    c.box = Box4();
    c.box.grow(lo, hi);
    c.cbox = Box4();
    c.cbox.grow(lo + hi);
    finish_range(c);
  }

  void bounds_of(uint32_t begin, uint32_t end, Range& r) const {
    Box4 box, cbox;
    for (uint32_t i = begin; i < end; ++i) {
      F4 lo, hi;
      p_.box(i, lo, hi);
      box.grow(lo, hi);
      cbox.grow(lo + hi);
    }
    r.box = box;
    r.cbox = cbox;
  }

  void finish(const Range& r, uint32_t mid, Range& left, Range& right) const {
    left = make_range(r.begin, mid);
    right = make_range(mid, r.end);
  }

  void median(const Range& r, int axis, Range& left, Range& right) const {
    const uint32_t mid = r.begin + r.count() / 2;
    p_.select(r.begin, r.end, mid, axis);
    finish(r, mid, left, right);
  }

  // Splits r (at least two primitives) into two non-empty ranges.
  void split(const Range& r, int level, Range& left, Range& right) {
    const uint32_t n = r.count();
    if (Prims::kMayMix && n <= s_.max_leaf && !p_.homogeneous(r.begin, r.end))
      return finish(r, p_.split_kinds(r.begin, r.end), left, right);
    const Vec3 extent = xyz(r.cbox.hi - r.cbox.lo);
    const int axis =
        extent.x >= extent.y ? (extent.x >= extent.z ? 0 : 2) : (extent.y >= extent.z ? 1 : 2);
    if (!(extent[axis] > 0.0f) || !std::isfinite(extent[axis]))
      return finish(r, r.begin + n / 2, left, right);  // all centroids equal: any split is as good
    if (n <= kSmallSplit) return split_small(r, level, axis, extent, left, right);
    if (level > kSahDepthLimit) return median(r, axis, left, right);
    split_binned(r, axis, extent, left, right);
  }

  // Bins [begin, end) into sets[0..S): S primitives a step, the j-th of each into set j.
  template <int S>
  void bin(uint32_t begin, uint32_t end, F4 cb_lo, F4 sc, BinSet* sets) const {
    const float kmax = float(s_.bins - 1);
    alignas(16) int k[S][4];
    uint32_t i = begin;
    for (; i + S <= end; i += S) {
      Box8 b[S];
      for (int j = 0; j < S; ++j) {
        F4 lo, hi;
        p_.box(i + j, lo, hi);
        bin4(lo + hi, cb_lo, sc, kmax, k[j]);
        b[j] = pack8(lo, hi);
      }
      for (int x = 0; x < 3; ++x)
        for (int j = 0; j < S; ++j) sets[j].add(x, k[j][x], b[j]);
    }
    for (int j = 0; i < end; ++i, ++j) {
      F4 lo, hi;
      p_.box(i, lo, hi);
      bin4(lo + hi, cb_lo, sc, kmax, k[0]);
      const Box8 b = pack8(lo, hi);
      for (int x = 0; x < 3; ++x) sets[j].add(x, k[0][x], b);
    }
  }

  // Bins [begin, end) into out (initialised), through S sets.
  template <int S>
  void bin_into(uint32_t begin, uint32_t end, F4 cb_lo, F4 sc, BinSet& out) const {
    if constexpr (S == 1) {
      bin<1>(begin, end, cb_lo, sc, &out);
    } else {
      const int k_bins = s_.bins;
      BinSet sets[S];
      for (int j = 0; j < S; ++j) sets[j].init(k_bins);
      bin<S>(begin, end, cb_lo, sc, sets);
      for (int j = 0; j < S; ++j) out.merge(sets[j], k_bins);
    }
  }

  void split_binned(const Range& r, int axis, const Vec3& extent, Range& left, Range& right) {
    const uint32_t n = r.count();
    const int k_bins = s_.bins;
    float scale[3];
    for (int a = 0; a < 3; ++a)
      scale[a] = extent[a] > 0.0f ? float(k_bins) * 0.99999f / extent[a] : 0.0f;
    const F4 cb_lo = r.cbox.lo;
    const F4 sc = f4(Vec3(scale[0], scale[1], scale[2]));
    BinSet bins(k_bins);
    if (pf_ && n >= kParallelBinMin) {
      const size_t chunks = (n + kBinChunk - 1) / kBinChunk;
      std::vector<BinSet> part(chunks, BinSet(k_bins));
      (*pf_)(chunks, [&](size_t c) {
        const uint32_t b = r.begin + uint32_t(c) * kBinChunk;
        bin_into<kBinSets>(b, std::min(r.end, b + kBinChunk), cb_lo, sc, part[c]);
      });
      for (const BinSet& q : part) bins.merge(q, k_bins);
    } else if (n >= kManyBinSets) {
      bin_into<kBinSets>(r.begin, r.end, cb_lo, sc, bins);
    } else if (n >= kTwoBinSets) {
      bin_into<2>(r.begin, r.end, cb_lo, sc, bins);
    } else {
      bin_into<1>(r.begin, r.end, cb_lo, sc, bins);
    }
    // SAH sweep: cost of splitting between bins k-1 and k, for every axis.
    const bool use[3] = {extent[0] > 0.0f, extent[1] > 0.0f, extent[2] > 0.0f};
    const SweepResult best = sweep3<kMaxBins>(k_bins, use, [&](int a, int k) {
      return SweepItem{lo8(bins.box[a][k]), hi8(bins.box[a][k]), bins.count[a][k]};
    });
    if (best.axis < 0) return median(r, axis, left, right);
    const int best_axis = best.axis, best_k = best.pos;
    Box4 lbox, rbox;
    for (int k = 0; k < k_bins; ++k)
      (k < best_k ? lbox : rbox).grow(lo8(bins.box[best_axis][k]), hi8(bins.box[best_axis][k]));

    // In-place partition; every primitive is classified once (by the same bin computation as
    // the binning), and its centroid joins the centroid bounds of its side on the way.
    const float kmax = float(k_bins - 1);
    auto is_left = [&](uint32_t i, F4& c) {
      F4 lo, hi;
      p_.box(i, lo, hi);
      c = lo + hi;
      alignas(16) int k[4];
      bin4(c, cb_lo, sc, kmax, k);
      return k[best_axis] < best_k;
    };
    Box4 lc, rc;
    uint32_t i = r.begin, j = r.end;  // [begin, i) left, [j, end) right
    if (n >= kBlockMin && mixed_sides(r.begin, is_left)) {
      // Sides that alternate often (primitives in no spatial order): Hoare's loops would
      // mispredict about every other step. Block partition (Edelkamp and Weiss 2016) classifies
      // a block at each end without branches, noting the misplaced ones, then swaps them in
      // pairs: the same pairs in the same order as Hoare's, so the same result.
      uint8_t off_l[kBlock], off_r[kBlock];
      uint32_t num_l = 0, num_r = 0, start_l = 0, start_r = 0;
      const F4 inf = splat4(kInfinity), ninf = splat4(-kInfinity);
      auto grow = [&](bool l, F4 c) {
        lc.lo = min4(lc.lo, select4(l, c, inf));
        lc.hi = max4(lc.hi, select4(l, c, ninf));
        rc.lo = min4(rc.lo, select4(l, inf, c));
        rc.hi = max4(rc.hi, select4(l, ninf, c));
      };
      while (j - i >= 2 * kBlock) {
        if (num_l == 0) {
          start_l = 0;
          for (uint32_t k = 0; k < kBlock; ++k) {
            F4 c;
            const bool l = is_left(i + k, c);
            grow(l, c);
            off_l[num_l] = uint8_t(k);
            num_l += !l;
          }
        }
        if (num_r == 0) {
          start_r = 0;
          for (uint32_t k = 0; k < kBlock; ++k) {
            F4 c;
            const bool l = is_left(j - 1 - k, c);
            grow(l, c);
            off_r[num_r] = uint8_t(k);
            num_r += l;
          }
        }
        const uint32_t num = std::min(num_l, num_r);
        for (uint32_t k = 0; k < num; ++k)
          p_.swap(i + off_l[start_l + k], j - 1 - off_r[start_r + k]);
        num_l -= num, num_r -= num, start_l += num, start_r += num;
        if (num_l == 0) i += kBlock;
        if (num_r == 0) j -= kBlock;
      }
    }
    for (;;) {  // Hoare's partition (of what the blocks left)
      F4 ci, cj;
      while (i < j && is_left(i, ci)) lc.grow(ci), ++i;
      while (i < j && !is_left(j - 1, cj)) rc.grow(cj), --j;
      if (i >= j) break;
      p_.swap(i, j - 1);
      lc.grow(cj);
      rc.grow(ci);
      ++i, --j;
    }
    left.begin = r.begin;
    left.end = right.begin = i;
    right.end = r.end;
    left.box = lbox;
    left.cbox = lc;
    right.box = rbox;
    right.cbox = rc;
    finish_range(left);
    finish_range(right);
  }

  // Whether the sides change at least kMixedChanges times over the first kMixedSample primitives
  // from begin (a cheap look at how well branches on the side would predict).
  template <class IsLeft>
  static bool mixed_sides(uint32_t begin, IsLeft& is_left) {
    F4 c;
    bool prev = is_left(begin, c);
    uint32_t changes = 0;
    for (uint32_t k = 1; k < kMixedSample; ++k) {
      const bool l = is_left(begin + k, c);
      changes += l != prev;
      prev = l;
    }
    return changes >= kMixedChanges;
  }

  // Exact SAH for a small range (n <= kSmallSplit, centroids not all equal): every split between
  // neighbours in centroid order on every axis with an extent is costed; the range is then
  // reordered along the best axis. Past the SAH depth limit: the median on the widest axis.
  void split_small(const Range& r, int level, int axis, const Vec3& extent, Range& left,
                   Range& right) const {
    const uint32_t n = r.count();
    if (n == 2) {  // one split only, and the order of the two does not matter
      single(r.begin, left);
      single(r.begin + 1, right);
      return;
    }
    F4 lo[kSmallSplit], hi[kSmallSplit];
    for (uint32_t i = 0; i < n; ++i) p_.box(r.begin + i, lo[i], hi[i]);
    // The best exact split, kept by the leaf decision or found now; past the SAH depth limit, or
    // when no split has a finite cost (overflowing boxes), the median on the widest axis.
    SmallSplit split = r.small;
    if (level > kSahDepthLimit) {
      split.axis = -1;
    } else if (split.axis < 0) {
      bool use[3];
      for (int a = 0; a < 3; ++a) use[a] = extent[a] > 0.0f;
      best_small_split(lo, hi, n, use, split);
    }
    if (split.axis < 0) {
      alignas(32) float c[3][kSmallPad];
      centroid_keys(lo, hi, n, c);
      centroid_order(c[axis], n, split.order);
      split.pos = uint8_t(n / 2);
    }
    const uint32_t best_i = split.pos;
    const uint8_t* o = split.order;
    p_.reorder(r.begin, n, o);
    Box4 box[2], cbox[2];
    for (uint32_t i = 0; i < n; ++i) {
      const int side = i < best_i ? 0 : 1;
      box[side].grow(lo[o[i]], hi[o[i]]);
      cbox[side].grow(lo[o[i]] + hi[o[i]]);
    }
    left.begin = r.begin;
    left.end = right.begin = r.begin + best_i;
    right.end = r.end;
    left.box = box[0];
    left.cbox = cbox[0];
    right.box = box[1];
    right.cbox = cbox[1];
    finish_range(left);
    finish_range(right);
  }

  Prims p_;
  SplitSettings s_;
  const ParallelFor* pf_;
};

}  // namespace frameless::bvh_split
