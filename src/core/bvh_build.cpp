// Binned-SAH builder of the 8-wide BVH (top-down, Embree-style: each node splits its largest
// child until eight slots are filled).
#include "core/bvh_build.h"

#include <algorithm>
#include <cmath>

namespace frameless {
namespace {

// Past this depth splits become object medians, which bounds the tree depth (and so the
// traversal stack) even for adversarial primitive distributions.
constexpr int kSahDepthLimit = 32;
constexpr int kMaxBins = 64;

struct Box {
  Vec3 lo{kInfinity};
  Vec3 hi{-kInfinity};
  void grow(const Vec3& l, const Vec3& h) {
    lo = glm::min(lo, l);
    hi = glm::max(hi, h);
  }
  void grow(const Box& b) { grow(b.lo, b.hi); }
  float half_area() const {
    const Vec3 d = hi - lo;
    if (!(d.x >= 0.0f && d.y >= 0.0f && d.z >= 0.0f)) return 0.0f;
    return d.x * d.y + d.y * d.z + d.z * d.x;
  }
};

struct Range {
  uint32_t begin = 0, end = 0;
  Box box;
  bool leaf_ok = false;
  uint32_t count() const { return end - begin; }
};

struct Bin {
  Box box;
  uint32_t count = 0;
};

class Builder {
 public:
  Builder(std::vector<PrimRef>& refs, uint32_t num_triangles, uint32_t first_patch,
          const AccelConfig& config)
      : refs_(refs),
        num_triangles_(num_triangles),
        first_patch_(first_patch),
        max_leaf_(std::clamp(config.max_leaf_size, 1, kMaxLeafSize)),
        bins_(std::clamp(config.sah_bins, 2, kMaxBins)) {}

  Range make_range(uint32_t begin, uint32_t end, const Box& box) const {
    Range r{begin, end, box, false};
    r.leaf_ok = r.count() <= uint32_t(max_leaf_) && homogeneous(begin, end);
    return r;
  }

  int kind(uint32_t i) const { return prim_kind(refs_[i].id, num_triangles_, first_patch_); }

  bool homogeneous(uint32_t begin, uint32_t end) const {
    for (uint32_t i = begin + 1; i < end; ++i)
      if (kind(i) != kind(begin)) return false;
    return true;
  }

  // Splits a node's range into at most eight children: the largest child that cannot be a
  // leaf is split first; free slots then go to splitting leaves (box tests are cheaper than
  // primitive tests, and the node exists anyway).
  int collect_children(const Range& r, int level, Range* ch) {
    int n = 1;
    ch[0] = r;
    while (n < kBvhWidth) {
      int best = -1;
      float best_area = -1.0f;
      for (int pass = 0; pass < 2 && best < 0; ++pass)
        for (int i = 0; i < n; ++i) {
          const bool want = pass == 0 ? !ch[i].leaf_ok : ch[i].count() > 1;
          if (want && ch[i].box.half_area() > best_area)
            best = i, best_area = ch[i].box.half_area();
        }
      if (best < 0) break;
      Range left, right;
      split(ch[best], level, left, right);
      ch[best] = left;
      ch[n++] = right;
    }
    return n;
  }

  // Builds the subtree of r (not a leaf) into nodes_; returns its node index.
  uint32_t build(const Range& r, int level) {
    const uint32_t index = uint32_t(nodes.size());
    nodes.emplace_back();
    clear_node(nodes[index]);
    depth = std::max(depth, level);
    Range ch[kBvhWidth];
    const int n = collect_children(r, level, ch);
    for (int i = 0; i < n; ++i) {
      set_child_box(nodes[index], i, ch[i].box);
      if (ch[i].leaf_ok) {
        nodes[index].child[i] = ch[i].begin;
        nodes[index].info[i] =
            uint8_t(ch[i].count() | leaf_kind_bits(kind(ch[i].begin)));
        ++leaves;
      } else {
        const uint32_t c = build(ch[i], level + 1);  // may reallocate nodes
        nodes[index].child[i] = c;
      }
    }
    return index;
  }

