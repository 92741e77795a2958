// The grid's trilinear interpolant at a point: the cell holding it (clamped into the grid), its
// eight voxels, and the value and gradient there, in float (the volume shader) or double
// (isosurface roots and normals). One fetch serves both value and gradient. Any thread.
#pragma once
#include <algorithm>
#include <cmath>

#include "core/volume/volume_grid.h"

namespace frameless {

template <class R>
struct TrilinearCell {
  int x = 0, y = 0, z = 0;  // the cell's first voxel
  R u = 0, v = 0, w = 0;    // the point within the cell, each in [0, 1]
  R c[8] = {};              // voxel (x + i, y + j, z + k) at c[i + 2j + 4k]
};

// The cell holding index-space point p (the last cell for points on the grid's far faces); `vox`
// is the grid's reader (with_voxels).
template <class R, class Voxels>
inline TrilinearCell<R> cell_at(const Voxels& vox, const VolumeGrid& g, const Vec3& p) {
  TrilinearCell<R> k;
  k.x = std::clamp(int(std::floor(p.x)), 0, g.nx - 2);
  k.y = std::clamp(int(std::floor(p.y)), 0, g.ny - 2);
  k.z = std::clamp(int(std::floor(p.z)), 0, g.nz - 2);
  k.u = R(p.x) - R(k.x), k.v = R(p.y) - R(k.y), k.w = R(p.z) - R(k.z);
  vox.corners(k.x, k.y, k.z, k.c);
  return k;
}

template <class R>
inline R lerp_cell(R a, R b, R s) {
  return a + s * (b - a);
}

template <class R>
inline R cell_value(const TrilinearCell<R>& k) {
  const R c00 = lerp_cell(k.c[0], k.c[1], k.u), c10 = lerp_cell(k.c[2], k.c[3], k.u);
  const R c01 = lerp_cell(k.c[4], k.c[5], k.u), c11 = lerp_cell(k.c[6], k.c[7], k.u);
  return lerp_cell(lerp_cell(c00, c10, k.v), lerp_cell(c01, c11, k.v), k.w);
}

// The gradient per index unit: each axis's differences, bilinear in the other two.
template <class R>
inline Vec3 cell_gradient(const TrilinearCell<R>& k) {
  const R* c = k.c;
  const R gx = lerp_cell(lerp_cell(c[1] - c[0], c[3] - c[2], k.v),
                         lerp_cell(c[5] - c[4], c[7] - c[6], k.v), k.w);
  const R gy = lerp_cell(lerp_cell(c[2] - c[0], c[3] - c[1], k.u),
                         lerp_cell(c[6] - c[4], c[7] - c[5], k.u), k.w);
  const R gz = lerp_cell(lerp_cell(c[4] - c[0], c[5] - c[1], k.u),
                         lerp_cell(c[6] - c[2], c[7] - c[3], k.u), k.v);
  return Vec3(float(gx), float(gy), float(gz));
}

}  // namespace frameless
