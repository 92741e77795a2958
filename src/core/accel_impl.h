// Accel's internal state, shared by accel.cpp (BVH build and traversal) and accel_choice.cpp
// (structure choice, grid dispatch); not a public interface.
#pragma once
#include <memory>
#include <vector>

#include "core/accel.h"
#include "core/bvh_node.h"
#include "core/grid_accel.h"

namespace frameless {

struct Accel::Impl {
  const Geometry* geom = nullptr;
  std::vector<Bvh8Node> nodes;     // the BVH (empty when the grid is in use)
  std::unique_ptr<GridAccel> grid;  // the hybrid grid, when chosen
  AccelStats stats;
  AlphaTest alpha;  // opaque == nullptr: no cut-out surfaces
};

}  // namespace frameless
