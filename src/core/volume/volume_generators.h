// Built-in volumes for tests and demos (issue 27): "volume:marschner-lobb:N",
// "volume:shepp-logan:N" (or NXxNYxNZ) and "volume:sphere:N".
#pragma once
#include <memory>
#include <string>

#include "core/base/parallel_for.h"
#include "core/volume/volume_grid.h"

namespace frameless {

// Each generator takes the caller's executor for its slices (core/base/parallel_for.h; empty: serial).

// Marschner and Lobb 1994's test signal on [-1, 1]^3, N^3 float voxels (f_M = 6, alpha = 0.25):
// rho = (1 - sin(pi z / 2) + alpha (1 + cos(2 pi f_M cos(pi r / 2)))) / (2 (1 + alpha)), r^2 = x^2 + y^2.
// Its usual isovalue is 0.5.
std::shared_ptr<const VolumeGrid> make_marschner_lobb(int n, const ParallelFor& pf = {});
float marschner_lobb(float x, float y, float z);

// The 3-D Shepp-Logan head phantom (Kak and Slaney's ten ellipsoids, with Toft's higher-contrast
// densities 1, -0.8, -0.2, -0.2, 0.1 x 6) on [-1, 1]^3 as 16-bit CT-like data: density x 4000.
// The skull is the outer shell (about 4000), brain tissue about 800, ventricles 0 to 400.
// Built row by row from each ellipsoid's span (10 s for 512 x 512 x 1734 on two threads), then
// smoothed twice by a [1 2 1] / 4 filter along each axis (about a Gaussian of one voxel, a
// scanner's blur) so its isosurfaces are not staircases.
std::shared_ptr<const VolumeGrid> make_shepp_logan(int nx, int ny, int nz, const ParallelFor& pf = {});

// The distance in voxels from the grid's centre, N^3 float voxels (an isovalue r gives a sphere
// of radius r voxels, up to the trilinear interpolant's error).
std::shared_ptr<const VolumeGrid> make_sphere_distance(int n, const ParallelFor& pf = {});

// "volume:KIND:N" or "volume:shepp-logan:NXxNYxNZ" -> its grid; a one-line error for an unknown
// kind, a side outside 2..4096 or more than 1 GiB of voxels (they are for tests and demos).
Result<std::shared_ptr<const VolumeGrid>> make_builtin_volume(const std::string& name, const ParallelFor& pf = {});
bool is_builtin_volume_name(const std::string& name);  // starts with "volume:"

}  // namespace frameless
