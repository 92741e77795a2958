#include "core/scene.h"

#include "core/scene_analysis.h"

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

void finalize_scene(Scene& scene, const AccelConfig& config) {
  scene.features = analyse_scene(scene);
  scene.accel.build(scene.geometry, config);
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
