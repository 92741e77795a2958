// Ray/sphere and ray/triangle tests against closed-form answers.
#include <gtest/gtest.h>

#include <cmath>

#include "core/geometry/intersect_sphere.h"
#include "core/geometry/intersect_triangle.h"

namespace frameless {
namespace {

Ray make_ray(Vec3 org, Vec3 dir, float tmin = 0.0f, float tmax = kInfinity) {
  Ray r;
  r.org = org;
  r.dir = dir;
  r.tmin = tmin;
  r.tmax = tmax;
  return r;
}

bool sphere_hit(const Ray& r, const Sphere& s, float& t) {
  return intersect_sphere(r.org, r.dir, s, r.tmin, r.tmax, t);
}

TEST(IntersectSphere, HeadOnHitsNearSide) {
  float t = 0.0f;
  ASSERT_TRUE(sphere_hit(make_ray({0, 0, -10}, {0, 0, 1}), {{0, 0, 0}, 2.0f}, t));
  EXPECT_FLOAT_EQ(t, 8.0f);
}

TEST(IntersectSphere, UnnormalisedDirectionScalesT) {
  float t = 0.0f;
  ASSERT_TRUE(sphere_hit(make_ray({0, 0, -10}, {0, 0, 2}), {{0, 0, 0}, 2.0f}, t));
  EXPECT_FLOAT_EQ(t, 4.0f);
}

TEST(IntersectSphere, OffAxisHitMatchesClosedForm) {
  // Ray along +z at x offset 1 against the unit-radius-2 sphere: t = 10 - sqrt(4 - 1).
  float t = 0.0f;
  ASSERT_TRUE(sphere_hit(make_ray({1, 0, -10}, {0, 0, 1}), {{0, 0, 0}, 2.0f}, t));
  EXPECT_NEAR(t, 10.0f - std::sqrt(3.0f), 1e-5f);
}

TEST(IntersectSphere, InsideFindsFarSide) {
  float t = 0.0f;
  ASSERT_TRUE(sphere_hit(make_ray({0.5f, 0, 0}, {1, 0, 0}), {{0, 0, 0}, 2.0f}, t));
  EXPECT_FLOAT_EQ(t, 1.5f);
  ASSERT_TRUE(sphere_hit(make_ray({0.5f, 0, 0}, {-1, 0, 0}), {{0, 0, 0}, 2.0f}, t));
  EXPECT_FLOAT_EQ(t, 2.5f);
}

TEST(IntersectSphere, IntervalIsRespected) {
  float t = 0.0f;
  const Sphere s{{0, 0, 0}, 2.0f};
  EXPECT_FALSE(sphere_hit(make_ray({0, 0, -10}, {0, 0, 1}, 0.0f, 7.9f), s, t));
  // tmin past the near side: the far side (t = 12) is the answer.
  ASSERT_TRUE(sphere_hit(make_ray({0, 0, -10}, {0, 0, 1}, 8.5f), s, t));
  EXPECT_FLOAT_EQ(t, 12.0f);
  EXPECT_FALSE(sphere_hit(make_ray({0, 0, -10}, {0, 0, 1}, 12.5f), s, t));
  EXPECT_FALSE(sphere_hit(make_ray({0, 0, -10}, {0, 0, -1}), s, t));  // behind the origin
}

TEST(IntersectSphere, MissesBesideTheSphere) {
  float t = 0.0f;
  EXPECT_FALSE(sphere_hit(make_ray({2.01f, 0, -10}, {0, 0, 1}), {{0, 0, 0}, 2.0f}, t));
}

TEST(IntersectSphere, SmallDistantSphereIsStable) {
  // A 1 cm sphere 100 km away: the textbook b^2 - c form loses every digit of the discriminant.
  const Sphere s{{0, 0, 1e5f}, 0.01f};
  float t = 0.0f;
  ASSERT_TRUE(sphere_hit(make_ray({0, 0, 0}, {0, 0, 1}), s, t));
  EXPECT_NEAR(t, 1e5f - 0.01f, 0.02f);
  // Offsets just inside and just outside the radius decide hit and miss correctly.
  EXPECT_TRUE(sphere_hit(make_ray({0.009f, 0, 0}, {0, 0, 1}), s, t));
  EXPECT_NEAR(t, 1e5f, 0.02f);
  EXPECT_FALSE(sphere_hit(make_ray({0.011f, 0, 0}, {0, 0, 1}), s, t));
  // Aimed from the origin at a point 0.9 r off the centre: still a hit.
  const Vec3 dir = glm::normalize(Vec3(0.009f, 0.0f, 1e5f));
  EXPECT_TRUE(sphere_hit(make_ray({0, 0, 0}, dir), s, t));
}

TEST(IntersectSphere, LargeSphereNearOriginIsStable) {
  // Ground "plane" as a huge sphere; a ray from just above it straight down hits at the offset.
  const Sphere s{{0, -1e6f, 0}, 1e6f};
  float t = 0.0f;
  ASSERT_TRUE(sphere_hit(make_ray({0, 1.0f, 0}, {0, -1, 0}), s, t));
  EXPECT_NEAR(t, 1.0f, 0.07f);  // one ulp of 1e6 is 0.0625
}

bool tri_hit(const Ray& r, Vec3 a, Vec3 b, Vec3 c, float& t, float& u, float& v) {
  return intersect_triangle(make_triangle_ray(r), a, b, c, r.tmin, r.tmax, t, u, v);
}

TEST(IntersectTriangle, HitGivesDistanceAndBarycentrics) {
  float t, u, v;
  const Vec3 a{0, 0, 0}, b{1, 0, 0}, c{0, 1, 0};
  ASSERT_TRUE(tri_hit(make_ray({0.25f, 0.5f, 1}, {0, 0, -1}), a, b, c, t, u, v));
  EXPECT_FLOAT_EQ(t, 1.0f);
  EXPECT_FLOAT_EQ(u, 0.25f);  // weight of b
  EXPECT_FLOAT_EQ(v, 0.5f);   // weight of c
  // From the back side the same point and weights.
  ASSERT_TRUE(tri_hit(make_ray({0.25f, 0.5f, -2}, {0, 0, 1}), a, b, c, t, u, v));
  EXPECT_FLOAT_EQ(t, 2.0f);
  EXPECT_FLOAT_EQ(u, 0.25f);
  EXPECT_FLOAT_EQ(v, 0.5f);
}

TEST(IntersectTriangle, ObliqueRayMatchesPlaneIntersection) {
  // Triangle in the plane x + y + z = 1; ray from the origin along (1, 2, 3) hits at t = 1/6.
  const Vec3 a{1, 0, 0}, b{0, 1, 0}, c{0, 0, 1};
  float t, u, v;
  ASSERT_TRUE(tri_hit(make_ray({0, 0, 0}, {1, 2, 3}), a, b, c, t, u, v));
  EXPECT_NEAR(t, 1.0f / 6.0f, 1e-6f);
  // Hit point (1/6, 2/6, 3/6) = (1-u-v) a + u b + v c.
  EXPECT_NEAR(u, 2.0f / 6.0f, 1e-6f);
  EXPECT_NEAR(v, 3.0f / 6.0f, 1e-6f);
}

TEST(IntersectTriangle, MissesOutsideParallelAndBehind) {
  float t, u, v;
  const Vec3 a{0, 0, 0}, b{1, 0, 0}, c{0, 1, 0};
  EXPECT_FALSE(tri_hit(make_ray({0.6f, 0.6f, 1}, {0, 0, -1}), a, b, c, t, u, v));
  EXPECT_FALSE(tri_hit(make_ray({-0.1f, 0.5f, 1}, {0, 0, -1}), a, b, c, t, u, v));
  EXPECT_FALSE(tri_hit(make_ray({0.2f, 0.2f, 0}, {1, 0, 0}), a, b, c, t, u, v));
  EXPECT_FALSE(tri_hit(make_ray({0.2f, 0.2f, 1}, {0, 0, 1}), a, b, c, t, u, v));
}

TEST(IntersectTriangle, IntervalIsRespected) {
  float t, u, v;
  const Vec3 a{0, 0, 0}, b{1, 0, 0}, c{0, 1, 0};
  EXPECT_FALSE(tri_hit(make_ray({0.2f, 0.2f, 1}, {0, 0, -1}, 0.0f, 0.99f), a, b, c, t, u, v));
  EXPECT_FALSE(tri_hit(make_ray({0.2f, 0.2f, 1}, {0, 0, -1}, 1.01f), a, b, c, t, u, v));
  EXPECT_TRUE(tri_hit(make_ray({0.2f, 0.2f, 1}, {0, 0, -1}, 0.999f, 1.001f), a, b, c, t, u, v));
  EXPECT_NEAR(t, 1.0f, 1e-6f);
}

TEST(IntersectTriangle, DegenerateTrianglesNeverHit) {
  float t, u, v;
  const Vec3 a{0, 0, 0}, b{1, 0, 0};
  EXPECT_FALSE(tri_hit(make_ray({0.5f, 0, 1}, {0, 0, -1}), a, b, Vec3{2, 0, 0}, t, u, v));
  EXPECT_FALSE(tri_hit(make_ray({0, 0, 1}, {0, 0, -1}), a, a, a, t, u, v));
}

TEST(IntersectTriangle, VertexHitIsExact) {
  float t, u, v;
  const Vec3 a{0, 0, 0}, b{1, 0, 0}, c{0, 1, 0};
  ASSERT_TRUE(tri_hit(make_ray({1, 0, 3}, {0, 0, -1}), a, b, c, t, u, v));
  EXPECT_FLOAT_EQ(u, 1.0f);
  EXPECT_FLOAT_EQ(v, 0.0f);
  EXPECT_FLOAT_EQ(t, 3.0f);
}

}  // namespace
}  // namespace frameless
