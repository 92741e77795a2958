// Hit-point reconstruction and ray-origin offsets: points on the primitive, normals facing the
// ray, and no self-intersection at scales 1e-4, 1 and 1e6 (and far from the origin).
#include "core/geometry/surface.h"

#include <gtest/gtest.h>

#include <cmath>

#include "core/base/rng.h"
#include "core/scene/scene.h"
#include "core/scene/scene_finalize.h"
#include "shading_scenes.h"

namespace frameless {
namespace {

using testing::add_sphere;

Vec3 random_unit(Rng& rng) {
  for (;;) {
    const Vec3 v(2.0f * rng.next_float() - 1.0f, 2.0f * rng.next_float() - 1.0f,
                 2.0f * rng.next_float() - 1.0f);
    const float l2 = glm::dot(v, v);
    if (l2 > 1e-4f && l2 <= 1.0f) return v / std::sqrt(l2);
  }
}

TEST(SurfacePoint, SphereHitIsProjectedOntoTheSphere) {
  Geometry g;
  add_sphere(g, Vec3(3.0f, -2.0f, 1.0f), 2.0f, 7);
  Ray r;
  r.org = Vec3(3.0f, -2.0f, 10.0f);
  r.dir = Vec3(0.0f, 0.0f, -1.0f);
  Hit h;
  h.prim = 0;
  h.t = 7.01f;  // a sloppy t: the reconstruction must not trust it
  const SurfacePoint sp = surface_point(g, r, h);
  EXPECT_NEAR(glm::length(sp.p - g.spheres[0].center), 2.0f, 1e-6f);
  EXPECT_TRUE(sp.front_face);
  EXPECT_NEAR(sp.ng.z, 1.0f, 1e-6f);
  EXPECT_EQ(sp.ns, sp.ng);
  EXPECT_EQ(sp.material, 7);
  // From inside, the normal turns toward the ray (inward) and front_face is false.
  r.org = g.spheres[0].center;
  h.t = 2.0f;
  const SurfacePoint in = surface_point(g, r, h);
  EXPECT_FALSE(in.front_face);
  EXPECT_NEAR(in.ng.z, 1.0f, 1e-6f);
  EXPECT_NEAR(in.p.z, -1.0f, 1e-6f);
}

TEST(SurfacePoint, TriangleUsesBarycentricsAndFacesTheRay) {
  Geometry g;
  g.positions = {Vec3(0.0f), Vec3(2.0f, 0.0f, 0.0f), Vec3(0.0f, 2.0f, 0.0f)};
  g.triangles = {UVec3(0, 1, 2)};
  g.triangle_material = {3};
  Ray r;
  r.org = Vec3(0.5f, 0.5f, 5.0f);
  r.dir = Vec3(0.0f, 0.0f, -1.0f);
  Hit h;
  h.prim = 0;
  h.t = 123.0f;  // ignored for triangles
  h.u = 0.25f;
  h.v = 0.25f;
  SurfacePoint sp = surface_point(g, r, h);
  EXPECT_EQ(sp.p, Vec3(0.5f, 0.5f, 0.0f));
  EXPECT_TRUE(sp.front_face);
  EXPECT_EQ(sp.ng, Vec3(0.0f, 0.0f, 1.0f));
  EXPECT_EQ(sp.material, 3);
  r.org.z = -5.0f;
  r.dir.z = 1.0f;
  sp = surface_point(g, r, h);
  EXPECT_FALSE(sp.front_face);
  EXPECT_EQ(sp.ng, Vec3(0.0f, 0.0f, -1.0f));
  // Vertex normals are interpolated and turned with the geometric normal.
  g.normals = {glm::normalize(Vec3(1.0f, 0.0f, 1.0f)), Vec3(0.0f, 0.0f, 1.0f),
               Vec3(0.0f, 0.0f, 1.0f)};
  sp = surface_point(g, r, h);
  EXPECT_LT(sp.ns.z, 0.0f);
  EXPECT_LT(sp.ns.x, 0.0f);
  EXPECT_NEAR(glm::length(sp.ns), 1.0f, 1e-6f);
}

TEST(SurfacePoint, DegeneratePrimitivesGiveFiniteNormals) {
  Geometry g;
  g.positions = {Vec3(1.0f), Vec3(1.0f), Vec3(1.0f)};  // zero area
  g.triangles = {UVec3(0, 1, 2)};
  add_sphere(g, Vec3(0.0f), 0.0f, 0);  // zero radius
  Ray r;
  r.org = Vec3(0.0f, 0.0f, 5.0f);
  r.dir = Vec3(0.0f, 0.0f, -1.0f);
  for (uint32_t prim : {0u, 1u}) {
    Hit h;
    h.prim = prim;
    h.t = 5.0f;
    const SurfacePoint sp = surface_point(g, r, h);
    EXPECT_TRUE(is_finite(sp.p) && is_finite(sp.ng) && is_finite(sp.ns)) << prim;
    EXPECT_NEAR(glm::length(sp.ng), 1.0f, 1e-6f);
  }
}

TEST(OffsetRayOrigin, MovesAlongTheNormalBySmallRelativeAmounts) {
  Rng rng(42);
  for (float scale : {1e-4f, 1.0f, 1e3f, 1e6f}) {
    for (int i = 0; i < 2000; ++i) {
      const Vec3 p = scale * (4.0f * random_unit(rng)) * rng.next_float();
      const Vec3 n = random_unit(rng);
      const Vec3 q = offset_ray_origin(p, n);
      const float m = std::max(std::fabs(p.x), std::max(std::fabs(p.y), std::fabs(p.z)));
      EXPECT_GT(glm::dot(q - p, n), 0.0f) << "scale " << scale;
      EXPECT_LE(glm::length(q - p), 1e-5f * m + 1e-30f) << "scale " << scale;
    }
  }
  // Even the exact origin moves.
  EXPECT_GT(offset_ray_origin(Vec3(0.0f), Vec3(0.0f, 1.0f, 0.0f)).y, 0.0f);
  // An axis-aligned normal moves only its own coordinate.
  const Vec3 q = offset_ray_origin(Vec3(1e5f, 1e5f, 1e5f), Vec3(0.0f, -1.0f, 0.0f));
  EXPECT_EQ(q.x, 1e5f);
  EXPECT_LT(q.y, 1e5f);
  EXPECT_EQ(q.z, 1e5f);
}

// Rays leaving random points of a sphere or a triangle into the outer hemisphere (reflection,
// shadow) must not hit that primitive again; rays entering the sphere must reach its far side.
// The same rays started from the unoffset point do self-intersect, so the test has power.
struct SelfHitCounts {
  int outward_hits = 0;
  int inward_short = 0;
  int outward_hits_unoffset = 0;
};

SelfHitCounts count_self_hits(float scale, Vec3 translate, bool sphere, uint64_t seed) {
  Scene scene;
  if (sphere) {
    add_sphere(scene.geometry, translate + scale * Vec3(0.3f, -0.2f, 0.1f), scale, 0);
  } else {
    scene.geometry.positions = {translate + scale * Vec3(-1.3f, -0.4f, -1.0f),
                                translate + scale * Vec3(1.1f, 0.3f, -0.9f),
                                translate + scale * Vec3(0.2f, 0.5f, 1.4f)};
    scene.geometry.triangles = {UVec3(0, 1, 2)};
    scene.geometry.triangle_material = {0};
  }
  scene.materials.push_back(Material{});
  finalize_scene(scene);
  Vec3 lo, hi;
  geometry_bounds(scene.geometry, lo, hi);
  const Vec3 center = 0.5f * (lo + hi);
  Rng rng(seed);
  SelfHitCounts c;
  for (int i = 0; i < 3000; ++i) {
    // A primary ray from a random point outside toward a random point near the centre.
    Ray r;
    r.org = center + 5.0f * scale * random_unit(rng);
    r.dir = glm::normalize(center + 0.5f * scale * random_unit(rng) - r.org);
    Hit h;
    if (!scene.accel.intersect(r, h)) continue;
    const SurfacePoint sp = surface_point(scene.geometry, r, h);
    Vec3 d = random_unit(rng);
    if (glm::dot(d, sp.ng) < 0.0f) d = -d;
    Ray out;
    out.org = offset_ray_origin(sp.p, sp.ng, sp.scale);
    out.dir = d;
    c.outward_hits += scene.accel.occluded(out);
    out.org = sp.p;
    c.outward_hits_unoffset += scene.accel.occluded(out);
    if (sphere) {
      Ray in;
      in.org = offset_ray_origin(sp.p, -sp.ng, sp.scale);
      in.dir = -d;
      Hit hin;
      // The far side of the sphere lies at least a chord away; a self-hit would be ~0.
      const bool hit_far = scene.accel.intersect(in, hin) && hin.t > 1e-3f * scale;
      c.inward_short += !hit_far && glm::dot(-d, sp.ng) < -1e-3f;
    }
  }
  return c;
}

TEST(OffsetRayOrigin, NoSelfIntersectionAtAnyScale) {
  int unoffset_total = 0;
  uint64_t seed = 1;
  for (float scale : {1e-4f, 1.0f, 1e6f}) {
    for (Vec3 translate : {Vec3(0.0f), Vec3(1e5f, -1e5f, 1e5f) * scale}) {
      for (bool sphere : {true, false}) {
        const SelfHitCounts c = count_self_hits(scale, translate, sphere, seed++);
        EXPECT_EQ(c.outward_hits, 0) << "scale " << scale << " sphere " << sphere;
        EXPECT_EQ(c.inward_short, 0) << "scale " << scale << " sphere " << sphere;
        unoffset_total += c.outward_hits_unoffset;
      }
    }
  }
  EXPECT_GT(unoffset_total, 100);
}

}  // namespace
}  // namespace frameless
