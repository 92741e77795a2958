#include "core/accel/triangle_block.h"

#include <algorithm>
#include <cstdlib>
#include <functional>
#include <limits>

#include "core/base/huge_pages.h"

namespace frameless {

bool triangle_lanes_wanted() {
  static const bool wanted = [] {
    const char* e = std::getenv("FRAMELESS_TRIANGLE_BLOCKS");
    return !(e && e[0] == '0' && e[1] == 0);
  }();
  return wanted;
}

// In passes over chunks of nodes, each through the caller's executor, with the numbers of the
// serial walk (blocks by parent, the root's first): it took 0.9 s of an 11 M-triangle build on
// any number of threads, reading every parent's children at random from the four-line nodes.
std::vector<TriangleBlock> lay_out_triangle_blocks(std::vector<Bvh8Node>& nodes, const std::vector<LeafTriangle>& leaf_tris,
                                                   const AccelConfig& config, size_t chunk) {
  std::vector<TriangleBlock> blocks;
#if defined(__AVX2__)
  if (!triangle_lanes_wanted()) return blocks;
  const size_t n = nodes.size(), per = std::max<size_t>(chunk, 1);
  const size_t chunks = (n + per - 1) / per;
  const auto each_chunk = [&](const std::function<void(size_t, size_t, size_t)>& body) {
    parallel_for_each(config.parallel_for, chunks,
                      [&](size_t c) { body(c, c * per, std::min(n, (c + 1) * per)); });
  };
  // Each node's single-triangle slots, kept apart (a byte a node) for the parents' reads below.
  std::vector<uint8_t> singles(n), blocked(n);
  each_chunk([&](size_t, size_t begin, size_t end) {
    for (size_t k = begin; k < end; ++k) {
      const Bvh8Node& nd = nodes[k];
      uint32_t m = 0;
      for (int i = 0; i < kBvhWidth; ++i)
        if (nd.info[i] == 1 && nd.child[i] < leaf_tris.size()) m |= 1u << i;  // one plain triangle
      singles[k] = uint8_t(__builtin_popcount(m) >= kMinBlockSingles ? m : 0u);
    }
  });
  // Each node's children with a block, and how many blocks each chunk's children take.
  std::vector<uint32_t> first(chunks);
  each_chunk([&](size_t c, size_t begin, size_t end) {
    uint32_t taken = 0;
    for (size_t k = begin; k < end; ++k) {
      const Bvh8Node& nd = nodes[k];
      uint32_t m = 0;
      for (int i = 0; i < kBvhWidth; ++i) {
        const bool node_child = nd.info[i] == 0 && nd.bounds[0][i] <= nd.bounds[1][i] && nd.child[i] < n;
        if (node_child && singles[nd.child[i]]) m |= 1u << i;
      }
      blocked[k] = uint8_t(m);
      taken += uint32_t(__builtin_popcount(m));
    }
    first[c] = taken;
  });
  // Blocks are numbered by parent, its children's consecutively (the root's first), so a parent
  // finds each child's block without reading the child.
  uint32_t count = n && singles[0] ? 1u : 0u;
  for (uint32_t& f : first) {
    const uint32_t taken = f;
    f = count;
    count += taken;
  }
  if (n && singles[0]) nodes[0].block = 0;
  // A node's own fields and its blocked children's numbers (each node is one parent's child: no
  // two chunks write one field).
  each_chunk([&](size_t c, size_t begin, size_t end) {
    uint32_t next = first[c];
    for (size_t k = begin; k < end; ++k) {
      Bvh8Node& nd = nodes[k];
      nd.singles = singles[k];
      nd.blocked = blocked[k];
      nd.child_blocks = next;
      for (uint32_t m = blocked[k]; m; m &= m - 1) nodes[nd.child[__builtin_ctz(m)]].block = next++;
    }
  });
  resize_huge(blocks, count);  // not zeroed (TriangleBlock's constructor): first written below, in parallel
  const float nan = std::numeric_limits<float>::quiet_NaN();
  each_chunk([&](size_t, size_t begin, size_t end) {
    for (size_t k = begin; k < end; ++k) {
      const Bvh8Node& nd = nodes[k];
      if (!nd.singles) continue;
      TriangleBlock& b = blocks[nd.block];
      std::fill(&b.v[0][0], &b.v[0][0] + 9 * kBvhWidth, nan);
      for (uint32_t m = nd.singles; m; m &= m - 1) {
        const int i = __builtin_ctz(m);
        const LeafTriangle& t = leaf_tris[nd.child[i]];
        for (int row = 0; row < 9; ++row) b.v[row][i] = t.p[row / 3][row % 3];
      }
    }
  });
#else
  (void)nodes, (void)leaf_tris, (void)config, (void)chunk;
#endif
  return blocks;
}

}  // namespace frameless
