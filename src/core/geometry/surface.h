// Hit-point reconstruction and robust ray-origin offsetting; pure functions, any thread.
#pragma once
#include "core/geometry/geometry.h"
#include "core/geometry/ray.h"

namespace frameless {

struct SurfacePoint {
  Vec3 p{0.0f};   // hit position, computed from the primitive (not org + t dir) for precision
  Vec3 ng{0.0f};  // unit geometric normal, facing against the incoming ray
  Vec3 ns{0.0f};  // unit shading normal, same hemisphere as ng
  bool front_face = true;  // the ray hit the outward side
  uint16_t material = 0;
  uint32_t prim = kInvalidId;  // the primitive hit (Hit::prim)
  // Largest coordinate magnitude of the primitive (vertices, or sphere centre + radius): the
  // rounding of any intersection test with it scales with this, so origin offsets must too.
  float scale = 0.0f;
};

SurfacePoint surface_point(const Geometry& geom, const Ray& ray, const Hit& hit);

// The surface point of a hit at distance t on sphere s (static or moving).
SurfacePoint sphere_surface_point(const Sphere& s, uint16_t material, const Ray& ray, float t);

// Offsets p along n by an amount proportional to p's floating-point magnitude so that a ray
// leaving p in n's hemisphere cannot re-hit the surface, at any scene scale (Waechter & Binder 2019).
// scale: SurfacePoint::scale of the primitive p lies on (0 when unknown: p's own magnitude).
Vec3 offset_ray_origin(const Vec3& p, const Vec3& n, float scale = 0.0f);

}  // namespace frameless
