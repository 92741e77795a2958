// Binary sphere files (sphere_file.h): streamed, checked reader; atomic writer; viridis colours.
#include "core/io/sphere_file.h"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <atomic>
#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <limits>
#include <new>
#include <optional>

namespace frameless {
namespace {

constexpr size_t kBlockBytes = size_t(1) << 20;
// Primitive ids are uint32 with kInvalidId reserved: a scene holds fewer than 2^32 - 1.
constexpr uint64_t kMaxPrimitives = 0xfffffffeull;

uint32_t load_u32(const unsigned char* p) {
  return uint32_t(p[0]) | uint32_t(p[1]) << 8 | uint32_t(p[2]) << 16 | uint32_t(p[3]) << 24;
}
uint64_t load_u64(const unsigned char* p) { return load_u32(p) | uint64_t(load_u32(p + 4)) << 32; }
float load_f32(const unsigned char* p) {
  const uint32_t u = load_u32(p);
  float f;
  std::memcpy(&f, &u, 4);
  return f;
}
void store_u32(unsigned char* p, uint32_t v) {
  for (int i = 0; i < 4; ++i) p[i] = (unsigned char)(v >> (8 * i));
}
void store_u64(unsigned char* p, uint64_t v) {
  store_u32(p, uint32_t(v));
  store_u32(p + 4, uint32_t(v >> 32));
}
void store_f32(unsigned char* p, float f) {
  uint32_t u;
  std::memcpy(&u, &f, 4);
  store_u32(p, u);
}

std::string number(double v) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%g", v);
  return buf;
}

// Where the bytes come from: memory, or a file read block by block into one buffer.
class Source {
 public:
  virtual ~Source() = default;
  // Pointer to bytes [offset, offset + n) (n <= kBlockBytes), valid until the next call; null
  // with *error set on failure.
  virtual const unsigned char* get(uint64_t offset, size_t n, std::string* error) = 0;
};

class MemorySource : public Source {
 public:
  explicit MemorySource(std::string_view b) : b_(b) {}
  const unsigned char* get(uint64_t offset, size_t, std::string*) override {
    return reinterpret_cast<const unsigned char*>(b_.data()) + offset;
  }

 private:
  std::string_view b_;
};

class FileSource : public Source {
 public:
  FileSource(int fd, const std::string& name) : fd_(fd), name_(name) {}
  const unsigned char* get(uint64_t offset, size_t n, std::string* error) override {
    if (buf_.empty()) buf_.resize(kBlockBytes);
    size_t done = 0;
    while (done < n) {
      const ssize_t r = pread(fd_, buf_.data() + done, n - done, off_t(offset + done));
      if (r < 0 && errno == EINTR) continue;
      if (r <= 0) {
        *error = name_ + ": read failed at byte " + std::to_string(offset + done) + ": " +
                 (r < 0 ? std::strerror(errno) : "file shrank while being read");
        return nullptr;
      }
      done += size_t(r);
    }
    return buf_.data();
  }

