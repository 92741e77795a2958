// Reading an irradiance volume: order-2 harmonics evaluated at the normal, blended trilinearly
// over the grid vertices that are not inside geometry.
#include "core/scene/irradiance_volume.h"

#include <algorithm>
#include <cmath>

namespace frameless {

std::array<float, 9> sh_basis(const Vec3& d) {
  return {0.282095f,
          0.488603f * d.y,
          0.488603f * d.z,
          0.488603f * d.x,
          1.092548f * d.x * d.y,
          1.092548f * d.y * d.z,
          0.315392f * (3.0f * d.z * d.z - 1.0f),
          1.092548f * d.x * d.z,
          0.546274f * (d.x * d.x - d.y * d.y)};
}

Vec3 IrradianceVolume::irradiance(const Vec3& p, const Vec3& n) const {
  if (sh.empty()) return Vec3(0.0f);
  // Grid coordinates with vertices at integers.
  const Vec3 g = (p - lo) / (hi - lo) * Vec3(float(nx), float(ny), float(nz)) - Vec3(0.5f);
  const int dims[3] = {nx, ny, nz};
  int i0[3];
  float f[3];
  for (int a = 0; a < 3; ++a) {
    const float c = std::clamp(g[a], 0.0f, float(dims[a] - 1));
    i0[a] = std::min(int(c), std::max(dims[a] - 2, 0));
    f[a] = dims[a] > 1 ? c - float(i0[a]) : 0.0f;
  }
  const std::array<float, 9> y = sh_basis(n);
  Vec3 sum(0.0f), all(0.0f);
  float wsum = 0.0f, wall = 0.0f;
  for (int c = 0; c < 8; ++c) {
    const int i = std::min(i0[0] + (c & 1), nx - 1), j = std::min(i0[1] + ((c >> 1) & 1), ny - 1),
              k = std::min(i0[2] + ((c >> 2) & 1), nz - 1);
    const float w = ((c & 1) ? f[0] : 1.0f - f[0]) * (((c >> 1) & 1) ? f[1] : 1.0f - f[1]) *
                    (((c >> 2) & 1) ? f[2] : 1.0f - f[2]);
    const std::array<Vec3, 9>& s = sh[index(i, j, k)];
    Vec3 e(0.0f);
    for (int b = 0; b < 9; ++b) e += s[size_t(b)] * y[size_t(b)];
    all += w * e;
    wall += w;
    if (valid[index(i, j, k)]) {
      sum += w * e;
      wsum += w;
    }
  }
  // Vertices inside walls would darken what lies beside them: leave them out while any is valid.
  const Vec3 e = wsum > 1e-4f ? sum / wsum : (wall > 0.0f ? all / wall : Vec3(0.0f));
  return glm::max(e, Vec3(0.0f));
}

}  // namespace frameless
