// In-place binned-SAH builder of the 8-wide BVH over spheres (bvh_build_spheres.h). The splits
// are build_bvh8's (bvh_build_split.h); what differs is memory: no PrimRef array (bounds are
// recomputed from the sphere), the sphere and material arrays are partitioned together in place,
// and nodes go to 4 MiB blocks, mapped on demand and freed as the final array is assembled.
// This file: the node blocks, the top of the tree and its subtree tasks, and the assembly; the
// sphere array as the splitter sees it is in bvh_build_spheres_internal.h.
#include "core/accel/bvh_build_spheres.h"

#include <algorithm>
#include <memory>
#include <new>
#include <vector>

#if defined(__unix__) || defined(__APPLE__)
#include <sys/mman.h>
#define FRAMELESS_NODE_MMAP 1
#endif

#include "core/accel/bvh_build_spheres_internal.h"
#include "core/base/huge_pages.h"

namespace frameless {
namespace sphere_bvh {

// Node storage of one subtree: fixed blocks that never move (references stay valid while
// children are added), mapped on demand so untouched pages are never resident, and unmapped as
// soon as they have been copied out.
class NodeArena {
 public:
  static constexpr size_t kBlockNodes = 16384;  // 4 MiB
  NodeArena() = default;
  NodeArena(const NodeArena&) = delete;
  NodeArena& operator=(const NodeArena&) = delete;
  ~NodeArena() {
    for (Bvh8Node* b : blocks_) free_block(b);
  }

  uint32_t add() {
    if (size_ == blocks_.size() * kBlockNodes) blocks_.push_back(new_block());
    const uint32_t i = uint32_t(size_++);
    clear_node(at(i));
    return i;
  }
  Bvh8Node& at(uint32_t i) { return blocks_[i / kBlockNodes][i % kBlockNodes]; }
  size_t size() const { return size_; }

  // Appends the nodes to out with `offset` added to their inner-node references, releasing each
  // block once copied.
  void drain_into(std::vector<Bvh8Node>& out, uint32_t offset) {
    for (size_t b = 0; b < blocks_.size(); ++b) {
      const size_t n = std::min(kBlockNodes, size_ - b * kBlockNodes);
      for (size_t i = 0; i < n; ++i) {
        Bvh8Node node = blocks_[b][i];
        for (int c = 0; c < kBvhWidth; ++c)
          if (node.info[c] == 0 && node.bounds[0][c] <= node.bounds[1][c]) node.child[c] += offset;
        out.push_back(node);
      }
      free_block(blocks_[b]);
      blocks_[b] = nullptr;
    }
    blocks_.clear();
    size_ = 0;
  }

 private:
  static Bvh8Node* new_block() {
#if defined(FRAMELESS_NODE_MMAP)
    void* p = mmap(nullptr, kBlockNodes * sizeof(Bvh8Node), PROT_READ | PROT_WRITE,
                   MAP_PRIVATE | MAP_ANONYMOUS, -1, 0);
    if (p == MAP_FAILED) throw std::bad_alloc();
    return static_cast<Bvh8Node*>(p);
#else
    return static_cast<Bvh8Node*>(::operator new(kBlockNodes * sizeof(Bvh8Node),
                                                 std::align_val_t(alignof(Bvh8Node))));
#endif
  }
  static void free_block(Bvh8Node* b) {
    if (!b) return;
#if defined(FRAMELESS_NODE_MMAP)
    munmap(b, kBlockNodes * sizeof(Bvh8Node));
#else
    ::operator delete(b, std::align_val_t(alignof(Bvh8Node)));
#endif
  }

  std::vector<Bvh8Node*> blocks_;
  size_t size_ = 0;
};

namespace {

// Builds subtrees into node arenas.
template <class Prims>
class Builder {
 public:
  Builder(const Prims& p, const SplitSettings& s) : split_(p, s, nullptr) {}

  // Builds the subtree of r (not a leaf) into arena; returns its node index there.
  uint32_t build(NodeArena& arena, const Range& r, int level) {
    const uint32_t index = arena.add();
    depth = std::max(depth, level);
    Range ch[kBvhWidth];
    const int n = split_.collect_children(r, level, ch);
    for (int i = 0; i < n; ++i) {
      set_child_box(arena.at(index), i, ch[i].box);
      if (ch[i].leaf_ok) {
        arena.at(index).child[i] = ch[i].begin;
        arena.at(index).info[i] = uint8_t(ch[i].count() | kSphereLeafBit);
        ++leaves;
      } else {
        const uint32_t c = build(arena, ch[i], level + 1);
        arena.at(index).child[i] = c;
      }
    }
    return index;
  }

  int depth = 0;
  size_t leaves = 0;

