// JSON scene files: every field of the documented example lands in the Scene, transforms act
// on positions and normals correctly.
#include <gtest/gtest.h>

#include "core/scenes/scene_load.h"

namespace frameless {
namespace {

const std::string kData = FRAMELESS_TEST_DATA;

Result<std::unique_ptr<Scene>> parse(const std::string& text) {
  return parse_scene_json(text, "t.json", kData + "/scenes");
}

TEST(SceneJson, ExampleLoadsEveryField) {
  auto s = load_scene(kData + "/scenes/example.json");
  ASSERT_TRUE(s.ok()) << s.error().message;
  const Scene& sc = **s;
  EXPECT_EQ(sc.camera.eye, Vec3(0, 2, 8));
  EXPECT_EQ(sc.camera.fov_deg, 45.0f);
  EXPECT_EQ(sc.settings.width, 320);
  EXPECT_EQ(sc.settings.height, 240);
  EXPECT_EQ(sc.settings.spp, 4);
  EXPECT_EQ(sc.settings.seed, 7u);
  EXPECT_FLOAT_EQ(sc.settings.min_contribution, 0.002f);
  EXPECT_EQ(sc.ambient.kind, AmbientKind::kHemisphere);
  ASSERT_EQ(sc.lights.size(), 2u);
  EXPECT_EQ(sc.lights[1].radius, 0.5f);
  EXPECT_EQ(sc.lights[1].color, Vec3(0.3f));
  ASSERT_EQ(sc.materials.size(), 4u);
  EXPECT_EQ(sc.materials[1].cls, MaterialClass::kMetal);
  EXPECT_EQ(sc.materials[1].kh, sc.materials[1].ks);
  EXPECT_EQ(sc.materials[2].cls, MaterialClass::kDielectric);
  EXPECT_EQ(sc.materials[3].cls, MaterialClass::kPolished);
  EXPECT_EQ(sc.geometry.num_spheres(), 2u);
  // plane 2 + box 12 + tetra 4 + square 3 + triangle 1
  EXPECT_EQ(sc.geometry.num_triangles(), 22u);
}

TEST(SceneJson, AmbientKinds) {
  auto none = parse(R"({"ambient":{"type":"none"},"materials":{"m":{"class":"diffuse"}},
      "objects":[{"type":"sphere","center":[0,0,0],"radius":1,"material":"m"}]})");
  ASSERT_TRUE(none.ok()) << none.error().message;
  EXPECT_EQ((*none)->ambient.kind, AmbientKind::kNone);
  auto c = parse(R"({"ambient":{"type":"constant","color":[0.1,0.2,0.3]},"materials":{"m":{"class":"diffuse"}},
      "objects":[{"type":"sphere","center":[0,0,0],"radius":1,"material":"m"}]})");
  ASSERT_TRUE(c.ok()) << c.error().message;
  EXPECT_EQ((*c)->ambient.constant, Vec3(0.1f, 0.2f, 0.3f));
}

TEST(SceneJson, BoxNormalsPointOutward) {
  auto s = parse(R"({"materials":{"m":{"class":"diffuse"}},
      "objects":[{"type":"box","min":[-1,-2,-3],"max":[1,2,3],"material":"m"}]})");
  ASSERT_TRUE(s.ok()) << s.error().message;
  const Geometry& g = (*s)->geometry;
  ASSERT_EQ(g.num_triangles(), 12u);
  for (const UVec3& t : g.triangles) {
    const Vec3 a = g.positions[t.x], b = g.positions[t.y], c = g.positions[t.z];
    const Vec3 n = glm::cross(b - a, c - a);
    EXPECT_GT(glm::dot(n, (a + b + c) / 3.0f), 0.0f);  // the box is centred on the origin
  }
}

