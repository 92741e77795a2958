#include "core/scene.h"

#include "core/scene_analysis.h"
#include "core/soft_shadow.h"
#include "core/texturing.h"

namespace frameless {

const char* material_class_name(MaterialClass c) {
  switch (c) {
    case MaterialClass::kDiffuse: return "diffuse";
    case MaterialClass::kMetal: return "metal";
    case MaterialClass::kDielectric: return "dielectric";
    case MaterialClass::kPolished: return "polished";
  }
  return "unknown";
}

const char* shadow_mode_name(ShadowMode m) {
  switch (m) {
    case ShadowMode::kHard: return "hard";
    case ShadowMode::kSoft: return "soft";
    case ShadowMode::kArea: return "area";
  }
  return "unknown";
}

void finalize_scene(Scene& scene, const AccelConfig& config) {
  scene.features = analyse_scene(scene);
  // Edge adjacency only where soft shadows will read it (skip what a scene doesn't need); it is
  // built before the accel so the build permutes it with the triangles.
  if (scene.features.has_soft_lights && scene.geometry.num_triangles() > 0) {
    if (scene.geometry.triangle_opposite.size() != scene.geometry.triangles.size())
      build_triangle_adjacency(scene.geometry);
  } else {
    scene.geometry.triangle_opposite = {};
  }
  scene.accel.build(scene.geometry, config);
  install_alpha_test(scene);
}

void set_shadow_settings(Scene& scene, ShadowMode mode, int samples, bool transparent) {
  scene.settings.shadows = mode;
  scene.settings.shadow_samples = samples;
  scene.settings.transparent_shadows = transparent;
  scene.features = analyse_scene(scene);
  // Adjacency is per triangle in the BVH's current order, so it can be built after the build.
  if (scene.features.has_soft_lights &&
      scene.geometry.triangle_opposite.size() != scene.geometry.triangles.size())
    build_triangle_adjacency(scene.geometry);
}

bool scene_bounds(const Geometry& g, Vec3& lo, Vec3& hi) {
  lo = Vec3(kInfinity);
  hi = Vec3(-kInfinity);
  for (const UVec3& t : g.triangles)
    for (int k = 0; k < 3; ++k) {
      lo = glm::min(lo, g.positions[t[k]]);
      hi = glm::max(hi, g.positions[t[k]]);
    }
  for (const Sphere& s : g.spheres) {
    lo = glm::min(lo, s.center - Vec3(s.radius));
    hi = glm::max(hi, s.center + Vec3(s.radius));
  }
  return g.num_primitives() > 0;
}

}  // namespace frameless
