// The built-in volumes: analytic signals sampled on a grid, slice by slice through the caller's executor.
#include "core/volume/volume_generators.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <vector>

namespace frameless {
namespace {

// Grid coordinate i of n mapped onto [-1, 1].
inline float unit(int i, int n) { return -1.0f + 2.0f * float(i) / float(n - 1); }

// Voxels written in place into the bytes the grid will own: no second copy of a big volume.
template <class T>
struct VoxelBuffer {
  std::vector<uint8_t> bytes;
  explicit VoxelBuffer(size_t n) : bytes(n * sizeof(T)) {}
  T* data() { return reinterpret_cast<T*>(bytes.data()); }  // new[]'s alignment suits any T
  T& operator[](size_t i) { return data()[i]; }
};

template <class T>
std::shared_ptr<const VolumeGrid> finish(int nx, int ny, int nz, VoxelType type, Vec3 spacing, VoxelBuffer<T>& v) {
  auto g = make_volume_grid(nx, ny, nz, type, spacing, owned_storage(std::move(v.bytes)), "built-in volume");
  return g ? *g : nullptr;  // generators only make valid grids
}

struct Ellipsoid {
  float density;
  float a, b, c;      // semi-axes along x, y, z
  float x0, y0, z0;   // centre
  float phi_deg;      // rotation about z
};

// Kak and Slaney's 3-D head (Principles of Computerized Tomographic Imaging, table 3.2) with the
// densities of Toft's modified 2-D phantom, which shows the inner structures at display contrast.
constexpr Ellipsoid kHead[10] = {
    {1.0f, 0.6900f, 0.920f, 0.810f, 0.00f, 0.0000f, 0.00f, 0.0f},
    {-0.8f, 0.6624f, 0.874f, 0.780f, 0.00f, -0.0184f, 0.00f, 0.0f},
    {-0.2f, 0.1100f, 0.310f, 0.220f, 0.22f, 0.0000f, 0.00f, -18.0f},
    {-0.2f, 0.1600f, 0.410f, 0.280f, -0.22f, 0.0000f, 0.00f, 18.0f},
    {0.1f, 0.2100f, 0.250f, 0.410f, 0.00f, 0.3500f, -0.15f, 0.0f},
    {0.1f, 0.0460f, 0.046f, 0.050f, 0.00f, 0.1000f, 0.25f, 0.0f},
    {0.1f, 0.0460f, 0.046f, 0.050f, 0.00f, -0.1000f, 0.25f, 0.0f},
    {0.1f, 0.0460f, 0.023f, 0.050f, -0.08f, -0.6050f, 0.00f, 0.0f},
    {0.1f, 0.0230f, 0.023f, 0.020f, 0.00f, -0.6060f, 0.00f, 0.0f},
    {0.1f, 0.0230f, 0.046f, 0.020f, 0.06f, -0.6050f, 0.00f, 0.0f},
};

// The phantom's ellipsoids have sharp edges, whose trilinear isosurfaces are staircases a voxel
// high: a [1 2 1] / 4 filter along each axis (about a voxel of blur, as a CT scanner's point
// spread gives) makes them smooth. In place, line by line; the executor takes whole slices (rows
// for the pass along z), so no two threads write one cache line (a line each made a 256^3
// phantom's smoothing twice as slow on two threads as on one).
void smooth_121(uint16_t* v, int nx, int ny, int nz, const ParallelFor& pf) {
  const size_t sy = size_t(nx), sz = size_t(nx) * size_t(ny);
  const auto line = [&](uint16_t* p, size_t stride, int n) {
    int prev = p[0];
    for (int i = 0; i < n; ++i) {
      const int c = p[size_t(i) * stride], next = i + 1 < n ? p[size_t(i + 1) * stride] : c;
      p[size_t(i) * stride] = uint16_t((prev + 2 * c + next + 2) / 4);
      prev = c;
    }
  };
  parallel_for_each(pf, size_t(nz), [&](size_t z) {  // along x, then along y, a slice at a time
    for (size_t y = 0; y < size_t(ny); ++y) line(v + z * sz + y * sy, 1, nx);
    for (size_t x = 0; x < size_t(nx); ++x) line(v + z * sz + x, sy, ny);
  });
  parallel_for_each(pf, size_t(ny), [&](size_t y) {  // along z, a row of lines at a time
    for (size_t x = 0; x < size_t(nx); ++x) line(v + y * sy + x, sz, nz);
  });
}

}  // namespace

float marschner_lobb(float x, float y, float z) {
  constexpr double kFm = 6.0, kAlpha = 0.25;
  const double r = std::sqrt(double(x) * x + double(y) * y);
  const double rho_r = std::cos(2.0 * kPi * kFm * std::cos(kPi * r / 2.0));
  return float((1.0 - std::sin(kPi * z / 2.0) + kAlpha * (1.0 + rho_r)) / (2.0 * (1.0 + kAlpha)));
}

std::shared_ptr<const VolumeGrid> make_marschner_lobb(int n, const ParallelFor& pf) {
  VoxelBuffer<float> v(size_t(n) * n * n);
  parallel_for_each(pf, size_t(n), [&](size_t zi) {
    const int z = int(zi);
    for (int y = 0; y < n; ++y)
      for (int x = 0; x < n; ++x)
        v[(size_t(z) * n + y) * n + x] = marschner_lobb(unit(x, n), unit(y, n), unit(z, n));
  });
  return finish(n, n, n, VoxelType::kFloat32, Vec3(2.0f / float(n - 1)), v);
}

std::shared_ptr<const VolumeGrid> make_shepp_logan(int nx, int ny, int nz, const ParallelFor& pf) {
  VoxelBuffer<uint16_t> v(size_t(nx) * ny * nz);
  parallel_for_each(pf, size_t(nz), [&](size_t zi) {
    const int z = int(zi);
    std::vector<float> row(static_cast<size_t>(nx));
    const float pz = unit(z, nz);
    for (int y = 0; y < ny; ++y) {
      std::fill(row.begin(), row.end(), 0.0f);
      const float py = unit(y, ny);
      for (const Ellipsoid& e : kHead) {
        // Inside when (R^T (p - c)) scaled by the axes has length <= 1, R a rotation about z:
        // a quadratic in x along the row, so each ellipsoid adds its density over one span.
        const float ph = e.phi_deg * float(kPi / 180.0), cs = std::cos(ph), sn = std::sin(ph);
        const float dy = py - e.y0, dz = (pz - e.z0) / e.c;
        // u = (cs dx + sn dy) / a, w = (-sn dx + cs dy) / b with dx = x - x0.
        const float qa = cs * cs / (e.a * e.a) + sn * sn / (e.b * e.b);
        const float qb = 2.0f * dy * (cs * sn / (e.a * e.a) - sn * cs / (e.b * e.b));
        const float qc = dy * dy * (sn * sn / (e.a * e.a) + cs * cs / (e.b * e.b)) + dz * dz - 1.0f;
        const float disc = qb * qb - 4.0f * qa * qc;
        if (disc < 0.0f) continue;
        const float s = std::sqrt(disc);
        const float x_lo = e.x0 + (-qb - s) / (2.0f * qa), x_hi = e.x0 + (-qb + s) / (2.0f * qa);
        const int i_lo = std::max(0, int(std::ceil((x_lo + 1.0f) * 0.5f * float(nx - 1))));
        const int i_hi = std::min(nx - 1, int(std::floor((x_hi + 1.0f) * 0.5f * float(nx - 1))));
        for (int i = i_lo; i <= i_hi; ++i) row[size_t(i)] += e.density;
      }
      uint16_t* out = v.data() + (size_t(z) * ny + y) * nx;
      for (int i = 0; i < nx; ++i) out[i] = uint16_t(std::clamp(std::lround(row[size_t(i)] * 4000.0f), 0L, 65535L));
    }
  });
  for (int pass = 0; pass < 2; ++pass) smooth_121(v.data(), nx, ny, nz, pf);  // a Gaussian of about one voxel
  return finish(nx, ny, nz, VoxelType::kUint16, Vec3(2.0f / float(nx - 1), 2.0f / float(ny - 1), 2.0f / float(nz - 1)),
                v);
}

std::shared_ptr<const VolumeGrid> make_sphere_distance(int n, const ParallelFor& pf) {
  VoxelBuffer<float> v(size_t(n) * n * n);
  const float c = 0.5f * float(n - 1);
  parallel_for_each(pf, size_t(n), [&](size_t zi) {
    const int z = int(zi);
    for (int y = 0; y < n; ++y)
      for (int x = 0; x < n; ++x)
        v[(size_t(z) * n + y) * n + x] = std::sqrt((x - c) * (x - c) + (y - c) * (y - c) + (z - c) * (z - c));
  });
  return finish(n, n, n, VoxelType::kFloat32, Vec3(1.0f), v);
}

// Built-in volumes are for tests and demos: at most 1 GiB (the Visible-Female-sized phantom is 909 MB).
constexpr uint64_t kMaxGeneratedBytes = uint64_t(1) << 30;

bool is_builtin_volume_name(const std::string& name) { return name.rfind("volume:", 0) == 0; }

Result<std::shared_ptr<const VolumeGrid>> make_builtin_volume(const std::string& name, const ParallelFor& pf) {
  const size_t colon = name.find(':', 7);
  const std::string kind = name.substr(7, colon == std::string::npos ? std::string::npos : colon - 7);
  const std::string size = colon == std::string::npos ? "" : name.substr(colon + 1);
  const auto bad = [&](const std::string& why) {
    return Error{name + ": " + why + " (expected volume:marschner-lobb:N, volume:shepp-logan:N or NXxNYxNZ, volume:sphere:N; N in 2..4096)"};
  };
  int d[3] = {0, 0, 0}, count = 0;
  size_t p = 0;
  while (true) {  // sides separated by 'x', each 1 to 4 digits
    size_t q = p;
    while (q < size.size() && size[q] >= '0' && size[q] <= '9' && q - p < 5) ++q;
    if (q == p || q - p > 4 || count == 3) return bad("size '" + size + "' is not N or NXxNYxNZ");
    d[count++] = std::stoi(size.substr(p, q - p));
    if (q == size.size()) break;
    if (size[q] != 'x') return bad("size '" + size + "' is not N or NXxNYxNZ");
    p = q + 1;
  }
  if (count == 2) return bad("size '" + size + "' has two sides");
  if (count == 1) d[1] = d[2] = d[0];
  for (int k = 0; k < 3; ++k)
    if (d[k] < 2 || d[k] > 4096) return bad("size '" + size + "' outside 2..4096");
  const uint64_t bytes = uint64_t(d[0]) * uint64_t(d[1]) * uint64_t(d[2]) * (kind == "shepp-logan" ? 2 : 4);
  if (bytes > kMaxGeneratedBytes) return bad("size '" + size + "' makes more than 1 GiB of voxels");
  if (kind == "shepp-logan") return make_shepp_logan(d[0], d[1], d[2], pf);
  if (count == 3) return bad("only shepp-logan takes three sides");
  if (kind == "marschner-lobb") return make_marschner_lobb(d[0], pf);
  if (kind == "sphere") return make_sphere_distance(d[0], pf);
  return bad("unknown kind '" + kind + "'");
}

}  // namespace frameless
