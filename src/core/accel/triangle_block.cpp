#include "core/accel/triangle_block.h"

#include <algorithm>
#include <cstdlib>
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

std::vector<TriangleBlock> lay_out_triangle_blocks(std::vector<Bvh8Node>& nodes, const std::vector<LeafTriangle>& leaf_tris,
                                                   const AccelConfig& config) {
  std::vector<TriangleBlock> blocks;
#if defined(__AVX2__)
  if (!triangle_lanes_wanted()) return blocks;
  const auto singles_of = [&](const Bvh8Node& n) {
    uint32_t m = 0;
    for (int i = 0; i < kBvhWidth; ++i)
      if (n.info[i] == 1 && n.child[i] < leaf_tris.size()) m |= 1u << i;  // one plain triangle
    return __builtin_popcount(m) >= kMinBlockSingles ? m : 0u;
  };
  for (Bvh8Node& n : nodes) n.singles = uint8_t(singles_of(n));
  // Blocks are numbered by parent, its children's consecutively (the root's first), so a parent
  // finds each child's block without reading the child.
  uint32_t count = 0;
  if (!nodes.empty() && nodes[0].singles) nodes[0].block = count++;
  for (Bvh8Node& n : nodes) {
    n.child_blocks = count;
    for (int i = 0; i < kBvhWidth; ++i) {
      const bool node_child = n.info[i] == 0 && n.bounds[0][i] <= n.bounds[1][i] && n.child[i] < nodes.size();
      if (node_child && nodes[n.child[i]].singles) {
        nodes[n.child[i]].block = count++;
        n.blocked |= uint8_t(1u << i);
      }
    }
  }
  resize_huge(blocks, count);
  const float nan = std::numeric_limits<float>::quiet_NaN();
  constexpr size_t kChunk = 1 << 14;
  parallel_for_each(config.parallel_for, (nodes.size() + kChunk - 1) / kChunk, [&](size_t c) {
    for (size_t k = c * kChunk; k < std::min(nodes.size(), (c + 1) * kChunk); ++k) {
      const Bvh8Node& n = nodes[k];
      if (!n.singles) continue;
      TriangleBlock& b = blocks[n.block];
      std::fill(&b.v[0][0], &b.v[0][0] + 9 * kBvhWidth, nan);
      for (uint32_t m = n.singles; m; m &= m - 1) {
        const int i = __builtin_ctz(m);
        const LeafTriangle& t = leaf_tris[n.child[i]];
        for (int row = 0; row < 9; ++row) b.v[row][i] = t.p[row / 3][row % 3];
      }
    }
  });
#else
  (void)nodes, (void)leaf_tris, (void)config;
#endif
  return blocks;
}

}  // namespace frameless