 private:
  int fd_;
  const std::string& name_;
  std::vector<unsigned char> buf_;
};

struct Header {
  uint32_t record = 0;
  uint64_t count = 0;
};

std::optional<Error> check_header(const unsigned char* h, uint64_t size, const std::string& name,
                                  Header& out) {
  if (std::memcmp(h, kSphereFileMagic, 8) != 0)
    return Error{name + ": header: magic is not FLSPHERE (not a frameless sphere file)"};
  const uint32_t version = load_u32(h + 8);
  if (version != kSphereFileVersion)
    return Error{name + ": header: version " + std::to_string(version) +
                 " is not supported (expected " + std::to_string(kSphereFileVersion) + ")"};
  out.record = load_u32(h + 12);
  if (out.record != 16 && out.record != 20)
    return Error{name + ": header: record size " + std::to_string(out.record) +
                 " is not 16 (x y z radius) or 20 (x y z radius scalar)"};
  out.count = load_u64(h + 16);
  if (load_u64(h + 24) != 0) return Error{name + ": header: reserved field is not zero"};
  // Exact size, checked by division so that no product can overflow.
  const uint64_t body = size - kSphereFileHeaderBytes;
  if (body % out.record != 0 || body / out.record != out.count) {
    const unsigned __int128 want =
        (unsigned __int128)out.count * out.record + kSphereFileHeaderBytes;
    std::string expected = want > std::numeric_limits<uint64_t>::max()
                               ? "more than 2^64"
                               : std::to_string(uint64_t(want));
    return Error{name + ": size " + std::to_string(size) + " is not header + count * record (" +
                 std::to_string(kSphereFileHeaderBytes) + " + " + std::to_string(out.count) +
                 " * " + std::to_string(out.record) + " = " + expected + " bytes)"};
  }
  return std::nullopt;
}

// The first thing wrong with a record, or "".
std::string record_problem(float x, float y, float z, float r) {
  const float v[3] = {x, y, z};
  const char* names[3] = {"x", "y", "z"};
  for (int a = 0; a < 3; ++a) {
    if (std::isnan(v[a])) return std::string(names[a]) + " is NaN";
    if (std::isinf(v[a])) return std::string(names[a]) + " is infinite";
  }
  if (std::isnan(r)) return "radius is NaN";
  if (r < 0.0f) return "radius is negative (" + number(r) + ")";
  if (std::isinf(r)) return "radius is infinite";
  return "";
}

Result<SphereFileInfo> load(Source& src, uint64_t size, const std::string& name, Geometry& g,
                            uint16_t first_material, int colormap_materials) {
  if (size < kSphereFileHeaderBytes)
    return Error{name + ": header: file is " + std::to_string(size) + " bytes, shorter than the " +
                 std::to_string(kSphereFileHeaderBytes) + "-byte header"};
  std::string error;
  const unsigned char* h = src.get(0, kSphereFileHeaderBytes, &error);
  if (!h) return Error{error};
  Header hd;
  if (auto e = check_header(h, size, name, hd)) return *e;
  if (colormap_materials < 0 || uint32_t(first_material) + uint32_t(colormap_materials) > 65536u)
    return Error{name + ": colour map: materials " + std::to_string(first_material) + " + " +
                 std::to_string(colormap_materials) + " do not fit in 16-bit material ids"};
  const uint64_t old_n = g.spheres.size(), old_m = g.sphere_material.size();
  if (hd.count > kMaxPrimitives - std::min<uint64_t>(kMaxPrimitives, g.num_primitives()))
    return Error{name + ": header: count " + std::to_string(hd.count) + " is more than a scene " +
                 "can hold (" + std::to_string(kMaxPrimitives) + " primitives in all)"};

  SphereFileInfo info;
  info.count = hd.count;
  info.has_scalar = hd.record == 20;
  const bool colormap = info.has_scalar && colormap_materials > 0;
  const bool materials = colormap || first_material != 0 || !g.sphere_material.empty();
  // Restores the previous sizes on any failure (contents before old_n are never touched).
  auto fail = [&](Error e) -> Result<SphereFileInfo> {
    g.spheres.resize(old_n);
    g.sphere_material.resize(old_m);
    return e;
  };
  try {
    g.spheres.reserve(old_n + hd.count);
    if (materials) {
      g.sphere_material.reserve(old_n + hd.count);
      g.sphere_material.resize(old_n, 0);  // spheres that had the implicit material 0
    }
  } catch (const std::bad_alloc&) {
    return fail(Error{name + ": not enough memory for " + std::to_string(hd.count) + " spheres"});
  } catch (const std::length_error&) {
    return fail(Error{name + ": not enough memory for " + std::to_string(hd.count) + " spheres"});
  }

  const uint32_t rec = hd.record;
  const uint64_t per_block = kBlockBytes / rec;
  float smin = kInfinity, smax = -kInfinity;
  for (uint64_t k0 = 0; k0 < hd.count; k0 += per_block) {
    const uint64_t n = std::min(per_block, hd.count - k0);
    const unsigned char* p = src.get(kSphereFileHeaderBytes + k0 * rec, size_t(n * rec), &error);
    if (!p) return fail(Error{error});
    for (uint64_t i = 0; i < n; ++i, p += rec) {
      const float x = load_f32(p), y = load_f32(p + 4), z = load_f32(p + 8), r = load_f32(p + 12);
      if (!(std::isfinite(x) && std::isfinite(y) && std::isfinite(z) && r >= 0.0f &&
            r <= std::numeric_limits<float>::max()))
        return fail(Error{name + ": record " + std::to_string(k0 + i) + ": " +
                          record_problem(x, y, z, r)});
      if (info.has_scalar) {
        const float s = load_f32(p + 16);
        if (!std::isfinite(s))
          return fail(Error{name + ": record " + std::to_string(k0 + i) + ": scalar is " +
                            (std::isnan(s) ? "NaN" : "infinite")});
        smin = std::min(smin, s);
        smax = std::max(smax, s);
      }
      g.spheres.push_back(Sphere{Vec3(x, y, z), r});
      if (materials && !colormap) g.sphere_material.push_back(first_material);
    }
  }
  if (info.has_scalar && hd.count > 0) {
    info.scalar_min = smin;
    info.scalar_max = smax;
  }
  if (colormap) {
    // Second pass over the scalars, now that their range is known.
    const double lo = info.scalar_min, span = double(info.scalar_max) - double(info.scalar_min);
    const double scale = span > 0.0 ? double(colormap_materials) / span : 0.0;
    for (uint64_t k0 = 0; k0 < hd.count; k0 += per_block) {
      const uint64_t n = std::min(per_block, hd.count - k0);
      const unsigned char* p = src.get(kSphereFileHeaderBytes + k0 * rec, size_t(n * rec), &error);
      if (!p) return fail(Error{error});
      for (uint64_t i = 0; i < n; ++i, p += rec) {
        const double t = (double(load_f32(p + 16)) - lo) * scale;  // NaN-safe clamp below
        const int k = t >= 0.0 ? (t < double(colormap_materials) ? int(t) : colormap_materials - 1)
                               : 0;
        g.sphere_material.push_back(uint16_t(first_material + k));
      }
    }
  }
  return info;
}

}  // namespace

