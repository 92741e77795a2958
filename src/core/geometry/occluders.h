// Occluder data soft shadows need beyond the primitives (edge adjacency, patch shadow grids);
// built on the loading thread by finalize_scene, read-only afterwards.
#pragma once
#include "core/geometry/geometry.h"

namespace frameless {

// Builds Geometry::triangle_opposite (edge adjacency by vertex position) for soft shadows.
void build_triangle_adjacency(Geometry& geom);

// Builds Geometry::patch_shadow_grid (each patch's occluder for soft shadows), in the patches'
// current order.
void build_patch_shadow_grid(Geometry& geom);

}  // namespace frameless
