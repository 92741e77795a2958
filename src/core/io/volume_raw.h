// Raw volume files (issue 27): headerless voxels whose sides, type and byte order the user states,
// the simplest way scanners and simulations hand over a grid.
#pragma once
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "core/base/error.h"
#include "core/base/types.h"
#include "core/volume/volume_grid.h"

namespace frameless {

struct RawVolumeSpec {
  int64_t nx = 0, ny = 0, nz = 0;
  VoxelType type = VoxelType::kUint8;
  bool big_endian = false;  // byte order of the file's 16/32-bit voxels
  Vec3 spacing{1.0f};
  uint64_t offset = 0;  // header bytes to skip
};

// A raw file of nx*ny*nz voxels (x fastest): its size must be exactly offset + voxels * bytes
// (one-line error otherwise, naming file, expected and actual sizes). When no byte swap is needed
// and the offset is a multiple of the voxel size (mapped voxels must be aligned for their type),
// the voxels are memory-mapped (map_file); otherwise they are read (and swapped where needed) into
// owned storage. The sides are checked with volume_size_problem before anything is allocated,
// opened or mapped.
Result<std::shared_ptr<const VolumeGrid>> read_raw_volume(const std::string& path, const RawVolumeSpec& spec);

// The same from bytes in memory (the fuzzer, tests): always owned storage. `path` names the
// source in errors.
Result<std::shared_ptr<const VolumeGrid>> decode_raw_volume(const std::string& bytes, const RawVolumeSpec& spec,
                                                            const std::string& path);

// Shared with the NRRD reader: whether voxels of `type` stored in the given byte order must be
// swapped on this machine, and the swap itself (in place, every voxel).
bool voxels_need_swap(VoxelType type, bool big_endian);
void swap_voxel_bytes(std::vector<uint8_t>& bytes, VoxelType type);

}  // namespace frameless
