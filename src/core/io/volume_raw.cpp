// Raw volumes: the sides are checked first (volume_size_problem), then the file's length; the
// voxels are mapped when their byte order is this machine's and they lie aligned, else read (and
// swapped where needed).
#include "core/io/volume_raw.h"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <bit>
#include <cerrno>
#include <cstring>
#include <new>
#include <utility>

#include "core/io/file_util.h"

namespace frameless {
namespace {

std::string dims_text(const RawVolumeSpec& s) {
  return std::to_string(s.nx) + "x" + std::to_string(s.ny) + "x" + std::to_string(s.nz) + " " + voxel_type_name(s.type);
}

// The bytes of the spec's voxels; "" in `problem` when its sides are acceptable.
uint64_t data_bytes(const RawVolumeSpec& s, std::string& problem) {
  problem = volume_size_problem(s.nx, s.ny, s.nz, s.type);
  if (!problem.empty()) return 0;
  return uint64_t(s.nx) * uint64_t(s.ny) * uint64_t(s.nz) * voxel_bytes(s.type);
}

// "" when a source of `actual` bytes holds exactly the header and the voxels, else why not.
std::string length_problem(uint64_t actual, uint64_t data, const RawVolumeSpec& s) {
  if (s.offset <= actual && actual - s.offset == data) return "";
  const std::string header = s.offset ? std::to_string(s.offset) + " header bytes + " : "";
  const std::string expected = s.offset > UINT64_MAX - data ? "more than 2^64" : std::to_string(s.offset + data);
  return "holds " + std::to_string(actual) + " bytes, expected " + expected + " (" + header + std::to_string(data) +
         " bytes of " + dims_text(s) + " voxels)";
}

Result<std::shared_ptr<const VolumeGrid>> make_grid(const RawVolumeSpec& s, std::shared_ptr<const VoxelStorage> storage,
                                                    const std::string& path) {
  return one_line(make_volume_grid(int(s.nx), int(s.ny), int(s.nz), s.type, s.spacing, std::move(storage), path));
}

// Reads exactly out.size() bytes at `at` (retrying short reads); false on an error or early end.
bool read_exact(int fd, uint64_t at, std::vector<uint8_t>& out) {
  size_t done = 0;
  while (done < out.size()) {
    const ssize_t n = ::pread(fd, out.data() + done, out.size() - done, off_t(at + done));
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) return false;
    done += size_t(n);
  }
  return true;
}

}  // namespace

bool voxels_need_swap(VoxelType type, bool big_endian) {
  return voxel_bytes(type) > 1 && big_endian != (std::endian::native == std::endian::big);
}

void swap_voxel_bytes(std::vector<uint8_t>& bytes, VoxelType type) {
  const size_t width = voxel_bytes(type);
  if (width == 1) return;
  uint8_t* p = bytes.data();
  const size_t n = bytes.size() / width * width;
  if (width == 2) {
    for (size_t i = 0; i < n; i += 2) std::swap(p[i], p[i + 1]);
  } else {
    for (size_t i = 0; i < n; i += 4) {
      std::swap(p[i], p[i + 3]);
      std::swap(p[i + 1], p[i + 2]);
    }
  }
}

Result<std::shared_ptr<const VolumeGrid>> read_raw_volume(const std::string& path, const RawVolumeSpec& spec) {
  std::string problem;
  const uint64_t data = data_bytes(spec, problem);
  if (!problem.empty()) return file_error(path, problem);
  const int fd = ::open(path.c_str(), O_RDONLY | O_CLOEXEC);
  if (fd < 0) return file_error(path, std::string("cannot open: ") + std::strerror(errno));
  struct Closer {
    int fd;
    ~Closer() { ::close(fd); }
  } closer{fd};
  // Devices and pipes have no length to check: only regular files hold volumes.
  struct stat st {};
  if (fstat(fd, &st) != 0 || !S_ISREG(st.st_mode)) return file_error(path, "not a regular file");
  if (const std::string p = length_problem(uint64_t(st.st_size), data, spec); !p.empty()) return file_error(path, p);
  // The grid reads voxels as their own type: a mapping must leave them aligned.
  if (!voxels_need_swap(spec.type, spec.big_endian) && spec.offset % voxel_bytes(spec.type) == 0) {
    auto mapped = map_file(path, spec.offset, data);
    if (!mapped) return Error{one_line(mapped.error().message)};
    return make_grid(spec, std::move(*mapped), path);
  }
  try {
    std::vector<uint8_t> bytes(data);  // no more than the file holds: its length was checked
    errno = 0;
    if (!read_exact(fd, spec.offset, bytes))
      return file_error(path, errno ? std::string("read error: ") + std::strerror(errno) : "the file ended early");
    if (voxels_need_swap(spec.type, spec.big_endian)) swap_voxel_bytes(bytes, spec.type);
    return make_grid(spec, owned_storage(std::move(bytes)), path);
  } catch (const std::bad_alloc&) {
    return file_error(path, "out of memory for " + std::to_string(data) + " bytes of voxels");
  }
}

Result<std::shared_ptr<const VolumeGrid>> decode_raw_volume(const std::string& bytes, const RawVolumeSpec& spec,
                                                            const std::string& path) {
  std::string problem;
  const uint64_t data = data_bytes(spec, problem);
  if (!problem.empty()) return file_error(path, problem);
  if (const std::string p = length_problem(bytes.size(), data, spec); !p.empty()) return file_error(path, p);
  try {
    const auto* first = reinterpret_cast<const uint8_t*>(bytes.data()) + spec.offset;
    std::vector<uint8_t> voxels(first, first + data);
    if (voxels_need_swap(spec.type, spec.big_endian)) swap_voxel_bytes(voxels, spec.type);
    return make_grid(spec, owned_storage(std::move(voxels)), path);
  } catch (const std::bad_alloc&) {
    return file_error(path, "out of memory for " + std::to_string(data) + " bytes of voxels");
  }
}

}  // namespace frameless
