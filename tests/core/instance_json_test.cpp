// JSON scenes: a mesh declared once under "meshes" and placed by "instance" objects; errors
// name the field.
#include <gtest/gtest.h>

#include "core/accel/instance.h"
#include "core/scenes/scene_load.h"

namespace frameless {
namespace {

std::string scene_with(const std::string& objects) {
  return R"({
  "materials": {"red": {"class": "diffuse", "kd": [0.8, 0.1, 0.1]}},
  "meshes": {"tri": {"type": "triangles", "material": "red",
                     "vertices": [[0, 0, 0], [1, 0, 0], [0, 1, 0]], "indices": [[0, 1, 2]]}},
  "objects": [)" + objects + "]}";
}

TEST(InstanceJson, MeshDeclaredOnceIsPlacedManyTimes) {
  auto s = parse_scene_json(scene_with(R"(
    {"type": "instance", "mesh": "tri"},
    {"type": "instance", "mesh": "tri", "transform": {"translate": [5, 0, 0], "scale": [-2, 1, 1]}},
    {"type": "instance", "mesh": "tri", "transform": {"translate": [0, 0, -3]}})"), "i.json", ".");
  ASSERT_TRUE(s) << s.error().message;
  const Scene& scene = **s;
  EXPECT_EQ(scene.geometry.instance_meshes.size(), 1u);
  EXPECT_EQ(scene.geometry.instances.size(), 3u);
  EXPECT_EQ(scene.geometry.num_triangles(), 0u);  // nothing flattened
  EXPECT_EQ(represented_triangles(scene.geometry), 3u);
  // The mirrored, stretched copy is where the transform puts it: (5 - 2 * 0.25, 0.25) is inside.
  Ray r;
  r.org = Vec3(4.5f, 0.25f, 1.0f);
  r.dir = Vec3(0, 0, -1);
  Hit h;
  ASSERT_TRUE(scene.accel.intersect(r, h));
  EXPECT_NE(h.inst, kInvalidId);
  EXPECT_NEAR(h.t, 1.0f, 1e-6f);
  r.org = Vec3(5.5f, 0.25f, 1.0f);  // mirrored away from +x
  EXPECT_FALSE(scene.accel.intersect(r, h));
}

TEST(InstanceJson, ErrorsNameTheField) {
  auto expect_error = [](const std::string& text, const std::string& field) {
    auto s = parse_scene_json(text, "i.json", ".");
    ASSERT_FALSE(s);
    EXPECT_NE(s.error().message.find(field), std::string::npos) << s.error().message;
  };
  expect_error(scene_with(R"({"type": "instance", "mesh": "nope"})"), "objects[0].mesh");
  expect_error(scene_with(R"({"type": "instance"})"), "objects[0].mesh");
  expect_error(scene_with(R"({"type": "instance", "mesh": "tri", "transform": {"scale": [0, 1, 1]}})"),
               "objects[0].transform.scale");
  expect_error(R"({"meshes": {"s": {"type": "sphere", "center": [0,0,0], "radius": 1}},
                  "objects": [{"type": "instance", "mesh": "s"}]})", "meshes.s.type");
  expect_error(R"({"meshes": {"m": {"type": "triangles", "vertices": [], "indices": []}},
                  "objects": [{"type": "instance", "mesh": "m"}]})", "meshes.m");
}

}  // namespace
}  // namespace frameless
