// Binary sphere files (millions of spheres, optionally a scalar per sphere shown through a colour
// map): reader, writer and the colour map; loading thread.
//
// Layout (all little-endian; version 1):
//   offset  size  field
//        0     8  magic "FLSPHERE" (8 ASCII bytes, no terminator)
//        8     4  uint32 version = 1
//       12     4  uint32 record size in bytes: 16 (x y z radius) or 20 (x y z radius scalar)
//       16     8  uint64 count: number of records
//       24     8  reserved, must be zero
//       32     -  count records of float32 fields, in the order above, no padding
// The file is exactly 32 + count * record size bytes. Every coordinate must be finite, every
// radius finite and >= 0 (a zero radius is accepted: a point, which no ray hits), every scalar
// finite. Records are numbered from 0 in error messages: "FILE: record 12: radius is NaN".
#pragma once
#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

#include "core/base/error.h"
#include "core/geometry/geometry.h"

namespace frameless {

inline constexpr char kSphereFileMagic[9] = "FLSPHERE";
inline constexpr uint32_t kSphereFileVersion = 1;
inline constexpr size_t kSphereFileHeaderBytes = 32;

struct SphereFileInfo {
  uint64_t count = 0;
  bool has_scalar = false;
  float scalar_min = 0, scalar_max = 0;  // over all records (0, 0 without scalars)
};

// Appends the file's spheres to geom.spheres. Materials: when the file has scalars and
// colormap_materials > 0, each sphere gets first_material + floor((s - min) / (max - min) *
// colormap_materials) (clamped; min == max gives first_material), over the file's scalar range.
// Otherwise each new sphere gets first_material, stored only when geom.sphere_material is in use
// (non-empty) or first_material != 0; an empty array means material 0 for all. sphere_material
// ends up empty or the size of spheres.
// Streams the file in 1 MiB blocks with pread(2): no copy of the file in memory, only the sphere
// (and material) arrays, which are reserved exactly once the header and the file size agree.
// With a colour map the scalars are read in a second pass (the range must be known first).
// On error returns one line "PATH: ...: what is wrong" and leaves geom's arrays at their
// previous sizes and contents.
Result<SphereFileInfo> load_sphere_file(const std::string& path, Geometry& geom,
                                        uint16_t first_material = 0, int colormap_materials = 0);
// The same from bytes in memory (tests, fuzzer); `name` stands for the path in messages.
Result<SphereFileInfo> parse_sphere_bytes(std::string_view bytes, const std::string& name,
                                          Geometry& geom, uint16_t first_material = 0,
                                          int colormap_materials = 0);

// Writes spheres (and scalars, one per sphere, when not null) as a version-1 file: to a temporary
// file in the same directory, then renamed over path. Values are written as given (no checks).
// Returns false with a one-line *error on failure (nothing is left behind).
bool write_sphere_file(const std::string& path, const std::vector<Sphere>& spheres,
                       const std::vector<float>* scalars, std::string* error);

// n linear-RGB diffuse colours sampled evenly from viridis (dark blue through teal to yellow;
// perceptually uniform, readable in grey and by colour-blind viewers): n = 1 gives the middle.
std::vector<Vec3> colormap_colors(int n);

}  // namespace frameless