TEST(SceneJson, PlaneFacesItsNormalAndHasItsSize) {
  auto s = parse(R"({"materials":{"m":{"class":"diffuse"}},
      "objects":[{"type":"plane","point":[0,1,0],"normal":[0,0,2],"size":4,"material":"m"}]})");
  ASSERT_TRUE(s.ok()) << s.error().message;
  const Geometry& g = (*s)->geometry;
  ASSERT_EQ(g.num_triangles(), 2u);
  for (const UVec3& t : g.triangles) {
    const Vec3 n = glm::cross(g.positions[t.y] - g.positions[t.x], g.positions[t.z] - g.positions[t.x]);
    EXPECT_GT(n.z, 0.0f);
  }
  Vec3 lo, hi;
  geometry_bounds(g, lo, hi);
  EXPECT_NEAR(hi.x - lo.x, 4.0f, 1e-5f);
  EXPECT_NEAR(hi.y - lo.y, 4.0f, 1e-5f);
  EXPECT_NEAR(lo.y, -1.0f, 1e-5f);
}

// Non-uniform scale: positions scale, normals transform by the inverse transpose.
TEST(SceneJson, TransformMovesPositionsAndNormalsCorrectly) {
  auto s = parse(R"({"materials":{"m":{"class":"diffuse"}},
      "objects":[{"type":"triangles","material":"m",
        "vertices":[[0,0,0],[1,0,0],[0,1,0]], "normals":[[1,1,0],[1,1,0],[1,1,0]],
        "indices":[[0,1,2]],
        "transform":{"translate":[10,0,0],"rotate":{"axis":[0,0,1],"degrees":90},"scale":[2,1,1]}}]})");
  ASSERT_TRUE(s.ok()) << s.error().message;
  const Geometry& g = (*s)->geometry;
  // (1,0,0) -> scale (2,0,0) -> rotate 90 about z (0,2,0) -> translate (10,2,0)
  EXPECT_NEAR(g.positions[1].x, 10.0f, 1e-5f);
  EXPECT_NEAR(g.positions[1].y, 2.0f, 1e-5f);
  // normal (1,1,0) -> inverse-transpose scale (0.5,1,0) -> rotate (-1,0.5,0) normalised
  const Vec3 want = glm::normalize(Vec3(-1.0f, 0.5f, 0.0f));
  EXPECT_NEAR(g.normals[0].x, want.x, 1e-5f);
  EXPECT_NEAR(g.normals[0].y, want.y, 1e-5f);
}

TEST(SceneJson, MirroringMatrixKeepsWindingOutward) {
  auto s = parse(R"({"materials":{"m":{"class":"diffuse"}},
      "objects":[{"type":"mesh","file":"../meshes/tetra.obj","material":"m",
                  "transform":[-1,0,0,0, 0,1,0,0, 0,0,1,0, 0,0,0,1]}]})");
  ASSERT_TRUE(s.ok()) << s.error().message;
  const Geometry& g = (*s)->geometry;
  for (const UVec3& t : g.triangles) {
    const Vec3 a = g.positions[t.x], b = g.positions[t.y], c = g.positions[t.z];
    EXPECT_GT(glm::dot(glm::cross(b - a, c - a), a + b + c), 0.0f);
  }
}

TEST(SceneJson, NoCameraFramesTheGeometry) {
  auto s = parse(R"({"materials":{"m":{"class":"diffuse"}},
      "objects":[{"type":"sphere","center":[100,0,0],"radius":1,"material":"m"}]})");
  ASSERT_TRUE(s.ok()) << s.error().message;
  EXPECT_EQ((*s)->camera.look, Vec3(100, 0, 0));
}

}  // namespace
}  // namespace frameless

namespace frameless {
namespace {

// Rotations listed in an array apply to points in the order written.
TEST(SceneJson, RotationArrayAppliesInOrder) {
  auto s = parse_scene_json(R"({"materials":{"m":{"class":"diffuse"}},
      "objects":[{"type":"triangles","material":"m",
        "vertices":[[1,0,0],[0,1,0],[0,0,1]], "indices":[[0,1,2]],
        "transform":{"rotate":[{"axis":[0,0,1],"degrees":90},{"axis":[1,0,0],"degrees":90}]}}]})",
                            "t.json", ".");
  ASSERT_TRUE(s.ok()) << s.error().message;
  // (1,0,0) -> about z: (0,1,0) -> about x: (0,0,1)
  const Vec3 p = (*s)->geometry.positions[0];
  EXPECT_NEAR(p.x, 0.0f, 1e-6f);
  EXPECT_NEAR(p.y, 0.0f, 1e-6f);
  EXPECT_NEAR(p.z, 1.0f, 1e-6f);
}

}  // namespace
}  // namespace frameless
