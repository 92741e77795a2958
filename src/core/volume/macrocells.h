// Parker et al.'s macrocells (Visualization '98): the value range of each block of M x M x M
// cells, so that rays skip blocks that cannot hold the isovalue (or, for the volume shader, whose
// values are all transparent). One level over the cells: a 512 x 512 x 1734 grid has 64 x 64 x
// 217 of them at M = 8, few enough that a ray's walk over them costs little beside its cells.
#pragma once
#include <vector>

#include "core/base/parallel_for.h"
#include "core/volume/volume_grid.h"

namespace frameless {

struct Macrocells {
  int size = 8;            // cells per macrocell side, a power of two
  int mx = 0, my = 0, mz = 0;
  std::vector<float> lo, hi;  // per macrocell: the smallest and largest voxel of its cells' corners
  size_t index(int x, int y, int z) const { return (size_t(z) * size_t(my) + size_t(y)) * size_t(mx) + size_t(x); }
};

// The range of every macrocell (cells [a M, a M + M) along x hold the voxels [a M, a M + M]),
// a z-slab of them per task of the caller's executor (empty: serial).
Macrocells build_macrocells(const VolumeGrid& grid, int size = 8, const ParallelFor& pf = {});

}  // namespace frameless
