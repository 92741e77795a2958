// Small scenes built in code for the shading, surface, render_sample and scale tests (test thread).
#pragma once
#include <memory>

#include "core/scene/scene.h"
#include "core/shading/shading.h"

namespace frameless::testing {

// Quad a-b-c-d (counter-clockwise seen from the side its normal cross(b-a, c-a) points to).
inline void add_quad(Geometry& g, Vec3 a, Vec3 b, Vec3 c, Vec3 d, uint16_t material) {
  const uint32_t base = uint32_t(g.positions.size());
  for (const Vec3& p : {a, b, c, d}) g.positions.push_back(p);
  g.triangles.push_back(UVec3(base, base + 1, base + 2));
  g.triangles.push_back(UVec3(base, base + 2, base + 3));
  g.triangle_material.push_back(material);
  g.triangle_material.push_back(material);
}

// Horizontal square at height y, half size h, centred on (cx, cz); normal up or down.
inline void add_horizontal_quad(Geometry& g, float y, float h, uint16_t material, bool up = true,
                                float cx = 0.0f, float cz = 0.0f) {
  const Vec3 a(cx - h, y, cz - h), b(cx - h, y, cz + h), c(cx + h, y, cz + h), d(cx + h, y, cz - h);
  if (up)
    add_quad(g, a, b, c, d, material);
  else
    add_quad(g, d, c, b, a, material);
}

// Whitted radiance along the ray from org towards dir (normalized here), a camera ray.
inline Vec3 radiance_along(const Scene& s, const Vec3& org, const Vec3& dir) {
  Ray r;
  r.org = org;
  r.dir = glm::normalize(dir);
  return trace_radiance(s, r, 0, Vec3(1.0f), nullptr);
}

inline void add_sphere(Geometry& g, Vec3 center, float radius, uint16_t material) {
  g.spheres.push_back(Sphere{center, radius});
  g.sphere_material.push_back(material);
}

inline Material make_material(MaterialClass cls) {
  Material m;
  m.cls = cls;
  return m;
}

// An empty scene with no ambient, black background, no lights and no pruning surprises.
inline std::unique_ptr<Scene> make_empty_scene() {
  auto s = std::make_unique<Scene>();
  s->ambient.kind = AmbientKind::kNone;
  s->settings.background = Vec3(0.0f);
  return s;
}

}  // namespace frameless::testing
