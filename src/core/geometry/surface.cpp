// Hit-point reconstruction from the primitive and robust origin offsets (Waechter & Binder 2019).
#include "core/geometry/surface.h"

#include <bit>
#include <cmath>
#include <cstdint>

namespace frameless {

namespace {

// Unit vector or, for a degenerate input, the fallback (keeps NaN out of shading).
Vec3 normalize_or(const Vec3& v, const Vec3& fallback) {
  const float len2 = glm::dot(v, v);
  if (!(len2 > 0.0f) || !(len2 < kInfinity)) return fallback;
  return v * (1.0f / std::sqrt(len2));
}

}  // namespace

SurfacePoint surface_point(const Geometry& geom, const Ray& ray, const Hit& hit) {
  SurfacePoint sp;
  sp.prim = hit.prim;
  const Vec3 back = -ray.dir;
  const uint32_t ntri = geom.num_triangles();
  if (hit.prim < ntri) {
    const UVec3 tri = geom.triangles[hit.prim];
    const Vec3 p0 = geom.positions[tri.x], p1 = geom.positions[tri.y], p2 = geom.positions[tri.z];
    const Vec3 e1 = p1 - p0, e2 = p2 - p0;
    // Barycentric reconstruction: edges are exact for nearby vertices, so p lies on the plane
    // to within half an ulp per component, unlike org + t dir whose error grows with t.
    sp.p = p0 + (hit.u * e1 + hit.v * e2);
    const Vec3 ng = normalize_or(glm::cross(e1, e2), back);
    sp.front_face = glm::dot(ng, ray.dir) < 0.0f;
    sp.ng = sp.front_face ? ng : -ng;
    if (!geom.normals.empty()) {
      const float w0 = 1.0f - hit.u - hit.v;
      const Vec3 ns =
          w0 * geom.normals[tri.x] + hit.u * geom.normals[tri.y] + hit.v * geom.normals[tri.z];
      sp.ns = normalize_or(sp.front_face ? ns : -ns, sp.ng);
      // An interpolated normal may tip below the true surface; fall back to the geometric one.
      if (glm::dot(sp.ns, sp.ng) <= 0.0f) sp.ns = sp.ng;
    } else {
      sp.ns = sp.ng;
    }
    sp.material = geom.triangle_material.empty() ? 0 : geom.triangle_material[hit.prim];
    const Vec3 mag = glm::max(glm::abs(p0), glm::max(glm::abs(p1), glm::abs(p2)));
    sp.scale = max_component(mag);
  } else if (hit.prim >= geom.first_patch()) {
    // Spline patch: position and normal from the patch at the root Broyden found (u, v).
    const uint32_t i = hit.prim - geom.first_patch();
    const PatchSurface& ps = geom.patches[i];
    sp.p = bezier_eval(ps.patch(), hit.u, hit.v);
    const Vec3 n = normalize_or(bezier_normal(ps.patch(), hit.u, hit.v), back);
    sp.front_face = glm::dot(n, ray.dir) < 0.0f;
    sp.ng = sp.front_face ? n : -n;
    sp.ns = sp.ng;
    sp.material = i < geom.patch_material.size() ? geom.patch_material[i] : 0;
    sp.scale = max_component(glm::max(glm::abs(ps.lo()), glm::abs(ps.hi())));
  } else {
    const uint32_t i = hit.prim - ntri;
    sp = sphere_surface_point(geom.spheres[i], geom.sphere_material.empty() ? 0 : geom.sphere_material[i],
                              ray, hit.t);
    sp.prim = hit.prim;
  }
  return sp;
}

SurfacePoint sphere_surface_point(const Sphere& s, uint16_t material, const Ray& ray, float t) {
  SurfacePoint sp;
  const Vec3 n = normalize_or(ray.org + t * ray.dir - s.center, -ray.dir);
  // Project back onto the sphere: the error is then that of center + radius * n only.
  sp.p = s.center + s.radius * n;
  sp.front_face = glm::dot(n, ray.dir) < 0.0f;
  sp.ng = sp.front_face ? n : -n;
  sp.ns = sp.ng;
  sp.material = material;
  sp.scale = max_component(glm::abs(s.center)) + std::fabs(s.radius);
  return sp;
}

// Waechter & Binder's integer-ULP offset, with documented changes:
//  * kIntScale is 16, not 256, with a minimum of one ULP on every non-zero normal component:
//    256 ULPs (sized for GPU instance transforms) move a point two units at 1e5, which visibly
//    shrinks contact shadows (scale_test fails with it); 1..16 ULPs still exceed the half-ULP
//    reconstruction error above plus the rounding of the sphere and watertight triangle tests.
//  * Their absolute "near the origin" threshold (1/32) and offset (1/65536) assume a scene of
//    unit size. Here the reference magnitude m is the larger of |p|'s largest coordinate and the
//    primitive's own coordinate scale (an intersection test rounds relative to the vertices, not
//    to p); coordinates within a factor 2 of m get integer ULPs, smaller ones (whose ULPs are too
//    fine to matter) a float offset of about 16 ULPs of m. So the rule is free of any unit.
Vec3 offset_ray_origin(const Vec3& p, const Vec3& n, float scale) {
  constexpr float kIntScale = 16.0f;
  constexpr float kFloatScale = 16.0f * 0x1.0p-23f;  // about 16 ULPs of m
  constexpr float kTinyScale = 0x1.0p-100f;          // p and scale both zero: any unit is a guess
  const float big = std::max(max_component(glm::abs(p)), std::fabs(scale));
  const float m = big > kTinyScale ? big : kTinyScale;  // NaN (never expected) becomes kTinyScale
  const float small_offset = kFloatScale * m;
  Vec3 out = p;
  for (int i = 0; i < 3; ++i) {
    const float ni = n[i];
    if (!(ni != 0.0f)) continue;  // zero or NaN: no offset along this axis
    const float pi = p[i];
    if (std::fabs(pi) < 0.5f * m) {
      out[i] = pi + ni * small_offset;
    } else {
      const int32_t ulps = int32_t(std::ceil(kIntScale * std::fabs(ni)));
      // Moving away from zero adds to the magnitude bits; toward zero subtracts.
      const int32_t delta = ((pi < 0.0f) == (ni < 0.0f)) ? ulps : -ulps;
      out[i] = std::bit_cast<float>(std::bit_cast<int32_t>(pi) + delta);
    }
  }
  return out;
}

}  // namespace frameless
