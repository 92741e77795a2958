// A volume of scalar samples on a regular grid (issue 27): voxels of 8-bit, 16-bit or 32-bit float
// data kept as stored (16-bit stays 16-bit), owned or memory-mapped from the file they came from.
// Voxel (i, j, k) sits at object-space point (i, j, k) * spacing; the (nx-1)(ny-1)(nz-1) cells
// between voxel centres hold the trilinear interpolant. Dense grids keep x fastest; sparse ones
// (OpenVDB files) are bricked. Built on the loading thread, read-only while rendering (any thread).
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
Result<std::shared_ptr<const VoxelStorage>> map_file(const std::string& path, uint64_t offset,
                                                     uint64_t length);

// At most 2^34 voxels (16 G; 32 GB of 16-bit data), and each side at most 2^20.
inline constexpr uint64_t kMaxVoxels = uint64_t(1) << 34;
inline constexpr int kMaxVolumeSide = 1 << 20;

// A sparse grid in bricks of 8^3 cells (OpenVDB's leaves): each brick stores its 9^3 voxels (the
// far faces repeat the next brick's first ones) so that every cell's eight voxels lie in one brick,
// and bricks whose voxels are all one value are stored once per value: empty space costs a table
// entry. Voxels past the grid's last ones repeat them.
inline constexpr int kBrickCells = 8, kBrickSide = 9, kBrickVoxels = 729;
struct BrickPool {
  int bx = 0, by = 0, bz = 0;   // bricks per axis: (n - 1) / 8 + 1
  std::vector<uint32_t> table;  // brick (x, y, z) -> its voxels at voxels[table[i] * kBrickVoxels]
  std::vector<float> voxels;    // per brick x fastest, then y, then z
  size_t stored() const { return voxels.size() / kBrickVoxels; }
  size_t bytes() const { return table.size() * sizeof(uint32_t) + voxels.size() * sizeof(float); }
};

struct VolumeGrid {
  int nx = 0, ny = 0, nz = 0;
  VoxelType type = VoxelType::kFloat32;
  Vec3 spacing{1.0f};  // object-space distance between neighbouring voxels along x, y, z
  std::shared_ptr<const VoxelStorage> storage;  // dense grids
  std::shared_ptr<const BrickPool> bricks;      // sparse grids (float32): storage is empty
  float min_value = 0.0f, max_value = 0.0f;     // over all voxels

  size_t voxels() const { return size_t(nx) * size_t(ny) * size_t(nz); }
  size_t index(int x, int y, int z) const {
    return (size_t(z) * size_t(ny) + size_t(y)) * size_t(nx) + size_t(x);
  }
  template <class T>
  const T* as() const {
    return reinterpret_cast<const T*>(storage->data());
  }
  size_t bytes() const { return bricks ? bricks->bytes() : storage ? storage->size() : 0; }
  float at(int x, int y, int z) const;  // one voxel, any type (slow paths and tests)
  Vec3 extent() const { return Vec3(float(nx - 1), float(ny - 1), float(nz - 1)) * spacing; }
};

// Checks a grid's sides (each 2..kMaxVolumeSide, the product at most kMaxVoxels), that the
// storage holds exactly its voxels, and that no float voxel is NaN or infinite; computes the value
// range. `what` names the source in errors ("FILE: what is wrong").
Result<std::shared_ptr<const VolumeGrid>> make_volume_grid(
    int nx, int ny, int nz, VoxelType type, Vec3 spacing,
    std::shared_ptr<const VoxelStorage> storage, const std::string& what);
// The size check alone, before anything is allocated or read: "" when fine, else what is wrong.
std::string volume_size_problem(int64_t nx, int64_t ny, int64_t nz, VoxelType type);

// The eight voxels of the cell whose first voxel is at p, in storage with strides sy and sz:
// voxel (x + i, y + j, z + k) at c[i + 2j + 4k].
template <class R, class T>
inline void load_corners(const T* p, size_t sy, size_t sz, R (&c)[8]) {
  c[0] = R(p[0]), c[1] = R(p[1]), c[2] = R(p[sy]), c[3] = R(p[sy + 1]);
  c[4] = R(p[sz]), c[5] = R(p[sz + 1]), c[6] = R(p[sz + sy]), c[7] = R(p[sz + sy + 1]);
}

// Reading voxels of a dense grid as their own type T: v(x, y, z), and a cell's eight corners.
template <class T>
struct DenseVoxels {
  const T* v;
  size_t sy, sz;  // strides of y and z
  size_t index(int x, int y, int z) const { return size_t(z) * sz + size_t(y) * sy + size_t(x); }
  float operator()(int x, int y, int z) const { return float(v[index(x, y, z)]); }
  template <class R>
  void corners(int x, int y, int z, R (&c)[8]) const {
    load_corners(v + index(x, y, z), sy, sz, c);
  }
};

// The same for a bricked grid: one table lookup finds the brick of a voxel or cell.
struct BrickedVoxels {
  const BrickPool* p;
  const float* at(int x, int y, int z) const {
    const size_t b =
        (size_t(z >> 3) * size_t(p->by) + size_t(y >> 3)) * size_t(p->bx) + size_t(x >> 3);
    return p->voxels.data() + size_t(p->table[b]) * kBrickVoxels +
           ((z & 7) * kBrickSide + (y & 7)) * kBrickSide + (x & 7);
  }
  float operator()(int x, int y, int z) const { return *at(x, y, z); }
  template <class R>
  void corners(int x, int y, int z, R (&c)[8]) const {
    load_corners(at(x, y, z), size_t(kBrickSide), size_t(kBrickSide * kBrickSide), c);
  }
};

// Calls f(voxels) with the grid's reader: DenseVoxels<T> of its own type, or BrickedVoxels.
template <class F>
decltype(auto) with_voxels(const VolumeGrid& g, F&& f) {
  if (g.bricks) return f(BrickedVoxels{g.bricks.get()});
  const size_t sy = size_t(g.nx), sz = size_t(g.nx) * size_t(g.ny);
  switch (g.type) {
    case VoxelType::kUint8:
      return f(DenseVoxels<uint8_t>{g.as<uint8_t>(), sy, sz});
    case VoxelType::kUint16:
      return f(DenseVoxels<uint16_t>{g.as<uint16_t>(), sy, sz});
    default:
      return f(DenseVoxels<float>{g.as<float>(), sy, sz});
  }
}

}  // namespace frameless
