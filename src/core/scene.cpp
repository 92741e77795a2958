#include "core/scene.h"

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
  SceneFeatures& f = scene.features;
  f = {};
  f.has_lights = !scene.lights.empty();
  f.has_spheres = !scene.geometry.spheres.empty();
  f.has_triangles = !scene.geometry.triangles.empty();
  f.has_vertex_normals = !scene.geometry.normals.empty();
  for (const Material& m : scene.materials) {
    f.has_dielectric |= m.cls == MaterialClass::kDielectric;
    f.has_reflection |= m.cls != MaterialClass::kDiffuse;
    f.has_highlights |= m.cls != MaterialClass::kDiffuse && glm::dot(m.kh, m.kh) > 0.0f;
    f.has_highlights |= m.cls == MaterialClass::kMetal && glm::dot(m.ks, m.ks) > 0.0f;
  }
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