  static void set_child_box(Bvh8Node& node, int i, const Box& b) {
    for (int a = 0; a < 3; ++a) {
      node.bounds[2 * a][i] = b.lo[a];
      node.bounds[2 * a + 1][i] = b.hi[a];
    }
  }

  std::vector<Bvh8Node> nodes;
  int depth = 0;
  size_t leaves = 0;

 private:
  Box bounds_of(uint32_t begin, uint32_t end) const {
    Box b;
    for (uint32_t i = begin; i < end; ++i) b.grow(refs_[i].lo, refs_[i].hi);
    return b;
  }

  void finish(const Range& r, uint32_t mid, Range& left, Range& right) const {
    left = make_range(r.begin, mid, bounds_of(r.begin, mid));
    right = make_range(mid, r.end, bounds_of(mid, r.end));
  }

  // Splits r (at least two primitives) into two non-empty ranges.
  void split(const Range& r, int level, Range& left, Range& right) {
    const auto first = refs_.begin() + r.begin, last = refs_.begin() + r.end;
    const uint32_t n = r.count();
    if (n <= uint32_t(max_leaf_) && !homogeneous(r.begin, r.end)) {
      // Mixed small set: the first one's kind first, so each leaf ends up with one kind.
      const int k0 = kind(r.begin);
      const auto it = std::stable_partition(first, last, [&](const PrimRef& p) {
        return prim_kind(p.id, num_triangles_, first_patch_) == k0;
      });
      return finish(r, uint32_t(it - refs_.begin()), left, right);
    }
    Box cb;  // bounds of the doubled centroids lo + hi
    for (auto it = first; it != last; ++it) cb.grow(it->lo + it->hi, it->lo + it->hi);
    const Vec3 extent = cb.hi - cb.lo;
    int axis =
        extent.x >= extent.y ? (extent.x >= extent.z ? 0 : 2) : (extent.y >= extent.z ? 1 : 2);
    const uint32_t mid = r.begin + n / 2;
    if (!(extent[axis] > 0.0f) || !std::isfinite(extent[axis])) {
      return finish(r, mid, left, right);  // all centroids equal: any split is as good
    }
    if (level > kSahDepthLimit) {
      std::nth_element(first, first + n / 2, last, [axis](const PrimRef& a, const PrimRef& b) {
        return a.lo[axis] + a.hi[axis] < b.lo[axis] + b.hi[axis];
      });
      return finish(r, mid, left, right);
    }
    const int k_bins = bins_;
    Bin bins[3][kMaxBins];
    float scale[3];
    for (int a = 0; a < 3; ++a)
      scale[a] = extent[a] > 0.0f ? float(k_bins) * 0.99999f / extent[a] : 0.0f;
    auto bin_of = [&](const PrimRef& p, int a) {
      const float k = (p.lo[a] + p.hi[a] - cb.lo[a]) * scale[a];
      // NaN-safe clamp (a NaN centroid lands in bin 0).
      return k >= 0.0f ? (k < float(k_bins) ? int(k) : k_bins - 1) : 0;
    };
    for (auto it = first; it != last; ++it)
      for (int a = 0; a < 3; ++a) {
        Bin& b = bins[a][bin_of(*it, a)];
        b.box.grow(it->lo, it->hi);
        ++b.count;
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
        acc.grow(bins[a][k].box);
        cnt += bins[a][k].count;
        right_cost[k] = cnt ? acc.half_area() * float(cnt) : kInfinity;
        right_box[k] = acc;
      }
      acc = Box();
      cnt = 0;
      for (int k = 1; k < k_bins; ++k) {
        acc.grow(bins[a][k - 1].box);
        cnt += bins[a][k - 1].count;
        if (cnt == 0 || cnt == n) continue;
        const float cost = acc.half_area() * float(cnt) + right_cost[k];
        if (cost < best_cost) {
          best_cost = cost, best_axis = a, best_k = k;
          best_left = acc, best_right = right_box[k];
        }
      }
    }
    if (best_axis < 0) {
      std::nth_element(first, first + n / 2, last, [axis](const PrimRef& a, const PrimRef& b) {
        return a.lo[axis] + a.hi[axis] < b.lo[axis] + b.hi[axis];
      });
      return finish(r, mid, left, right);
    }
    const auto it = std::partition(first, last,
                                   [&](const PrimRef& p) { return bin_of(p, best_axis) < best_k; });
    const uint32_t m = uint32_t(it - refs_.begin());
    left = make_range(r.begin, m, best_left);
    right = make_range(m, r.end, best_right);
  }

