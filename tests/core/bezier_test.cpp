// Bicubic Bézier patches: evaluation, subpatches, and limit normals at poles (the direct ray
// intersector: patch_surface_test.cpp).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>
#include <vector>

#include "core/geometry/bezier.h"
#include "core/io/patch_io.h"

#include "bezier_patches.h"

namespace frameless {
namespace {

using test_util::cap_patch;
using test_util::curved_patch;
using test_util::ref_point;
using test_util::teapot;

TEST(BezierPatch, EvalMatchesDeCasteljauAndDerivatives) {
  const BezierPatch p = curved_patch();
  EXPECT_EQ(bezier_eval(p, 0, 0), p.p[0]);
  EXPECT_EQ(bezier_eval(p, 1, 0), p.p[3]);   // u runs along a row
  EXPECT_EQ(bezier_eval(p, 0, 1), p.p[12]);  // v runs down the rows
  EXPECT_EQ(bezier_eval(p, 1, 1), p.p[15]);
  std::mt19937 rng(7);
  std::uniform_real_distribution<float> uni(0.0f, 1.0f);
  for (int k = 0; k < 100; ++k) {
    const float u = uni(rng), v = uni(rng), h = 1e-3f;
    Vec3 du, dv;
    const Vec3 q = bezier_eval(p, u, v, &du, &dv);
    EXPECT_LT(glm::length(q - Vec3(ref_point(p, u, v))), 1e-5f);
    const Vec3 fu = Vec3((ref_point(p, u + h, v) - ref_point(p, u - h, v)) / (2.0 * h));
    const Vec3 fv = Vec3((ref_point(p, u, v + h) - ref_point(p, u, v - h)) / (2.0 * h));
    EXPECT_LT(glm::length(du - fu), 1e-3f * glm::length(fu) + 1e-4f);
    EXPECT_LT(glm::length(dv - fv), 1e-3f * glm::length(fv) + 1e-4f);
  }
}

TEST(BezierPatch, SubpatchIsTheRestrictedSurfaceAndSharesItsEdge) {
  const BezierPatch p = curved_patch();
  const BezierPatch s = bezier_subpatch(p, 0.25f, 0.75f, 0.1f, 0.6f);
  for (float a : {0.0f, 0.3f, 1.0f})
    for (float b : {0.0f, 0.6f, 1.0f})
      EXPECT_LT(glm::length(bezier_eval(s, a, b) - bezier_eval(p, 0.25f + 0.5f * a, 0.1f + 0.5f * b)), 1e-5f);
  const BezierPatch left = bezier_subpatch(p, 0.0f, 0.5f, 0.0f, 1.0f);
  const BezierPatch right = bezier_subpatch(p, 0.5f, 1.0f, 0.0f, 1.0f);
  for (int i = 0; i < 4; ++i) EXPECT_EQ(left.p[4 * i + 3], right.p[4 * i]);
}

TEST(BezierNormal, RegularPointsAreTheUnitCrossProduct) {
  const BezierPatch p = curved_patch();
  for (float u : {0.0f, 0.3f, 0.9f})
    for (float v : {0.0f, 0.5f, 1.0f}) {
      Vec3 du, dv;
      bezier_eval(p, u, v, &du, &dv);
      EXPECT_LT(glm::length(bezier_normal(p, u, v) - glm::normalize(glm::cross(du, dv))), 1e-5f);
    }
}

void expect_unit(const Vec3& n) {
  EXPECT_TRUE(is_finite(n)) << n.x << " " << n.y << " " << n.z;
  EXPECT_NEAR(glm::length(n), 1.0f, 1e-5f);
}

float angle_deg(const Vec3& a, const Vec3& b) {
  return glm::degrees(std::acos(std::clamp(glm::dot(a, b), -1.0f, 1.0f)));
}

TEST(BezierNormal, CollapsedEdgeGivesTheLimitNormalAtThePole) {
  const BezierPatch cap = cap_patch();
  // Everywhere, including the whole collapsed row v = 0 and its corners: finite and unit.
  for (int a = 0; a <= 16; ++a)
    for (int b = 0; b <= 16; ++b) expect_unit(bezier_normal(cap, a / 16.0f, b / 16.0f));
  for (float u : {0.0f, 0.2f, 0.5f, 0.8f, 1.0f}) {
    const Vec3 pole = bezier_normal(cap, u, 0.0f);
    EXPECT_LT(angle_deg(pole, Vec3(0, 0, 1)), 0.01f) << "u " << u;
    // The limit: continuous with the normal just inside.
    EXPECT_LT(angle_deg(pole, bezier_normal(cap, u, 1e-3f)), 0.5f) << "u " << u;
  }
  // The same cap with the roles of u and v swapped (a collapsed column): the normal flips with
  // the parametrisation's handedness.
  BezierPatch t;
  for (int i = 0; i < 4; ++i)
    for (int j = 0; j < 4; ++j) t.p[4 * i + j] = cap.p[4 * j + i];
  for (float v : {0.0f, 0.5f, 1.0f}) EXPECT_LT(angle_deg(bezier_normal(t, 0.0f, v), Vec3(0, 0, -1)), 0.01f);
  // No surface at all: still a finite unit vector.
  BezierPatch point;
  for (Vec3& q : point.p) q = Vec3(1, 2, 3);
  expect_unit(bezier_normal(point, 0.5f, 0.5f));
}

TEST(BezierNormal, TeapotPolesPointAlongTheAxis) {
  auto patches = teapot();
  if (!patches) GTEST_SKIP() << "no teapot (apt-get install povray-examples): " << patches.error().message;
  ASSERT_EQ(patches->size(), 32u);
  // Patches 20-23 are the lid's knob, pole (0,0,3.15) on top; 28-31 the bottom, pole at the origin.
  for (int k : {20, 21, 22, 23, 28, 29, 30, 31}) {
    const Vec3 axis(0.0f, 0.0f, k < 24 ? 1.0f : -1.0f);
    for (float u : {0.0f, 0.25f, 0.5f, 1.0f}) {
      const Vec3 n = bezier_normal((*patches)[k], u, 0.0f);
      expect_unit(n);
      EXPECT_LT(angle_deg(n, axis), 0.01f) << "patch " << k << " u " << u;
    }
  }
}

}  // namespace
}  // namespace frameless
