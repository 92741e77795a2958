// Ablation variants and moved copies of a loaded scene, for benchmarks and precision tests.
#include "core/scenes/scene_variants.h"

#include "core/scene/scene_finalize.h"
#include "core/shading/optics.h"

namespace frameless {

bool apply_scene_variant(Scene& scene, const std::string& variant) {
  if (variant == "no-lights") {
    scene.lights.clear();
  } else if (variant == "no-dielectric") {
    for (Material& m : scene.materials)
      if (m.cls == MaterialClass::kDielectric) {
        m.cls = MaterialClass::kPolished;
        m.kd = Vec3(0.6f);
        m.r0 = Vec3(r0_from_ior(m.ior));
      }
  } else if (variant == "no-highlights") {
    for (Material& m : scene.materials) {
      m.kh = Vec3(0.0f);
      if (m.cls == MaterialClass::kMetal) {
        m.cls = MaterialClass::kPolished;  // a metal's highlight is its ks: keep a mirror coat
        m.kd = 0.5f * m.ks;
        m.r0 = m.ks;
      }
    }
  } else {
    return false;
  }
  scene.name += "/" + variant;
  finalize_scene(scene);
  return true;
}

void translate_scene(Scene& scene, const Vec3& offset) {
  for (Vec3& p : scene.geometry.positions) p += offset;
  for (Sphere& s : scene.geometry.spheres) s.center += offset;
  for (DynamicObject& o : scene.dynamic) o.sphere.center += offset;
  for (Light& l : scene.lights) l.position += offset;  // directional lights have no position
  scene.camera.eye += offset;
  scene.camera.look += offset;
  finalize_scene(scene);
}

}  // namespace frameless
