// Parker's "ambient based on radiosity solutions" (seed section 3.1.1): an irradiance volume
// (Greger, Shirley, Hubbard and Greenberg 1998, the seed's reference [13]). A grid of points over
// the scene, each holding the irradiance arriving from every direction as order-2 spherical
// harmonics (Ramamoorthi and Hanrahan 2001); the Whitted integrator reads it as l_a(p, n).
// Baked on the loading thread (core/shading/irradiance_bake.h); read-only while rendering.
#pragma once
#include <array>
#include <cstdint>
#include <vector>

#include "core/base/types.h"

namespace frameless {

struct IrradianceVolume {
  Vec3 lo{0.0f}, hi{1.0f};  // the box the grid spans; vertex (i, j, k) at cell centres
  int nx = 1, ny = 1, nz = 1;
  std::vector<std::array<Vec3, 9>> sh;  // irradiance E(n) = sum of sh[c] Y_c(n), per vertex
  std::vector<uint8_t> valid;           // 0: the vertex lies inside geometry (sees back faces)

  size_t index(int i, int j, int k) const { return (size_t(k) * size_t(ny) + size_t(j)) * size_t(nx) + size_t(i); }
  Vec3 vertex(int i, int j, int k) const {
    return lo + (hi - lo) * Vec3((float(i) + 0.5f) / float(nx), (float(j) + 0.5f) / float(ny),
                                 (float(k) + 0.5f) / float(nz));
  }
  // Irradiance at p towards unit normal n: trilinear over the valid vertices around p.
  Vec3 irradiance(const Vec3& p, const Vec3& n) const;
};

// The real spherical harmonics of order <= 2 at unit direction d.
std::array<float, 9> sh_basis(const Vec3& d);

}  // namespace frameless
