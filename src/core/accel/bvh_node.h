// Memory layout of the 8-wide BVH node shared by the builder and the traversal; any thread.
#pragma once
#include <cstdint>
#include <vector>

#include "core/base/types.h"

namespace frameless {

inline constexpr int kBvhWidth = 8;
// Bits of Bvh8Node::info marking a sphere or a spline-patch leaf; the low 6 bits hold the
// primitive count.
inline constexpr uint8_t kSphereLeafBit = 0x80;
inline constexpr uint8_t kPatchLeafBit = 0x40;
inline constexpr uint8_t kLeafCountMask = 0x3f;
inline constexpr int kMaxLeafSize = 63;

// Eight child boxes in SoA order for one AVX2 box test (one cache line per plane pair), then
// the child references. info[i] == 0: child[i] is a node index; otherwise child[i] is a leaf:
// the first of (info[i] & kLeafCountMask) consecutive triangles, or spheres when kSphereLeafBit
// is set, or patches when kPatchLeafBit is set.
// Unused slots hold an empty box (lo = +inf, hi = -inf), which no ray can enter.
struct alignas(64) Bvh8Node {
  float bounds[6][kBvhWidth];  // lo_x, hi_x, lo_y, hi_y, lo_z, hi_z
  uint32_t child[kBvhWidth];
  uint8_t info[kBvhWidth];
  // Slots whose single-triangle leaves are tested together from block `block` (triangle_block.h);
  // 0: none (every leaf is visited on its own).
  uint8_t singles;
  // Slots holding a node with a block: the k-th of them has block child_blocks + k, so a ray
  // entering the child asks for its block with its node (triangle_block.h).
  uint8_t blocked;
  uint8_t pad[14];
  uint32_t child_blocks;
  uint32_t block;
};
static_assert(sizeof(Bvh8Node) == 256, "Bvh8Node must stay four cache lines");

// A triangle's three vertices, kept by the BVH in leaf order: a leaf's triangles are one
// contiguous run, so a ray reaching a leaf waits for one fetch, not for the indices and then the
// vertices they name (two dependent misses on a big or scattered mesh).
struct LeafTriangle {
  // Left unwritten: a big mesh's are hundreds of megabytes, first written (and their pages first
  // touched) by lay_out_leaf_triangles' parallel chunks, not zeroed on one thread before them.
  LeafTriangle() {}
  LeafTriangle(const Vec3& a, const Vec3& b, const Vec3& c) : p{a, b, c} {}
  Vec3 p[3];
};
static_assert(sizeof(LeafTriangle) == 36);

inline void clear_node(Bvh8Node& n) {
  for (int i = 0; i < kBvhWidth; ++i) {
    for (int a = 0; a < 3; ++a) {
      n.bounds[2 * a][i] = kInfinity;
      n.bounds[2 * a + 1][i] = -kInfinity;
    }
    n.child[i] = 0;
    n.info[i] = 0;
  }
  n.singles = n.blocked = 0;
  n.child_blocks = n.block = 0;
  for (uint8_t& p : n.pad) p = 0;
}

}  // namespace frameless
