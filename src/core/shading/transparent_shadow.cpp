// Transparent shadows: a shadow ray through dielectrics keeps k_t at each interface it crosses
// and Beer's law inside, instead of being blocked (RTRT's glass). Pure, any thread.
#include <cmath>

#include "core/scene/scene_intersect.h"
#include "core/shading/optics.h"
#include "core/shading/soft_shadow.h"

namespace frameless {

Vec3 shadow_transmittance(const Scene& scene, const Ray& ray, bool ignore_opaque,
                          const DynamicFrame* frame) {
  Vec3 tr(1.0f);
  Ray r = ray;
  // Where the current stretch inside a dielectric began: the ray's origin when it starts inside.
  Vec3 entered = ray.org;
  const Vec3 end = std::isfinite(ray.tmax) ? ray.org + ray.tmax * ray.dir : Vec3(0.0f);
  auto absorb = [&](const MaterialParams& m, const Vec3& from, const Vec3& to) {
    const float len = glm::length(to - from);
    for (int c = 0; c < 3; ++c) tr[c] *= std::exp(-m.extinction[c] * len);
  };
  const MaterialParams* inside = nullptr;
  // The shadow ray is not bent at interfaces (the usual approximation of transparent shadows).
  for (int crossings = 0; crossings < 64; ++crossings) {
    Hit h;
    if (!scene_intersect(scene, frame, r, h)) {
      // Ends inside a dielectric (a light within glass): absorb up to the end of the ray.
      if (inside && std::isfinite(ray.tmax)) absorb(*inside, entered, end);
      return inside && !std::isfinite(ray.tmax) ? Vec3(0.0f) : tr;
    }
    const SurfacePoint sp = scene_surface_point(scene, frame, r, h);
    const MaterialParams& m = frame_material(scene, frame, sp.material);
    if (m.cls == MaterialClass::kDielectric) {
      // A back-face hit leaves the medium (even when the ray started inside it).
      if (!sp.front_face) absorb(m, inside ? entered : ray.org, sp.p);
      // k_t = 1 - k_s at this crossing (Schlick, as in shading).
      const float cos_i = std::fabs(glm::dot(r.dir, sp.ng));
      tr *= 1.0f - schlick(cos_i, r0_from_ior(m.ior));
      inside = sp.front_face ? &m : nullptr;
      entered = sp.p;
    } else if (!ignore_opaque) {
      return Vec3(0.0f);
    }
    if (max_component(tr) <= 0.0f) return Vec3(0.0f);
    // Continue from just beyond the surface, keeping the same end point.
    r.org = offset_ray_origin(sp.p, -sp.ng, sp.scale);
    r.tmin = 0.0f;
    r.tmax = std::isfinite(ray.tmax) ? std::max(0.0f, glm::dot(end - r.org, r.dir)) : kInfinity;
    if (!(r.tmax > 0.0f)) return tr;
  }
  return tr;
}

}  // namespace frameless