 private:
  Splitter<Prims> split_;
};

// A subtree below the top of the tree, built into its own arena.
struct Task {
  Range range;
  int level = 0;
  uint32_t parent = 0;  // top node and slot that refer to it
  int slot = 0;
  NodeArena arena;
  int depth = 0;
  size_t leaves = 0;
};

// The top of the tree: nodes whose ranges are larger than max_task, built breadth-first. A wave
// of one node (the root) splits with chunked parallel binning; a wave of several splits its
// nodes in parallel. Inner children of at most max_task spheres become tasks. Node order (breadth
// first, slots in order) does not depend on the executor.
template <class Prims>
struct Top {
  const Prims& prims;
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
        Splitter<Prims> split(prims, settings, p);
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
            nodes[index].info[i] = uint8_t(c.count() | kSphereLeafBit);
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

template <class Prims>
Bvh8 build(const Prims& prims, uint32_t n, const AccelConfig& config) {
  Bvh8 out;
  // The split into top and tasks depends on n only, so the layout is the same with or without
  // an executor (and whatever order it runs things in).
  const bool big = n > kParallelMin;
  const bool parallel = bool(config.parallel_for) && big;
  const ParallelFor* pf = parallel ? &config.parallel_for : nullptr;
  const SplitSettings settings = split_settings(config, n, kSphereNodeCost);
  Top<Prims> top{prims, settings, pf, big ? std::max(kMinTask, n / 128) : 0xffffffffu, {}, {}, 0, 0};
  top.build(Splitter<Prims>(prims, settings, pf).make_range(0, n));

  // Subtrees: largest first (better balance on a dynamic executor), each into its own arena.
  std::vector<size_t> order(top.tasks.size());
  for (size_t k = 0; k < order.size(); ++k) order[k] = k;
  std::stable_sort(order.begin(), order.end(), [&](size_t a, size_t b) {
    return top.tasks[a]->range.count() > top.tasks[b]->range.count();
  });
  auto build_one = [&](size_t k) {
    Task& t = *top.tasks[order[k]];
    Builder<Prims> b(prims, settings);
    b.build(t.arena, t.range, t.level);
    t.depth = b.depth;
    t.leaves = b.leaves;
  };
  if (parallel && top.tasks.size() > 1) {
    config.parallel_for(top.tasks.size(), build_one);
  } else {
    for (size_t k = 0; k < top.tasks.size(); ++k) build_one(k);
  }

  // Assemble: the top nodes (root first), then each task's nodes in task order. The result is
  // reserved exactly and each arena block is released as soon as it is copied.
  size_t total = top.nodes.size();
  for (const auto& t : top.tasks) total += t->arena.size();
  reserve_huge(out.nodes, total);
  out.depth = top.depth;
  out.leaves = top.leaves;
  size_t offset = top.nodes.size();
  for (const auto& t : top.tasks) {
    top.nodes[t->parent].child[t->slot] = uint32_t(offset);
    offset += t->arena.size();
  }
  out.nodes.insert(out.nodes.end(), top.nodes.begin(), top.nodes.end());
  std::vector<Bvh8Node>().swap(top.nodes);
  for (const auto& t : top.tasks) {
    t->arena.drain_into(out.nodes, uint32_t(out.nodes.size()));
    out.depth = std::max(out.depth, t->depth);
    out.leaves += t->leaves;
  }
  return out;
}

}  // namespace
}  // namespace sphere_bvh

Bvh8 build_bvh8_spheres(std::vector<Sphere>& spheres, std::vector<uint16_t>& materials,
                        const AccelConfig& config) {
  using namespace sphere_bvh;
  if (spheres.empty()) return {};
  const uint32_t n = uint32_t(spheres.size());
  // A material array of another size is malformed: leave it alone (as Accel::build does).
  uint16_t* mats = materials.size() == spheres.size() ? materials.data() : nullptr;
  // Bounds that are all finite need no check per use (the same bounds either way).
  bool finite = true;
  if (config.parallel_for && n > kParallelMin) {
    const size_t chunks = (n + kBinChunk - 1) / kBinChunk;
    std::vector<uint8_t> part(chunks);
    config.parallel_for(chunks, [&](size_t c) {
      const uint32_t b = uint32_t(c) * kBinChunk;
      part[c] = finite_boxes(spheres.data(), b, std::min(n, b + kBinChunk));
    });
    for (uint8_t f : part) finite = finite && f;
  } else {
    finite = finite_boxes(spheres.data(), 0, n);
  }
  if (finite) return build(SpherePrims<false>{spheres.data(), mats}, n, config);
  return build(SpherePrims<true>{spheres.data(), mats}, n, config);
}

}  // namespace frameless
