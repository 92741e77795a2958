// Sparse volumes as OpenVDB stores them (issue 27): leaves of 8^3 voxels and constant tiles of
// larger aligned cubes at integer index coordinates, the background everywhere else; and their
// bricked grid (volume_grid.h), which keeps the sparsity: only leaves near the data are stored.
#pragma once
#include <array>
#include <memory>
#include <string>
#include <vector>

#include "core/volume/volume_grid.h"

namespace frameless {

using Index3 = std::array<int, 3>;

struct SparseLeaf {
  Index3 origin{};  // a multiple of 8 per axis
  std::array<float, 512>
      v{};  // voxel origin + (i, j, k) at v[i * 64 + j * 8 + k] (z fastest, as OpenVDB)
};
struct SparseTile {
  Index3 origin{};  // a multiple of side per axis
  int side = 8;     // 8, 128 or 4096 voxels (OpenVDB's nodes of 5-4-3 trees)
  float value = 0.0f;
};
struct SparseVolume {
  float background = 0.0f;
  std::vector<SparseLeaf> leaves;
  std::vector<SparseTile> tiles;  // later tiles cover earlier ones; leaves cover tiles
};

struct BrickedGrid {
  std::shared_ptr<const VolumeGrid>
      grid;  // spacing 1: grid voxel (x, y, z) is index origin + (x, y, z)
  Index3 origin{};
};

// The grid over everything that is not the background (leaves, and tiles of other values), with
// one voxel of background around it so that surfaces close; its origin a multiple of 8, so that
// bricks are the leaves. Refuses non-finite voxels, empty volumes, bounds beyond the grid limits
// (volume_grid.h) and bricks that would take more than `max_bytes` with their table, naming `what`.
inline constexpr uint64_t kMaxBrickBytes = uint64_t(1) << 34;  // 16 GiB
Result<BrickedGrid> brick_sparse_volume(const SparseVolume& s, const std::string& what,
                                        uint64_t max_bytes = kMaxBrickBytes);

}  // namespace frameless
