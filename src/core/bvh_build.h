// Binned-SAH builder of the 8-wide BVH over primitive bounds; runs on the loading thread
// (optionally fanning subtrees out through AccelConfig::parallel_for).
#pragma once
#include <cstdint>
#include <vector>

#include "core/accel.h"
#include "core/bvh_node.h"

namespace frameless {

// Bounds of one primitive; id < num_triangles is a triangle, then spheres up to first_patch,
// then spline patches.
struct PrimRef {
  Vec3 lo{0.0f};
  uint32_t id = 0;
  Vec3 hi{0.0f};
  uint32_t pad = 0;
};

struct Bvh8 {
  std::vector<Bvh8Node> nodes;  // nodes[0] is the root (absent when there are no primitives)
  int depth = 0;                // node levels, root = 1
  size_t leaves = 0;
};

// Builds over refs and leaves refs in leaf order: the triangles of refs (in order) are the
// permuted triangle array, likewise the spheres and patches, and leaf child indices point into
// those arrays. Every leaf holds primitives of one kind only. first_patch defaults to "none".
Bvh8 build_bvh8(std::vector<PrimRef>& refs, uint32_t num_triangles, const AccelConfig& config,
                uint32_t first_patch = 0xffffffffu);

// Kind of primitive id: 0 triangle, 1 sphere, 2 patch.
inline int prim_kind(uint32_t id, uint32_t num_triangles, uint32_t first_patch) {
  return id < num_triangles ? 0 : id < first_patch ? 1 : 2;
}
inline uint8_t leaf_kind_bits(int kind) {
  return kind == 0 ? uint8_t(0) : kind == 1 ? kSphereLeafBit : kPatchLeafBit;
}

}  // namespace frameless
