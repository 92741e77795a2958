// A triangle mesh of an isosurface (the seed's case for tracing spline patches directly, made for
// volumes: `bench volume` traces Parker's exact isosurface against this mesh of it through the
// BVH). Marching tetrahedra: each cell is cut into six tetrahedra around its main diagonal, and
// each tetrahedron the isovalue crosses gives one or two triangles whose corners interpolate the
// crossing linearly along the tetrahedron's edges (no case table; no ambiguous faces). Corners
// carry the interpolant's gradient as their normal. Grid index space; any thread.
#pragma once
#include <vector>

#include "core/volume/macrocells.h"

namespace frameless {

struct IsoMesh {
  std::vector<Vec3> positions;  // three per triangle, index space
  std::vector<Vec3> normals;    // one per position, pointing out of the inside
};

// The mesh of `iso` (inside: values above it when inside_above), skipping the macrocells whose
// range misses it; a z-slab of macrocells per task of the caller's executor (empty: serial).
IsoMesh marching_tetrahedra(const VolumeGrid& grid, const Macrocells& cells, float iso, bool inside_above,
                            const ParallelFor& pf = {});

}  // namespace frameless