  std::vector<PrimRef>& refs_;
  uint32_t num_triangles_;
  uint32_t first_patch_;
  int max_leaf_;
  int bins_;
};

}  // namespace

Bvh8 build_bvh8(std::vector<PrimRef>& refs, uint32_t num_triangles, const AccelConfig& config,
                uint32_t first_patch) {
  Bvh8 out;
  if (refs.empty()) return out;
  Builder root(refs, num_triangles, first_patch, config);
  Box all;
  for (const PrimRef& p : refs) all.grow(p.lo, p.hi);
  root.nodes.emplace_back();
  clear_node(root.nodes[0]);
  Range ch[kBvhWidth];
  const int n = root.collect_children(root.make_range(0, uint32_t(refs.size()), all), 1, ch);

  // Subtrees below the root are independent (disjoint ranges of refs): build each into its own
  // node array, possibly in parallel, then append them in slot order (deterministic layout).
  std::vector<int> inner;
  for (int i = 0; i < n; ++i) {
    Builder::set_child_box(root.nodes[0], i, ch[i].box);
    if (ch[i].leaf_ok) {
      root.nodes[0].child[i] = ch[i].begin;
      root.nodes[0].info[i] =
          uint8_t(ch[i].count() | leaf_kind_bits(root.kind(ch[i].begin)));
      ++root.leaves;
    } else {
      inner.push_back(i);
    }
  }
  std::vector<Builder> subs(inner.size(), Builder(refs, num_triangles, first_patch, config));
  auto build_one = [&](size_t k) { subs[k].build(ch[inner[k]], 2); };
  if (config.parallel_for && refs.size() > 65536) {
    config.parallel_for(inner.size(), build_one);
  } else {
    for (size_t k = 0; k < inner.size(); ++k) build_one(k);
  }
  size_t total = 1;
  for (const Builder& s : subs) total += s.nodes.size();
  out.nodes.reserve(total);
  out.nodes.push_back(root.nodes[0]);
  out.depth = 1;
  out.leaves = root.leaves;
  for (size_t k = 0; k < subs.size(); ++k) {
    const uint32_t offset = uint32_t(out.nodes.size());
    out.nodes[0].child[inner[k]] = offset;
    for (Bvh8Node node : subs[k].nodes) {
      for (int i = 0; i < kBvhWidth; ++i)
        if (node.info[i] == 0) node.child[i] += offset;
      out.nodes.push_back(node);
    }
    out.depth = std::max(out.depth, subs[k].depth);
    out.leaves += subs[k].leaves;
    std::vector<Bvh8Node>().swap(subs[k].nodes);
  }

  // Leaves point into refs; remap to the index within their kind's permuted array.
  std::vector<uint32_t> rank(refs.size());
  uint32_t next[3] = {0, 0, 0};
  for (size_t i = 0; i < refs.size(); ++i) rank[i] = next[prim_kind(refs[i].id, num_triangles, first_patch)]++;
  for (Bvh8Node& node : out.nodes)
    for (int i = 0; i < kBvhWidth; ++i)
      if (node.info[i] != 0) node.child[i] = rank[node.child[i]];
  return out;
}

}  // namespace frameless