Result<SphereFileInfo> parse_sphere_bytes(std::string_view bytes, const std::string& name,
                                          Geometry& geom, uint16_t first_material,
                                          int colormap_materials) {
  MemorySource src(bytes);
  return one_line(load(src, bytes.size(), name, geom, first_material, colormap_materials));
}

Result<SphereFileInfo> load_sphere_file(const std::string& path, Geometry& geom,
                                        uint16_t first_material, int colormap_materials) {
  const int fd = open(path.c_str(), O_RDONLY | O_CLOEXEC);
  if (fd < 0) return one_line(Result<SphereFileInfo>(Error{path + ": cannot open: " + std::strerror(errno)}));
  struct stat st;
  if (fstat(fd, &st) != 0 || !S_ISREG(st.st_mode)) {
    close(fd);
    return one_line(Result<SphereFileInfo>(Error{path + ": not a regular file"}));
  }
#if defined(POSIX_FADV_SEQUENTIAL)
  posix_fadvise(fd, 0, 0, POSIX_FADV_SEQUENTIAL);
#endif
  FileSource src(fd, path);
  auto r = load(src, uint64_t(st.st_size), path, geom, first_material, colormap_materials);
  close(fd);
  return one_line(std::move(r));
}

bool write_sphere_file(const std::string& path, const std::vector<Sphere>& spheres,
                       const std::vector<float>* scalars, std::string* error) {
  auto fail = [&](const std::string& msg) {
    if (error) *error = one_line(msg);
    return false;
  };
  if (scalars && scalars->size() != spheres.size())
    return fail(path + ": scalars: " + std::to_string(scalars->size()) + " values for " +
                std::to_string(spheres.size()) + " spheres");
  static std::atomic<unsigned> counter{0};
  const std::string tmp =
      path + ".tmp" + std::to_string(getpid()) + "_" + std::to_string(counter++);
  const int fd = open(tmp.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_CLOEXEC, 0666);
  if (fd < 0) return fail(path + ": cannot create temporary file: " + std::strerror(errno));
  const uint32_t rec = scalars ? 20 : 16;
  std::vector<unsigned char> buf;
  buf.reserve(kBlockBytes + kSphereFileHeaderBytes);
  auto flush = [&]() {
    size_t done = 0;
    while (done < buf.size()) {
      const ssize_t w = write(fd, buf.data() + done, buf.size() - done);
      if (w < 0 && errno == EINTR) continue;
      if (w <= 0) return false;
      done += size_t(w);
    }
    buf.clear();
    return true;
  };
  unsigned char h[kSphereFileHeaderBytes] = {};
  std::memcpy(h, kSphereFileMagic, 8);
  store_u32(h + 8, kSphereFileVersion);
  store_u32(h + 12, rec);
  store_u64(h + 16, spheres.size());
  buf.insert(buf.end(), h, h + sizeof h);
  bool ok = true;
  for (size_t i = 0; i < spheres.size() && ok; ++i) {
    unsigned char r[20];
    store_f32(r, spheres[i].center.x);
    store_f32(r + 4, spheres[i].center.y);
    store_f32(r + 8, spheres[i].center.z);
    store_f32(r + 12, spheres[i].radius);
    if (scalars) store_f32(r + 16, (*scalars)[i]);
    buf.insert(buf.end(), r, r + rec);
    if (buf.size() >= kBlockBytes) ok = flush();
  }
  if (ok) ok = flush();
  const int saved = errno;
  if (close(fd) != 0 && ok) ok = false;
  if (!ok) {
    unlink(tmp.c_str());
    return fail(path + ": write failed: " + std::strerror(saved ? saved : errno));
  }
  if (std::rename(tmp.c_str(), path.c_str()) != 0) {
    const int e = errno;
    unlink(tmp.c_str());
    return fail(path + ": cannot rename temporary file: " + std::strerror(e));
  }
  return true;
}

