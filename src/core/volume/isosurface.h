// Parker et al.'s isosurfaces (Visualization '98): the exact first crossing of a ray with the
// level set of the grid's trilinear interpolant. Each cell on the ray's way, after the macrocells
// have skipped those whose range misses the isovalue, gives a cubic in the ray parameter; its
// first root in the cell is isolated between the cubic's extrema and refined by bisection in
// double precision. All in grid index space (voxel (i, j, k) at point (i, j, k)); any thread.
#pragma once
#include "core/volume/macrocells.h"

namespace frameless {

// The first t in [tmin, tmax] where org + t dir crosses `iso`; false when there is none. With
// `cells` null every cell along the ray is solved (the brute force the tests hold it against).
bool intersect_isosurface(const VolumeGrid& grid, const Macrocells* cells, float iso, const Vec3& org,
                          const Vec3& dir, float tmin, float tmax, float& t);

// The interpolant and its gradient (per index unit) at index-space point p inside the grid.
float trilinear_value(const VolumeGrid& grid, const Vec3& p);
Vec3 trilinear_gradient(const VolumeGrid& grid, const Vec3& p);

// The ray's parameter range inside box [lo, hi]; false when it misses (or the range is empty).
bool clip_to_box(const Vec3& lo, const Vec3& hi, const Vec3& org, const Vec3& dir, float& t0, float& t1);

}  // namespace frameless
