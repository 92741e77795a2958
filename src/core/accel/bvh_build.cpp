// Binned-SAH builder of the 8-wide BVH over primitive references (top-down, Embree-style: each
// node splits its largest child until eight slots are filled; the splits are in
// bvh_build_split.h). Inputs of more than kParallelMin references are built as a breadth-first
// top of the tree (its big splits bin in parallel chunks, its waves of nodes split in parallel)
// plus independent subtree tasks, through the caller's parallel_for. Which ranges are tasks
// depends on sizes only and every step is deterministic, so the tree (and the reference order)
// is the same bytes whether built serially or in parallel, whatever the executor's order.
#include "core/accel/bvh_build.h"

#include <algorithm>
#include <functional>
#include <cmath>
#include <limits>
#include <memory>
#include <new>
#include <type_traits>
#include <utility>

#include "core/accel/bvh_build_split.h"
#include "core/base/huge_pages.h"

namespace frameless {
namespace {

using namespace bvh_split;

static_assert(sizeof(PrimRef) == 32, "PrimRef must be lo, id, hi, pad");

// The reference array as bvh_split::Splitter sees it.
struct RefPrims {
  PrimRef* r;
  uint32_t num_triangles;
  uint32_t first_patch;
  bool mixed;  // more than one kind of primitive: leaves must be checked for one kind
  static constexpr bool kMayMix = true;

  int kind(uint32_t i) const { return prim_kind(r[i].id, num_triangles, first_patch); }
  // The bounds with the w lanes (id, pad) zeroed.
  void box(uint32_t i, F4& lo, F4& hi) const {
    lo = xyz0(load4(&r[i].lo.x));
    hi = xyz0(load4(&r[i].hi.x));
  }
  void swap(uint32_t i, uint32_t j) const { std::swap(r[i], r[j]); }
  void reorder(uint32_t begin, uint32_t n, const uint8_t* order) const {
    PrimRef tmp[kSmallSplit];
    for (uint32_t i = 0; i < n; ++i) tmp[i] = r[begin + order[i]];
    std::copy(tmp, tmp + n, r + begin);
  }
  void select(uint32_t begin, uint32_t end, uint32_t k, int axis) const {
    std::nth_element(r + begin, r + k, r + end, [axis](const PrimRef& a, const PrimRef& b) {
      return a.lo[axis] + a.hi[axis] < b.lo[axis] + b.hi[axis];
    });
  }
  bool homogeneous(uint32_t begin, uint32_t end) const {
    if (!mixed) return true;
    for (uint32_t i = begin + 1; i < end; ++i)
      if (kind(i) != kind(begin)) return false;
    return true;
  }
  // Mixed small set: the first one's kind first, so each leaf ends up with one kind.
  uint32_t split_kinds(uint32_t begin, uint32_t end) const {
    const int k0 = kind(begin);
    const uint32_t nt = num_triangles, fp = first_patch;
    PrimRef* it = std::stable_partition(r + begin, r + end, [&](const PrimRef& p) {
      return prim_kind(p.id, nt, fp) == k0;
    });
    return uint32_t(it - r);
  }
};

using Split = Splitter<RefPrims>;

// Builds subtrees into node arrays.
class Builder {
 public:
  Builder(const RefPrims& p, const SplitSettings& s) : p_(p), split_(p, s, nullptr) {}

  // Builds the subtree of r (not a leaf) into nodes; returns its node index.
  uint32_t build(std::vector<Bvh8Node>& nodes, const Range& r, int level) {
    const uint32_t index = uint32_t(nodes.size());
    nodes.emplace_back();
    clear_node(nodes[index]);
    depth = std::max(depth, level);
    Range ch[kBvhWidth];
    const int n = split_.collect_children(r, level, ch);
    for (int i = 0; i < n; ++i) {
      set_child_box(nodes[index], i, ch[i].box);
      if (ch[i].leaf_ok) {
        nodes[index].child[i] = ch[i].begin;
        nodes[index].info[i] = uint8_t(ch[i].count() | leaf_kind_bits(p_.kind(ch[i].begin)));
        ++leaves;
      } else {
        const uint32_t c = build(nodes, ch[i], level + 1);  // may reallocate nodes
        nodes[index].child[i] = c;
      }
    }
    return index;
  }

  int depth = 0;
  size_t leaves = 0;

