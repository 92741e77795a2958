// render_sample / trace_sample: determinism, jitter inside the pixel, depth and normal outputs,
// and that no NaN or Inf ever leaves a sample.
#include "core/shading/render_sample.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include "core/scene/scene_finalize.h"
#include "shading_scenes.h"

namespace frameless {
namespace {

using testing::add_horizontal_quad;
using testing::add_quad;
using testing::add_sphere;
using testing::make_empty_scene;
using testing::make_material;

// A unit diffuse sphere at the origin, seen from (0, 0, 5), lit from above.
std::unique_ptr<Scene> sphere_scene() {
  auto s = make_empty_scene();
  s->materials.push_back(make_material(MaterialClass::kDiffuse));
  add_sphere(s->geometry, Vec3(0.0f), 1.0f, 0);
  s->lights.push_back(Light{Vec3(2.0f, 5.0f, 5.0f), Vec3(1.0f), 0.0f});
  s->settings.background = Vec3(0.2f, 0.3f, 0.4f);
  finalize_scene(*s);
  return s;
}

bool same(const SampleResult& a, const SampleResult& b) {
  return a.color == b.color && a.normal == b.normal && a.valid == b.valid &&
         (a.depth == b.depth || (std::isinf(a.depth) && std::isinf(b.depth)));
}

TEST(RenderSample, IsDeterministicAndCentredWithoutJitter) {
  auto s = sphere_scene();
  const CameraBasis cam = make_camera_basis(Camera{}, 33, 25);
  for (int y = 0; y < 25; y += 3)
    for (int x = 0; x < 33; x += 4) {
      EXPECT_TRUE(same(render_sample(*s, cam, x, y, 7), render_sample(*s, cam, x, y, 7)));
      EXPECT_TRUE(same(render_sample(*s, cam, x, y, 7, false),
                       trace_sample(*s, cam, x + 0.5f, y + 0.5f, 0)));
    }
}

TEST(RenderSample, DepthAndNormalAtTheCentreAndOnAMiss) {
  auto s = sphere_scene();
  const CameraBasis cam = make_camera_basis(Camera{}, 33, 25);
  const SampleResult c = render_sample(*s, cam, 16, 12, 0, false);
  EXPECT_TRUE(c.valid);
  EXPECT_NEAR(c.depth, 4.0f, 1e-5f);
  EXPECT_NEAR(c.normal.z, 1.0f, 1e-5f);
  EXPECT_GT(c.color.x, 0.0f);
  const SampleResult miss = render_sample(*s, cam, 0, 0, 0, false);
  EXPECT_TRUE(miss.valid);
  EXPECT_TRUE(std::isinf(miss.depth) && miss.depth > 0.0f);
  EXPECT_EQ(miss.normal, Vec3(0.0f));
  EXPECT_EQ(miss.color, s->settings.background);
}

// Reprojection's point: a jittered sample's hit, moved onto its pixel centre's ray at the same
// view depth; on a miss the centre ray's direction. Hits name what they hit.
TEST(RenderSample, PointLiesOnThePixelCentresRayAtTheHitsViewDepth) {
  auto s = sphere_scene();
  const CameraBasis cam = make_camera_basis(Camera{}, 33, 25);
  for (const float jx : {0.1f, 0.5f, 0.9f})
    for (const float jy : {0.2f, 0.8f}) {
      const SampleResult r = trace_sample(*s, cam, 16.0f + jx, 12.0f + jy, 0);
      ASSERT_EQ(r.object, kPointStatic);
      const Ray centre = camera_ray(cam, 16.5f, 12.5f), jittered = camera_ray(cam, 16.0f + jx, 12.0f + jy);
      const Vec3 off = r.position - centre.org;
      EXPECT_LT(glm::length(glm::cross(centre.dir, off)), 1e-5f * glm::length(off));  // on the centre ray
      const Vec3 hit = jittered.org + jittered.dir * r.depth;
      EXPECT_NEAR(glm::dot(off, cam.w), glm::dot(hit - cam.eye, cam.w), 1e-5f);  // at the hit's depth
    }
  const SampleResult miss = trace_sample(*s, cam, 0.3f, 0.7f, 0);
  EXPECT_EQ(miss.object, kPointSky);
  EXPECT_LT(glm::length(glm::normalize(miss.position) - camera_ray(cam, 0.5f, 0.5f).dir), 1e-6f);
}

// On a plane facing the camera, depth grows monotonically away from the image centre, so a
// jittered sample of an off-centre pixel lies between the depths of the pixel's corners.
TEST(RenderSample, JitterStaysInsideThePixelAndVaries) {
  auto s = make_empty_scene();
  s->materials.push_back(make_material(MaterialClass::kDiffuse));
  add_quad(s->geometry, Vec3(-10.0f, -10.0f, 0.0f), Vec3(10.0f, -10.0f, 0.0f),
           Vec3(10.0f, 10.0f, 0.0f), Vec3(-10.0f, 10.0f, 0.0f), 0);
  finalize_scene(*s);
  const CameraBasis cam = make_camera_basis(Camera{}, 16, 16);
  const int x = 3, y = 4;  // upper-left quadrant
  const float lo = trace_sample(*s, cam, x + 1.0f, y + 1.0f, 0).depth;
  const float hi = trace_sample(*s, cam, float(x), float(y), 0).depth;
  ASSERT_LT(lo, hi);
  float min_d = kInfinity, max_d = 0.0f;
  for (uint32_t i = 0; i < 256; ++i) {
    const float d = render_sample(*s, cam, x, y, i).depth;
    EXPECT_GE(d, lo * (1.0f - 1e-6f));
    EXPECT_LE(d, hi * (1.0f + 1e-6f));
    min_d = std::min(min_d, d);
    max_d = std::max(max_d, d);
  }
  // 256 uniform jitters cover most of the depth range (fails if jitter were constant).
  EXPECT_LT(min_d - lo, 0.2f * (hi - lo));
  EXPECT_GT(max_d - lo, 0.8f * (hi - lo));
  // The global seed changes the jitter.
  const float d0 = render_sample(*s, cam, x, y, 0).depth;
  s->settings.seed = 99;
  EXPECT_NE(render_sample(*s, cam, x, y, 0).depth, d0);
}

TEST(RenderSample, NanOrInfNeverLeaves) {
  const CameraBasis cam = make_camera_basis(Camera{}, 12, 10);
  auto check_all = [&](const Scene& s, bool expect_dropped) {
    int dropped = 0;
    for (int y = 0; y < 10; ++y)
      for (int x = 0; x < 12; ++x) {
        const SampleResult r = render_sample(s, cam, x, y, 0);
        EXPECT_TRUE(is_finite(r.color) && is_finite(r.normal));
        EXPECT_FALSE(std::isnan(r.depth));
        dropped += !r.valid;
      }
    if (expect_dropped)
      EXPECT_GT(dropped, 0);
    else
      EXPECT_EQ(dropped, 0);
  };
  auto nan_material = sphere_scene();
  nan_material->materials[0].kd = Vec3(std::numeric_limits<float>::quiet_NaN());
  check_all(*nan_material, true);
  auto inf_light = sphere_scene();
  inf_light->lights[0].color = Vec3(kInfinity);
  check_all(*inf_light, true);

  // Degenerate geometry must shade finitely: zero-area and needle triangles, a zero-radius
  // sphere, coincident and nested spheres, a light inside geometry.
  auto degenerate = sphere_scene();
  Material glass = make_material(MaterialClass::kDielectric);
  glass.extinction = Vec3(0.5f);
  Material metal = make_material(MaterialClass::kMetal);
  metal.ks = Vec3(0.7f);
  degenerate->materials.push_back(glass);
  degenerate->materials.push_back(metal);
  Geometry& g = degenerate->geometry;
  add_quad(g, Vec3(-1.0f, 0.0f, 0.5f), Vec3(-1.0f, 0.0f, 0.5f), Vec3(1.0f, 0.0f, 0.5f),
           Vec3(1.0f, 0.0f, 0.5f), 1);  // zero area
  add_quad(g, Vec3(-2.0f, -1.0f, 1.5f), Vec3(2.0f, -1.0f, 1.5f), Vec3(2.0f, -1.0f + 1e-7f, 1.5f),
           Vec3(-2.0f, -1.0f + 1e-7f, 1.5f), 2);  // needle
  add_sphere(g, Vec3(0.5f, 0.5f, 1.0f), 0.0f, 1);
  add_sphere(g, Vec3(-0.5f, 0.5f, 1.0f), 0.3f, 1);
  add_sphere(g, Vec3(-0.5f, 0.5f, 1.0f), 0.3f, 2);  // coincident
  add_sphere(g, Vec3(-0.5f, 0.5f, 1.0f), 0.1f, 1);  // nested
  add_horizontal_quad(g, -1.0f, 5.0f, 2);
  degenerate->lights.push_back(Light{Vec3(-0.5f, 0.5f, 1.0f), Vec3(1.0f), 0.0f});
  degenerate->ambient.kind = AmbientKind::kHemisphere;
  finalize_scene(*degenerate);
  check_all(*degenerate, false);
}

}  // namespace
}  // namespace frameless
