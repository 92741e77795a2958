// Parker's isosurfaces against a mesh of the same isosurface (marching tetrahedra of the same
// data, core/volume/marching_tetrahedra.h) traced by the BVH: the seed's case for tracing
// spline patches directly, made for volumes (`bench volume`).
#pragma once
#include <nlohmann/json.hpp>

#include "core/scene/scene.h"

namespace frameless::bench {

// Meshes the first isosurface of `iso_scene` (the scene's other objects kept), builds its BVH,
// renders w x h at spp on `threads`, and reports triangles, build time, memory (mesh and BVH
// against the volume's data and macrocells), samples/s and the image's RMSE against `iso_rgb`
// (the isosurface's own frame). `mesh_only_json`: the same scene file without the volume.
nlohmann::json compare_with_mesh(const Scene& iso_scene, const std::string& mesh_only_json, const std::string& dir,
                                 int w, int h, int spp, int threads, const std::vector<float>& iso_rgb,
                                 double iso_seconds);

}  // namespace frameless::bench
