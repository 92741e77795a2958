// Binned-SAH builder of the 8-wide BVH over primitive bounds; runs on the loading thread
// (optionally fanning subtrees out through AccelConfig::parallel_for).
#pragma once
#include <cstdint>
#include <vector>

#include "core/accel.h"
#include "core/bvh_node.h"

namespace frameless {

// Bounds of one primitive; id < num_triangles is a triangle, otherwise a sphere.
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
// permuted triangle array, likewise the spheres, and leaf child indices point into those arrays.
// Every leaf holds primitives of one kind only.
Bvh8 build_bvh8(std::vector<PrimRef>& refs, uint32_t num_triangles, const AccelConfig& config);

}  // namespace frameless
