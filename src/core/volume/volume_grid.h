// A volume of scalar samples on a regular grid (issue 27): voxels of 8-bit, 16-bit or 32-bit float
// data kept as stored (16-bit stays 16-bit), owned or memory-mapped from the file they came from.
// Voxel (i, j, k) sits at object-space point (i, j, k) * spacing; the (nx-1)(ny-1)(nz-1) cells
// between voxel centres hold the trilinear interpolant. Built on the loading thread, read-only
// while rendering (any thread).
#pragma once
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "core/base/error.h"
#include "core/base/types.h"

namespace frameless {

enum class VoxelType : uint8_t { kUint8, kUint16, kFloat32 };
size_t voxel_bytes(VoxelType type);
const char* voxel_type_name(VoxelType type);  // "uint8", "uint16", "float32"

// The bytes of a grid: x fastest, then y, then z, in this machine's byte order.
class VoxelStorage {
 public:
  virtual ~VoxelStorage() = default;
  virtual const uint8_t* data() const = 0;
  virtual size_t size() const = 0;
};
std::shared_ptr<const VoxelStorage> owned_storage(std::vector<uint8_t> bytes);
// `length` bytes of a file from `offset`, mapped read-only (pages load on first touch, so a
// volume of several GB costs address space, not memory, until rays reach it).
Result<std::shared_ptr<const VoxelStorage>> map_file(const std::string& path, uint64_t offset, uint64_t length);

// At most 2^34 voxels (16 G; 32 GB of 16-bit data), and each side at most 2^20.
inline constexpr uint64_t kMaxVoxels = uint64_t(1) << 34;
inline constexpr int kMaxVolumeSide = 1 << 20;

struct VolumeGrid {
  int nx = 0, ny = 0, nz = 0;
  VoxelType type = VoxelType::kFloat32;
  Vec3 spacing{1.0f};  // object-space distance between neighbouring voxels along x, y, z
  std::shared_ptr<const VoxelStorage> storage;
  float min_value = 0.0f, max_value = 0.0f;  // over all voxels

  size_t voxels() const { return size_t(nx) * size_t(ny) * size_t(nz); }
  size_t index(int x, int y, int z) const { return (size_t(z) * size_t(ny) + size_t(y)) * size_t(nx) + size_t(x); }
  template <class T>
  const T* as() const { return reinterpret_cast<const T*>(storage->data()); }
  float at(int x, int y, int z) const;      // one voxel, any type (slow paths and tests)
  Vec3 extent() const { return Vec3(float(nx - 1), float(ny - 1), float(nz - 1)) * spacing; }
};

// Checks a grid's sides (each 2..kMaxVolumeSide, the product at most kMaxVoxels), that the
// storage holds exactly its voxels, and that no float voxel is NaN or infinite; computes the value
// range. `what` names the source in errors ("FILE: what is wrong").
Result<std::shared_ptr<const VolumeGrid>> make_volume_grid(int nx, int ny, int nz, VoxelType type, Vec3 spacing,
                                                           std::shared_ptr<const VoxelStorage> storage,
                                                           const std::string& what);
// The size check alone, before anything is allocated or read: "" when fine, else what is wrong.
std::string volume_size_problem(int64_t nx, int64_t ny, int64_t nz, VoxelType type);

// Calls f(const T* voxels) with the grid's voxels as their own type.
template <class F>
decltype(auto) with_voxels(const VolumeGrid& g, F&& f) {
  switch (g.type) {
    case VoxelType::kUint8: return f(g.as<uint8_t>());
    case VoxelType::kUint16: return f(g.as<uint16_t>());
    default: return f(g.as<float>());
  }
}

}  // namespace frameless
