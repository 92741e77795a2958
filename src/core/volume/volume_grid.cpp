// Grids, their storage (owned or memory-mapped) and their checks.
#include "core/volume/volume_grid.h"

#include <fcntl.h>
#include <sys/mman.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstring>
#include <type_traits>

namespace frameless {
namespace {

class OwnedStorage final : public VoxelStorage {
 public:
  explicit OwnedStorage(std::vector<uint8_t> b) : bytes_(std::move(b)) {}
  const uint8_t* data() const override { return bytes_.data(); }
  size_t size() const override { return bytes_.size(); }

 private:
  std::vector<uint8_t> bytes_;
};

class MappedStorage final : public VoxelStorage {
 public:
  MappedStorage(void* base, size_t length, size_t skip)
      : base_(base), length_(length), skip_(skip) {}
  ~MappedStorage() override { munmap(base_, length_); }
  const uint8_t* data() const override { return static_cast<const uint8_t*>(base_) + skip_; }
  size_t size() const override { return length_ - skip_; }

 private:
  void* base_;
  size_t length_, skip_;  // the mapping starts on a page: the data `skip_` bytes into it
};

}  // namespace

size_t voxel_bytes(VoxelType type) {
  return type == VoxelType::kUint8 ? 1 : type == VoxelType::kUint16 ? 2 : 4;
}

const char* voxel_type_name(VoxelType type) {
  return type == VoxelType::kUint8 ? "uint8" : type == VoxelType::kUint16 ? "uint16" : "float32";
}

std::shared_ptr<const VoxelStorage> owned_storage(std::vector<uint8_t> bytes) {
  return std::make_shared<OwnedStorage>(std::move(bytes));
}

Result<std::shared_ptr<const VoxelStorage>> map_file(const std::string& path, uint64_t offset,
                                                     uint64_t length) {
  const int fd = ::open(path.c_str(), O_RDONLY | O_CLOEXEC);
  if (fd < 0) return Error{path + ": cannot open: " + std::strerror(errno)};
  struct stat st {};
  if (fstat(fd, &st) != 0 || uint64_t(st.st_size) < offset + length) {
    ::close(fd);
    return Error{path + ": file is shorter than the " + std::to_string(offset + length) +
                 " bytes its volume needs"};
  }
  const uint64_t page = uint64_t(sysconf(_SC_PAGESIZE));
  const uint64_t start = offset / page * page, skip = offset - start;
  void* p = mmap(nullptr, size_t(length + skip), PROT_READ, MAP_PRIVATE, fd, off_t(start));
  ::close(fd);  // the mapping keeps the file
  if (p == MAP_FAILED)
    return Error{path + ": cannot map " + std::to_string(length) +
                 " bytes: " + std::strerror(errno)};
  return std::shared_ptr<const VoxelStorage>(
      std::make_shared<MappedStorage>(p, size_t(length + skip), size_t(skip)));
}

float VolumeGrid::at(int x, int y, int z) const {
  return with_voxels(*this, [&](const auto& v) { return v(x, y, z); });
}

std::string volume_size_problem(int64_t nx, int64_t ny, int64_t nz, VoxelType type) {
  const std::string dims = std::to_string(nx) + "x" + std::to_string(ny) + "x" + std::to_string(nz);
  if (nx < 2 || ny < 2 || nz < 2) return "dimensions " + dims + ": each must be at least 2";
  if (nx > kMaxVolumeSide || ny > kMaxVolumeSide || nz > kMaxVolumeSide)
    return "dimensions " + dims + ": each must be at most " + std::to_string(kMaxVolumeSide);
  const uint64_t n = uint64_t(nx) * uint64_t(ny);  // both below 2^21: no overflow
  if (n > kMaxVoxels || n * uint64_t(nz) > kMaxVoxels)
    return "dimensions " + dims + ": more than 2^34 voxels";
  const uint64_t bytes = n * uint64_t(nz) * voxel_bytes(type);
  const long pages = sysconf(_SC_PHYS_PAGES), page = sysconf(_SC_PAGESIZE);
  if (pages > 0 && page > 0 && bytes > uint64_t(pages) * uint64_t(page))
    return "dimensions " + dims + " of " + voxel_type_name(type) + ": " +
           std::to_string(bytes >> 20) + " MiB, more than this machine's memory";
  return "";
}

Result<std::shared_ptr<const VolumeGrid>> make_volume_grid(
    int nx, int ny, int nz, VoxelType type, Vec3 spacing,
    std::shared_ptr<const VoxelStorage> storage, const std::string& what) {
  if (const std::string p = volume_size_problem(nx, ny, nz, type); !p.empty())
    return Error{what + ": " + p};
  if (!(spacing.x > 0.0f && spacing.y > 0.0f && spacing.z > 0.0f) || !is_finite(spacing))
    return Error{what + ": spacing must be positive and finite"};
  auto g = std::make_shared<VolumeGrid>();
  g->nx = nx;
  g->ny = ny;
  g->nz = nz;
  g->type = type;
  g->spacing = spacing;
  g->storage = std::move(storage);
  const size_t n = g->voxels();
  if (!g->storage || g->storage->size() != n * voxel_bytes(type))
    return Error{what + ": holds " + std::to_string(g->storage ? g->storage->size() : 0) +
                 " bytes, " + std::to_string(n * voxel_bytes(type)) + " expected for " +
                 std::to_string(nx) + "x" + std::to_string(ny) + "x" + std::to_string(nz) + " " +
                 voxel_type_name(type)};
  float lo = kInfinity, hi = -kInfinity;
  size_t bad = n;
  with_voxels(*g, [&](const auto& v) {
    if constexpr (!std::is_same_v<std::decay_t<decltype(v)>, BrickedVoxels>)  // dense here
      for (size_t i = 0; i < n; ++i) {
        const float x = float(v.v[i]);
        if (!std::isfinite(x)) {
          bad = i;
          return;
        }
        lo = std::min(lo, x);
        hi = std::max(hi, x);
      }
  });
  if (bad < n) {
    const size_t x = bad % size_t(nx), y = bad / size_t(nx) % size_t(ny),
                 z = bad / (size_t(nx) * size_t(ny));
    return Error{what + ": voxel (" + std::to_string(x) + ", " + std::to_string(y) + ", " +
                 std::to_string(z) + ") is not a finite number"};
  }
  g->min_value = lo;
  g->max_value = hi;
  return std::shared_ptr<const VolumeGrid>(std::move(g));
}

}  // namespace frameless
