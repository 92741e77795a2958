// OpenVDB volumes (.vdb; issue 27): a strict reader of our own for the grids scientists and
// film pipelines write, so that a broken file gets one line, never a crash (fuzzed).
//
// Read: file versions 222 and later (OpenVDB 3 to 12); float and double grids of the standard
// 5-4-3 tree, saved at full precision or as half floats; raw, zlib and Blosc compression, with or
// without active-mask compression; linear maps (uniform scale, scale, translation, their
// combinations, affine, unitary). Refused with a reason: other value types (vectors, integers,
// points), instanced grids, frustum maps, files without grid offsets. The grid keeps its
// sparsity: it becomes a bricked grid (core/volume/sparse_volume.h) whose bricks are the leaves.
// Errors: "FILE: what is wrong (byte N)".
#pragma once
#include <string>

#include "core/base/error.h"
#include "core/geometry/geometry.h"
#include "core/volume/sparse_volume.h"

namespace frameless {

struct VdbVolume {
  BrickedGrid bricked;
  std::string name;        // the grid's name in the file
  std::string grid_class;  // "level set", "fog volume" or "unknown" (OpenVDB's class metadata)
  Affine index_to_world;   // the grid's map: OpenVDB index space -> its world space
  size_t leaves = 0, tiles = 0;
  // Grid index (x, y, z) -> OpenVDB's world: index_to_world of origin + (x, y, z).
  Affine grid_to_world() const;
};

// The grid named `grid` ("" = the first float or double grid).
Result<VdbVolume> read_vdb(const std::string& path, const std::string& grid);

// The same for a file's bytes in memory (the fuzzer, tests); `path` names it in errors. A grid
// whose bricks would take more than `max_brick_bytes` is refused (brick_sparse_volume).
Result<VdbVolume> decode_vdb(const uint8_t* data, size_t size, const std::string& path,
                             const std::string& grid, uint64_t max_brick_bytes = kMaxBrickBytes);

}  // namespace frameless
