// Spline surfaces in scenes (seed section 3.3): the built-in teapot, "bezier" objects in JSON
// (file and inline control points, transformed), shading and shadows on patches.
#include <gtest/gtest.h>

#include <cmath>

#include "core/geometry/surface.h"
#include "core/scenes/scene_load.h"
#include "core/shading/render_sample.h"
#include "core/shading/soft_shadow.h"

namespace frameless {
namespace {

// A dome: 4 x 4 controls over [-1, 1]^2, corners at 0, the middle four at `height` (convex for a
// positive height, a bowl for a negative one).
std::string dome_json(const std::string& extra_object = "", float height = 1.0f) {
  std::string pts;
  for (int i = 0; i < 4; ++i)
    for (int j = 0; j < 4; ++j) {
      const float x = -1.0f + 2.0f * float(j) / 3.0f, z = -1.0f + 2.0f * float(i) / 3.0f;
      const bool inner_i = i == 1 || i == 2, inner_j = j == 1 || j == 2;
      const float y = height * (inner_i && inner_j ? 1.0f : (inner_i || inner_j ? 0.5f : 0.0f));
      pts += (pts.empty() ? "" : ", ") + std::string("[") + std::to_string(x) + ", " +
             std::to_string(y) + ", " + std::to_string(z) + "]";
    }
  return R"({"camera": {"eye": [0, 6, 0.01], "look": [0, 0, 0], "fov": 40},
    "lights": [{"type": "spherical", "position": [0, 8, 0], "radius": 0.8, "color": [1, 1, 1]}],
    "materials": {"m": {"class": "diffuse", "kd": [0.7, 0.7, 0.7]}},
    "objects": [{"type": "bezier", "material": "m", "depth": 3,
                 "transform": {"translate": [0, 0.5, 0]}, "patches": [[)" +
         pts + "]]}" + extra_object + "]}";
}

TEST(PatchScene, InlinePatchesAreTransformedAndHitWhereTheSurfaceIs) {
  auto scene = parse_scene_json(dome_json(), "dome.json", ".");
  ASSERT_TRUE(scene) << scene.error().message;
  const Scene& s = **scene;
  ASSERT_EQ(s.geometry.num_patches(), 1u);
  // The dome's top: P(0.5, 0.5) = 0.5 (corner ring) ... the bicubic weights give y = 0.75 + 0.5.
  Ray r;
  r.org = Vec3(0.0f, 10.0f, 0.0f);
  r.dir = Vec3(0.0f, -1.0f, 0.0f);
  Hit h;
  ASSERT_TRUE(s.accel.intersect(r, h));
  EXPECT_NEAR(10.0f - h.t, 0.5f + 0.75f, 1e-4f);
  const SurfacePoint sp = surface_point(s.geometry, r, h);
  EXPECT_NEAR(sp.ng.y, 1.0f, 1e-4f);
  EXPECT_NEAR(h.u, 0.5f, 1e-4f);  // texture coordinates are the patch parameters
  EXPECT_NEAR(h.v, 0.5f, 1e-4f);
}

// A bowl's chords (the soft-shadow grid) lie above its surface: they must not shadow it.
TEST(PatchScene, APatchDoesNotShadowItselfUnderSoftShadows) {
  auto scene = parse_scene_json(dome_json("", -1.0f), "bowl.json", ".");
  ASSERT_TRUE(scene) << scene.error().message;
  const Scene& s = **scene;
  ASSERT_FALSE(s.geometry.patch_shadow_grid.empty());
  int shadowed = 0, tested = 0;
  for (int i = 1; i < 20; ++i)
    for (int j = 1; j < 20; ++j) {
      Ray r;
      r.org = Vec3(-0.95f + 0.1f * float(i), 10.0f, -0.95f + 0.1f * float(j));
      r.dir = Vec3(0.0f, -1.0f, 0.0f);
      Hit h;
      if (!s.accel.intersect(r, h)) continue;
      const SurfacePoint sp = surface_point(s.geometry, r, h);
      ShadowQuery q;
      q.org = offset_ray_origin(sp.p, sp.ng, sp.scale);
      q.dir = glm::normalize(s.lights[0].position - q.org);
      if (glm::dot(q.dir, sp.ng) < 0.3f) continue;
      const float dist = glm::length(s.lights[0].position - q.org);
      q.tmax = dist - s.lights[0].radius;
      q.half_angle = std::asin(s.lights[0].radius / dist);
      q.tan_half = std::tan(q.half_angle);
      q.receiver = sp.prim;
      ++tested;
      shadowed += soft_visibility(s, q) < 1.0f;
    }
  EXPECT_GT(tested, 100);
  EXPECT_EQ(shadowed, 0);
}

TEST(PatchScene, PatchesCastSoftShadows) {
  auto scene = parse_scene_json(
      dome_json(R"(, {"type": "plane", "point": [0, 0, 0], "normal": [0, 1, 0], "size": 20, "material": "m"})"),
      "dome.json", ".");
  ASSERT_TRUE(scene) << scene.error().message;
  const Scene& s = **scene;
  auto vis = [&](float x) {
    ShadowQuery q;
    q.org = Vec3(x, 1e-4f, 0.0f);
    const Vec3 l = s.lights[0].position - q.org;
    q.dir = glm::normalize(l);
    q.tmax = glm::length(l) - s.lights[0].radius;
    q.half_angle = std::asin(s.lights[0].radius / glm::length(l));
    q.tan_half = std::tan(q.half_angle);
    return soft_visibility(s, q);
  };
  EXPECT_EQ(vis(0.0f), 0.0f);  // under the dome
  EXPECT_EQ(vis(3.0f), 1.0f);  // far outside
  bool penumbra = false;
  for (float x = 0.8f; x < 1.4f; x += 0.02f) penumbra |= vis(x) > 0.0f && vis(x) < 1.0f;
  EXPECT_TRUE(penumbra);
}

TEST(PatchScene, BadBezierObjectsGetOneLineErrors) {
  auto err = [](const std::string& obj) {
    auto r = parse_scene_json(R"({"materials": {"m": {"class": "diffuse"}}, "objects": [)" + obj + "]}",
                              "b.json", ".");
    return r ? std::string() : r.error().message;
  };
  EXPECT_NE(err(R"({"type": "bezier", "material": "m", "patches": [[[0, 0, 0]]]})").find(
                "objects[0].patches[0]: expected 16 control points"),
            std::string::npos);
  EXPECT_NE(err(R"({"type": "bezier", "material": "m"})").find("needs exactly one"), std::string::npos);
  EXPECT_NE(err(R"({"type": "bezier", "material": "m", "file": "missing.inc"})").find("objects[0].file"),
            std::string::npos);
  EXPECT_NE(err(R"({"type": "bezier", "material": "m", "file": "x.inc", "depth": 12})").find(
                "objects[0].depth"),
            std::string::npos);
}

TEST(PatchScene, TheBuiltInTeapotIsThirtyTwoDirectlyTracedPatches) {
  auto scene = load_scene("teapot");
  if (!scene) GTEST_SKIP() << scene.error().message;  // povray-examples not installed
  const Scene& s = **scene;
  EXPECT_EQ(s.geometry.num_patches(), 32u);
  const CameraBasis b = make_camera_basis(s.camera, 40, 30);
  int teapot = 0;
  for (int y = 0; y < 30; ++y)
    for (int x = 0; x < 40; ++x) {
      const SampleResult r = render_sample(s, b, x, y, 0, false);
      ASSERT_TRUE(r.valid);
      ASSERT_TRUE(is_finite(r.color));
      Hit h;
      if (s.accel.intersect(camera_ray(b, x + 0.5f, y + 0.5f), h) && h.prim >= s.geometry.first_patch())
        ++teapot;
    }
  EXPECT_GT(teapot, 100);  // the teapot fills a good part of the view
}

}  // namespace
}  // namespace frameless
