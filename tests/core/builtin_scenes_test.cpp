// Built-in scenes: each loads, is finalized, and has what its description promises.
#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <set>

#include <gtest/gtest.h>

#include "core/scene/dynamic.h"
#include "core/scenes/builtin_scenes.h"
#include "core/scenes/scene_load.h"

namespace frameless {
namespace {

TEST(BuiltinScenes, DefaultShowsAllFourClassesAndHemisphereAmbient) {
  auto s = load_scene("default");
  ASSERT_TRUE(s.ok()) << s.error().message;
  std::set<MaterialClass> used;
  for (uint16_t m : (*s)->geometry.sphere_material) used.insert((*s)->materials[m].cls);
  for (uint16_t m : (*s)->geometry.triangle_material) used.insert((*s)->materials[m].cls);
  EXPECT_EQ(used.size(), 4u);
  EXPECT_EQ((*s)->ambient.kind, AmbientKind::kHemisphere);
  EXPECT_EQ((*s)->lights.size(), 1u);
  EXPECT_TRUE(camera_is_valid((*s)->camera));
  EXPECT_TRUE((*s)->features.has_dielectric);
  EXPECT_TRUE((*s)->features.has_triangles);
}

TEST(BuiltinScenes, DefaultCameraSeesTheSpheres) {
  auto s = load_scene("default");
  ASSERT_TRUE(s.ok());
  const Scene& sc = **s;
  const CameraBasis b = make_camera_basis(sc.camera, sc.settings.width, sc.settings.height);
  int hits = 0;
  for (const Sphere& sp : sc.geometry.spheres) {
    Ray r;
    r.org = b.eye;
    r.dir = glm::normalize(sp.center - b.eye);
    Hit h;
    hits += sc.accel.intersect(r, h) && h.prim >= sc.geometry.num_triangles();
  }
  EXPECT_GE(hits, 6);
}

TEST(BuiltinScenes, BallsAreDynamicRestOnTheFloorAndMove) {
  auto s = load_scene("balls");
  ASSERT_TRUE(s.ok()) << s.error().message;
  const Scene& sc = **s;
  ASSERT_EQ(sc.dynamic.size(), 16u);
  EXPECT_EQ(sc.geometry.num_spheres(), 0u);  // outside the static BVH, tested per ray
  const WorldState w = initial_world(sc);
  DynamicFrame f0, f1;
  evaluate_frame(sc, w, 0.0, f0);
  int moved = 0;
  for (double t = 0.1; t < 30.0; t += 0.37) {
    evaluate_frame(sc, w, t, f1);
    for (size_t i = 0; i < f1.spheres.size(); ++i) {
      // Never below the floor, but for the cubic Hermite between stored steps across a bounce
      // (millimetres; collisions are chaotic, so which bounce dips most depends on rounding).
      EXPECT_GE(f1.spheres[i].center.y - f1.spheres[i].radius, -3e-3f);
      moved += f0.spheres[i].center != f1.spheres[i].center;
    }
  }
  EXPECT_GT(moved, 0);
}

TEST(BuiltinScenes, RandomSpheresAreSeededAndCounted) {
  auto a = load_scene("spheres:1000");
  auto b = load_scene("spheres:1000:1");
  auto c = load_scene("spheres:1000:7");
  ASSERT_TRUE(a.ok() && b.ok() && c.ok());
  EXPECT_EQ((*a)->geometry.num_spheres(), 1000u);
  std::multiset<float> xa, xb, xc;
  for (const Sphere& s : (*a)->geometry.spheres) xa.insert(s.center.x);
  for (const Sphere& s : (*b)->geometry.spheres) xb.insert(s.center.x);
  for (const Sphere& s : (*c)->geometry.spheres) xc.insert(s.center.x);
  EXPECT_EQ(xa, xb);
  EXPECT_NE(xa, xc);
  EXPECT_TRUE(camera_is_valid((*a)->camera));
  auto one = load_scene("spheres:1");
  ASSERT_TRUE(one.ok());
  EXPECT_EQ((*one)->geometry.num_spheres(), 1u);
}

TEST(BuiltinScenes, RandomSpheresRejectBadCounts) {
  for (const char* bad : {"spheres:0", "spheres:", "spheres:x", "spheres:35000001", "spheres:5:",
                          "spheres:-3", "spheres:99999999999999999999999"}) {
    auto s = load_scene(bad);
    ASSERT_FALSE(s.ok()) << bad;
    EXPECT_NE(s.error().message.find(bad), std::string::npos) << s.error().message;
  }
}

TEST(BuiltinScenes, TriangleSoupIsSeededCountedAndOverlapping) {
  auto a = load_scene("soup:2000");
  auto b = load_scene("soup:2000:1");
  auto c = load_scene("soup:2000:7");
  ASSERT_TRUE(a.ok() && b.ok() && c.ok());
  const Geometry& g = (*a)->geometry;
  ASSERT_EQ(g.num_triangles(), 2000u);
  EXPECT_EQ(g.positions.size(), 6000u);
  EXPECT_EQ(g.positions, (*b)->geometry.positions);  // seed 1 is the default
  EXPECT_NE(g.positions, (*c)->geometry.positions);
  // Each triangle lies within one unit of its centre on every axis, the centres fill a cube of
  // side cbrt(N) = 12.6: triangles overlap their neighbours.
  Vec3 lo, hi;
  ASSERT_TRUE(geometry_bounds(g, lo, hi));
  for (int a = 0; a < 3; ++a) {
    EXPECT_GT(hi[a] - lo[a], 12.0f);
    EXPECT_LT(hi[a] - lo[a], 14.0f);
  }
  for (const UVec3& t : g.triangles)
    for (int a = 0; a < 3; ++a) {
      const float span = std::max({g.positions[t.x][a], g.positions[t.y][a], g.positions[t.z][a]}) -
                         std::min({g.positions[t.x][a], g.positions[t.y][a], g.positions[t.z][a]});
      ASSERT_LE(span, 1.0f);
    }
  EXPECT_TRUE(camera_is_valid((*a)->camera));
  for (const char* bad : {"soup:0", "soup:", "soup:x", "soup:20000001", "soup:5:", "soup:-3"}) {
    auto s = load_scene(bad);
    ASSERT_FALSE(s.ok()) << bad;
    EXPECT_NE(s.error().message.find(bad), std::string::npos) << s.error().message;
  }
  EXPECT_NE(std::string(builtin_scene_help()).find("soup:N"), std::string::npos);
}

TEST(BuiltinScenes, ThirtyFiveMillionSpheres) {
  if (!std::getenv("FRAMELESS_LONG_TESTS")) GTEST_SKIP() << "set FRAMELESS_LONG_TESTS=1";
  auto s = make_builtin_scene("spheres:35000000");
  ASSERT_TRUE(s.ok()) << s.error().message;
  EXPECT_EQ((*s)->geometry.num_spheres(), 35000000u);
}

TEST(BuiltinScenes, BunnyLoadsOrNamesThePackage) {
  auto s = load_scene("bunny");
  FILE* f = std::fopen(kBunnyPath, "rb");
  if (!f) {
    ASSERT_FALSE(s.ok());
    EXPECT_NE(s.error().message.find("glmark2-data"), std::string::npos);
    return;
  }
  std::fclose(f);
  ASSERT_TRUE(s.ok()) << s.error().message;
  EXPECT_GT((*s)->geometry.num_triangles(), 60000u);
  EXPECT_TRUE(camera_is_valid((*s)->camera));
}

TEST(BuiltinScenes, UnknownNameIsAnError) {
  auto s = load_scene("nosuchscene");
  ASSERT_FALSE(s.ok());
  EXPECT_NE(s.error().message.find("nosuchscene"), std::string::npos);
  EXPECT_NE(std::string(builtin_scene_help()).find("spheres:N"), std::string::npos);
}

}  // namespace
}  // namespace frameless