std::vector<Vec3> colormap_colors(int n) {
  // Viridis (matplotlib) at nine even stops, sRGB bytes; interpolated in sRGB, then linearised
  // for the renderer's linear diffuse colours.
  static constexpr unsigned char kStops[9][3] = {{0x44, 0x01, 0x54}, {0x47, 0x2d, 0x7b},
                                                 {0x3b, 0x52, 0x8b}, {0x2c, 0x72, 0x8e},
                                                 {0x21, 0x91, 0x8c}, {0x28, 0xae, 0x80},
                                                 {0x5e, 0xc9, 0x62}, {0xad, 0xdc, 0x30},
                                                 {0xfd, 0xe7, 0x25}};
  std::vector<Vec3> out;
  if (n <= 0) return out;
  out.reserve(size_t(n));
  for (int i = 0; i < n; ++i) {
    const float t = n == 1 ? 0.5f : float(i) / float(n - 1);
    const float x = t * 8.0f;
    const int k = std::min(7, int(x));
    const float f = x - float(k);
    Vec3 c;
    for (int a = 0; a < 3; ++a) {
      const float srgb = ((1.0f - f) * kStops[k][a] + f * kStops[k + 1][a]) / 255.0f;
      c[a] = srgb <= 0.04045f ? srgb / 12.92f : std::pow((srgb + 0.055f) / 1.055f, 2.4f);
    }
    out.push_back(c);
  }
  return out;
}

}  // namespace frameless