 private:
  RefPrims p_;
  Split split_;
};

// A subtree below the top of the tree, built into its own node array.
struct Task {
  Range range;
  int level = 0;
  uint32_t parent = 0;  // top node and slot that refer to it
  int slot = 0;
  std::vector<Bvh8Node> nodes;
  int depth = 0;
  size_t leaves = 0;
};

// The top of the tree: nodes whose ranges are larger than max_task, built breadth-first. A wave
// of one node (the root) splits with chunked parallel binning; a wave of several splits its
// nodes in parallel. Inner children of at most max_task references become tasks. Node order
// (breadth first, slots in order) does not depend on the executor.
struct Top {
  const RefPrims& prims;
  const SplitSettings& settings;
  const ParallelFor* pf;
  uint32_t max_task;
  std::vector<Bvh8Node> nodes;
  std::vector<std::unique_ptr<Task>> tasks;
  int depth = 0;
  size_t leaves = 0;

  struct Item {
    Range r;
    uint32_t parent = kInvalidId;  // node and slot that refer to it (none for the root)
    int slot = 0;
    Range ch[kBvhWidth];
    int n = 0;
  };

  void build(const Range& root) {
    std::vector<Item> wave(1);
    wave[0].r = root;
    for (int level = 1; !wave.empty(); ++level) {
      auto split_one = [&](size_t k, const ParallelFor* p) {
        Split split(prims, settings, p);
        wave[k].n = split.collect_children(wave[k].r, level, wave[k].ch);
      };
      if (wave.size() == 1 || !pf) {
        for (size_t k = 0; k < wave.size(); ++k) split_one(k, pf);
      } else {
        (*pf)(wave.size(), [&](size_t k) { split_one(k, nullptr); });
      }
      std::vector<Item> next;
      for (const Item& it : wave) {
        const uint32_t index = uint32_t(nodes.size());
        nodes.emplace_back();
        clear_node(nodes[index]);
        if (it.parent != kInvalidId) nodes[it.parent].child[it.slot] = index;
        depth = std::max(depth, level);
        for (int i = 0; i < it.n; ++i) {
          const Range& c = it.ch[i];
          set_child_box(nodes[index], i, c.box);
          if (c.leaf_ok) {
            nodes[index].child[i] = c.begin;
            nodes[index].info[i] = uint8_t(c.count() | leaf_kind_bits(prims.kind(c.begin)));
            ++leaves;
          } else if (c.count() <= max_task) {
            auto t = std::make_unique<Task>();
            t->range = c;
            t->level = level + 1;
            t->parent = index;
            t->slot = i;
            tasks.push_back(std::move(t));
          } else {
            next.emplace_back();
            next.back().r = c;
            next.back().parent = index;
            next.back().slot = i;
          }
        }
      }
      wave.swap(next);
    }
  }
};

}  // namespace

Bvh8 build_bvh8(std::vector<PrimRef>& refs, uint32_t num_triangles, const AccelConfig& config,
                uint32_t first_patch) {
  return build_bvh8(refs.data(), refs.size(), num_triangles, config, first_patch);
}

Bvh8 build_bvh8(PrimRef* refs, size_t count, uint32_t num_triangles, const AccelConfig& config,
                uint32_t first_patch) {
  Bvh8 out;
  if (count == 0) return out;
  const uint32_t n = uint32_t(count);
  // Which kinds are present (leaves must hold one kind; one kind needs no checks).
  uint32_t kinds = 0;
  for (uint32_t i = 0; i < n; ++i) kinds |= 1u << prim_kind(refs[i].id, num_triangles, first_patch);
  const RefPrims prims{refs, num_triangles, first_patch, (kinds & (kinds - 1)) != 0};
  const SplitSettings settings = split_settings(config, n, kTriangleNodeCost);
  // The split into top and tasks depends on n only, so the layout is the same with or without
  // an executor (and whatever order it runs things in).
  const bool big = n > kParallelMin;
  const bool parallel = bool(config.parallel_for) && big;
  const ParallelFor* pf = parallel ? &config.parallel_for : nullptr;
  const Range root = Split(prims, settings, pf).make_range(0, n);

  if (!big) {
    // One serial recursion, straight into the result.
    Builder b(prims, settings);
    out.nodes.reserve(n / 6 + 1);  // at most kParallelMin references: never huge
    b.build(out.nodes, root, 1);
    out.depth = b.depth;
    out.leaves = b.leaves;
  } else {
    Top top{prims, settings, pf, std::max(kMinTask, n / 128), {}, {}, 0, 0};
    top.build(root);

    out.depth = top.depth;
    out.leaves = top.leaves;
    if (!parallel) {
      // Serially the subtrees go straight after the top nodes, in task order: the layout the
      // parallel assembly below makes, without the copy.
      out.nodes = std::move(top.nodes);
      reserve_huge(out.nodes, n / 6 + 1);
      for (const auto& t : top.tasks) {
        out.nodes[t->parent].child[t->slot] = uint32_t(out.nodes.size());
        Builder b(prims, settings);
        b.build(out.nodes, t->range, t->level);
        out.depth = std::max(out.depth, b.depth);
        out.leaves += b.leaves;
      }
    } else {
      auto run = [&](size_t count, const std::function<void(size_t)>& body) {
        if (count > 1) {
          config.parallel_for(count, body);
        } else if (count == 1) {
          body(0);
        }
      };
      // Subtrees: largest first (better balance on a dynamic executor), each into its own
      // array, then appended in task order with their node indices offset.
      std::vector<size_t> order(top.tasks.size());
      for (size_t k = 0; k < order.size(); ++k) order[k] = k;
      std::stable_sort(order.begin(), order.end(), [&](size_t a, size_t b) {
        return top.tasks[a]->range.count() > top.tasks[b]->range.count();
      });
      run(top.tasks.size(), [&](size_t k) {
        Task& t = *top.tasks[order[k]];
        Builder b(prims, settings);
        t.nodes.reserve(t.range.count() / 6 + 1);
        b.build(t.nodes, t.range, t.level);
        t.depth = b.depth;
        t.leaves = b.leaves;
      });
      size_t total = top.nodes.size();
      std::vector<uint32_t> base(top.tasks.size());
      for (size_t k = 0; k < top.tasks.size(); ++k) {
        const Task& t = *top.tasks[k];
        top.nodes[t.parent].child[t.slot] = base[k] = uint32_t(total);
        total += t.nodes.size();
        out.depth = std::max(out.depth, t.depth);
        out.leaves += t.leaves;
      }
      resize_huge(out.nodes, total);
      std::copy(top.nodes.begin(), top.nodes.end(), out.nodes.begin());
      std::vector<Bvh8Node>().swap(top.nodes);
      run(top.tasks.size(), [&](size_t k) {
        Task& t = *top.tasks[k];
        Bvh8Node* dst = out.nodes.data() + base[k];
        for (const Bvh8Node& node : t.nodes) {
          *dst = node;
          for (int i = 0; i < kBvhWidth; ++i)
            if (node.info[i] == 0 && node.bounds[0][i] <= node.bounds[1][i])
              dst->child[i] += base[k];
          ++dst;
        }
        std::vector<Bvh8Node>().swap(t.nodes);
      });
    }
  }

  // Leaves point into refs; remap to the index within their kind's permuted array (the same
  // index when there is one kind).
  if (prims.mixed) {
    std::vector<uint32_t> rank(n);
    uint32_t next[3] = {0, 0, 0};
    for (uint32_t i = 0; i < n; ++i)
      rank[i] = next[prim_kind(refs[i].id, num_triangles, first_patch)]++;
    for (Bvh8Node& node : out.nodes)
      for (int i = 0; i < kBvhWidth; ++i)
        if (node.info[i] != 0) node.child[i] = rank[node.child[i]];
  }
  return out;
}

PrimRefArray::PrimRefArray(size_t n)
    : p_(n ? static_cast<PrimRef*>(::operator new(n * sizeof(PrimRef))) : nullptr), n_(n) {}

void PrimRefArray::Free::operator()(PrimRef* p) const {
  if (owns) ::operator delete(p);
}

namespace {

constexpr size_t kChunk = 16384;

// Runs body(begin, end) over [0, n): in chunks of kChunk through config.parallel_for when n is
// large and there is one, else once over everything.
void for_chunks(size_t n, const AccelConfig& config,
                const std::function<void(size_t, size_t)>& body) {
  const size_t chunks = (n + kChunk - 1) / kChunk;
  if (config.parallel_for && n > kParallelMin && chunks > 1) {
    config.parallel_for(chunks, [&](size_t c) { body(c * kChunk, std::min(n, (c + 1) * kChunk)); });
  } else if (n > 0) {
    body(0, n);
  }
}

// Whether all six bounds are finite (x - x is 0 exactly for finite x, NaN otherwise).
inline bool finite_bounds(const Vec3& lo, const Vec3& hi) {
  const Vec3 z = (lo - lo) + (hi - hi);
  return z.x == 0.0f && z.y == 0.0f && z.z == 0.0f;
}

}  // namespace

PrimRefArray make_prim_refs(const Geometry& g, const AccelConfig& config, PrimRef* into) {
  const uint32_t nt = g.num_triangles(), ns = g.num_spheres(), np = g.num_patches();
  const size_t n = size_t(nt) + ns + np;
  PrimRefArray refs = into ? PrimRefArray(into, n) : PrimRefArray(n);
  PrimRef* r = refs.data();
  const Vec3* pos = g.positions.data();
  const size_t num_pos = g.positions.size();
  for_chunks(n, config, [&](size_t begin, size_t end) {
    for (size_t i = begin; i < end; ++i) {
      Vec3 lo(0.0f), hi(0.0f);
      if (i < nt) {
        const UVec3 t = g.triangles[i];
        if (t.x < num_pos && t.y < num_pos && t.z < num_pos) {
          const Vec3 &a = pos[t.x], &b = pos[t.y], &c = pos[t.z];
          lo = glm::min(a, glm::min(b, c));
          hi = glm::max(a, glm::max(b, c));
        }
      } else if (i < size_t(nt) + ns) {
        const Sphere& s = g.spheres[i - nt];
        lo = s.center - Vec3(std::abs(s.radius));
        hi = s.center + Vec3(std::abs(s.radius));
      } else {
        const PatchSurface& p = g.patches[i - nt - ns];
        lo = p.lo();
        hi = p.hi();
      }
      if (!finite_bounds(lo, hi)) lo = hi = Vec3(0.0f);
      new (&r[i]) PrimRef{lo, uint32_t(i), hi, 0u};
    }
  });
  return refs;
}

void permute_geometry(Geometry& g, const PrimRef* refs, size_t n, const AccelConfig& config) {
  const uint32_t count[3] = {g.num_triangles(), g.num_spheres(), g.num_patches()};
  const uint32_t base[3] = {0, count[0], count[0] + count[1]};
  const uint32_t first_patch = base[2];
  // Where the references of each chunk go: their rank among those of their kind.
  const size_t chunks = (n + kChunk - 1) / kChunk;
  std::vector<uint32_t> offset(3 * std::max<size_t>(chunks, 1), 0);
  if (count[1] + count[2] > 0) {
    for_chunks(n, config, [&](size_t begin, size_t end) {
      uint32_t* o = &offset[3 * (begin / kChunk)];
      for (size_t i = begin; i < end; ++i) ++o[prim_kind(refs[i].id, count[0], first_patch)];
    });
    uint32_t next[3] = {0, 0, 0};
    for (size_t c = 0; c < chunks; ++c)
      for (int k = 0; k < 3; ++k) {
        const uint32_t here = offset[3 * c + k];
        offset[3 * c + k] = next[k];
        next[k] += here;
      }
  } else {
    for (size_t c = 0; c < chunks; ++c) offset[3 * c] = uint32_t(c * kChunk);
  }
  auto gather = [&](auto& v, int kind) {
    if (v.size() != count[kind] || v.empty()) return;  // absent optional array: leave alone
    std::remove_reference_t<decltype(v)> out;
    resize_huge(out, v.size());
    for_chunks(n, config, [&](size_t begin, size_t end) {
      uint32_t o = offset[3 * (begin / kChunk) + kind];
      for (size_t i = begin; i < end; ++i)
        if (prim_kind(refs[i].id, count[0], first_patch) == kind)
          out[o++] = v[refs[i].id - base[kind]];
    });
    v.swap(out);
  };
  gather(g.triangles, 0);
  gather(g.triangle_material, 0);
  gather(g.triangle_opposite, 0);
  gather(g.spheres, 1);
  gather(g.sphere_material, 1);
  gather(g.patch_material, 2);
  if (count[2] > 0) {  // few and heavy: moved one by one
    std::vector<PatchSurface> out;
    out.reserve(count[2]);
    for (size_t i = 0; i < n; ++i)
      if (refs[i].id >= first_patch) out.push_back(std::move(g.patches[refs[i].id - first_patch]));
    g.patches.swap(out);
  }
}

void lay_out_leaf_triangles(const Geometry& g, const AccelConfig& config, std::vector<LeafTriangle>& out) {
  const size_t n = g.num_triangles(), num_pos = g.positions.size();
  if (out.capacity() < n) std::vector<LeafTriangle>().swap(out);  // not two copies at the peak of a rebuild
  resize_huge(out, n);
  const Vec3 nan(std::numeric_limits<float>::quiet_NaN());
  for_chunks(n, config, [&](size_t begin, size_t end) {
    for (size_t i = begin; i < end; ++i) {
      const UVec3 t = g.triangles[i];
      const bool ok = t.x < num_pos && t.y < num_pos && t.z < num_pos;
      // Constructed anew: the storage may have held the build's references (Accel::build_bvh).
      new (&out[i]) LeafTriangle(ok ? LeafTriangle(g.positions[t.x], g.positions[t.y], g.positions[t.z])
                                    : LeafTriangle(nan, nan, nan));
    }
  });
}

}  // namespace frameless
