// Moving instances (core/accel/instance_top.h): a moved top level finds exactly what a top built from
// scratch over the moved transforms finds, the old top never changes, refits that loosen the
// tree too much rebuild it, and bad moves are refused with a one-line error.
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "core/accel/instance.h"
#include "core/accel/instance_top.h"
#include "core/scenes/scene_load.h"
#include "random_geometry.h"

namespace frameless {
namespace {

// A shared mesh of random triangles placed n times on a grid (rotated, stretched, mirrored).
struct Field {
  MeshList meshes;
  std::vector<Instance> instances;
};

Affine placement(int k, float spread) {
  Affine a;
  const float c = std::cos(0.9f * float(k)), s = std::sin(0.9f * float(k));
  const Vec3 scale(k % 3 == 0 ? -0.8f : 0.8f, 0.5f + 0.1f * float(k % 5), 0.7f);
  a.m = glm::mat3(Vec3(c, 0, -s), Vec3(0, 1, 0), Vec3(s, 0, c)) *
        glm::mat3(Vec3(scale.x, 0, 0), Vec3(0, scale.y, 0), Vec3(0, 0, scale.z));
  a.t = spread * Vec3(float(k % 10), 0.0f, float(k / 10));
  return a;
}

Field make_field(int n) {
  Field f;
  auto mesh = std::make_shared<InstancedMesh>();
  mesh->geometry = random_triangles(7, 300, false);
  build_instanced_mesh(*mesh);
  f.meshes.push_back(mesh);
  for (int k = 0; k < n; ++k) {
    Instance inst;
    EXPECT_TRUE(make_instance(0, placement(k, 2.5f), inst));
    f.instances.push_back(inst);
  }
  return f;
}

// Rays from above the field down into it, and sideways through it.
std::vector<Ray> field_rays(int n, uint32_t seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<float> u(-3.0f, 28.0f), d(-1.0f, 1.0f);
  std::vector<Ray> rays(static_cast<size_t>(n));
  for (Ray& r : rays) {
    r.org = Vec3(u(rng), 6.0f + d(rng), u(rng));
    r.dir = glm::normalize(Vec3(d(rng), -1.0f, d(rng)));
    if (&r - rays.data() >= n / 2) r.org.y = 0.3f * d(rng), r.dir = glm::normalize(Vec3(1.0f, 0.05f * d(rng), d(rng)));
  }
  return rays;
}

// Hits of both tops agree: same distance, primitive and declared instance.
int expect_same_hits(const InstanceTop& a, const InstanceTop& b, const std::vector<Ray>& rays) {
  int hits = 0;
  for (const Ray& r : rays) {
    Hit ha, hb;
    const bool fa = intersect_instances(a, r, ha, false), fb = intersect_instances(b, r, hb, false);
    EXPECT_EQ(fa, fb);
    EXPECT_EQ(occluded_instances(a, r), fa);
    EXPECT_EQ(occluded_instances(b, r), fb);
    if (!fa || !fb) continue;
    ++hits;
    EXPECT_EQ(ha.t, hb.t);
    EXPECT_EQ(ha.prim, hb.prim);
    EXPECT_EQ(a.declared[ha.inst], b.declared[hb.inst]);
  }
  return hits;
}

TEST(InstanceMotion, MovedTopFindsWhatAFreshBuildFinds) {
  Field f = make_field(60);
  auto top = build_instance_top(f.instances, f.meshes);
  // Move a third of the instances a little (a refit keeps the tree), rotate one, drop one low.
  std::vector<InstanceMove> moves;
  for (uint32_t k = 0; k < 60; k += 3) {
    Affine a = placement(int(k), 2.5f);
    a.t += Vec3(0.7f, 0.2f * float(k % 4), -0.5f);
    if (k == 9) a.m = glm::mat3(Vec3(0, 0, 1), Vec3(0, 1, 0), Vec3(-1, 0, 0)) * a.m;
    if (k == 30) a.t.y -= 3.0f;
    moves.push_back({k, a});
  }
  InstanceUpdate u;
  auto moved = move_instances(*top, moves, {}, &u);
  ASSERT_TRUE(moved) << moved.error().message;
  EXPECT_EQ(u.moved, moves.size());
  EXPECT_FALSE(u.rebuilt);  // small moves: a refit
  std::vector<Instance> expect = f.instances;
  for (const InstanceMove& m : moves) ASSERT_TRUE(make_instance(0, m.to_world, expect[m.index]));
  auto fresh = build_instance_top(expect, f.meshes);
  const std::vector<Ray> rays = field_rays(20000, 3);
  EXPECT_GT(expect_same_hits(**moved, *fresh, rays), 4000);
  // The old top is untouched: it still agrees with a build over the old transforms.
  auto old = build_instance_top(f.instances, f.meshes);
  EXPECT_GT(expect_same_hits(*top, *old, rays), 4000);
  // And the box of the instance dropped low went down with it.
  const uint32_t p = (*moved)->position[30];
  EXPECT_LT((*moved)->hi[p].y, top->hi[top->position[30]].y - 2.0f);
}

TEST(InstanceMotion, ScatteringInstancesRebuildsTheTopLevel) {
  Field f = make_field(100);
  auto top = build_instance_top(f.instances, f.meshes);
  // Scatter the grid (instance k to place 37k + 11 mod 100): neighbours in a leaf land far
  // apart, so the refit leaves boxes spanning the field.
  std::vector<InstanceMove> moves;
  for (uint32_t k = 0; k < 100; ++k) moves.push_back({k, placement(int((37 * k + 11) % 100), 2.5f)});
  InstanceUpdate u;
  auto moved = move_instances(*top, moves, {}, &u);
  ASSERT_TRUE(moved) << moved.error().message;
  EXPECT_TRUE(u.rebuilt);
  EXPECT_LE((*moved)->cost, kRebuildFactor * (*moved)->built_cost);
  std::vector<Instance> expect(100);
  for (const InstanceMove& m : moves) ASSERT_TRUE(make_instance(0, m.to_world, expect[m.index]));
  auto fresh = build_instance_top(expect, f.meshes);
  EXPECT_GT(expect_same_hits(**moved, *fresh, field_rays(10000, 5)), 2000);
}

TEST(InstanceMotion, BadMovesAreRefusedAndChangeNothing) {
  Field f = make_field(10);
  auto top = build_instance_top(f.instances, f.meshes);
  Affine singular;
  singular.m = glm::mat3(0.0f);
  auto r = move_instances(*top, {{2, placement(2, 1.0f)}, {10, placement(0, 1.0f)}});
  ASSERT_FALSE(r);
  EXPECT_EQ(r.error().message, "move 1: instance 10 out of range (the scene has 10)");
  r = move_instances(*top, {{3, singular}});
  ASSERT_FALSE(r);
  EXPECT_EQ(r.error().message, "move 0: instance 3: singular or non-finite transform");
  Affine nan = placement(1, 1.0f);
  nan.t.x = std::nanf("");
  EXPECT_FALSE(move_instances(*top, {{1, nan}}));
  EXPECT_EQ(top->instances[top->position[2]].to_world.t, placement(2, 2.5f).t);
}

TEST(InstanceMotion, JsonInstanceMotionIsParsedAndChecked) {
  const std::string head = R"({
  "materials": {"red": {"class": "diffuse", "kd": [0.8, 0.1, 0.1]}},
  "meshes": {"tri": {"type": "triangles", "material": "red",
                     "vertices": [[0, 0, 0], [1, 0, 0], [0, 1, 0]], "indices": [[0, 1, 2]]}},
  "objects": [{"type": "instance", "mesh": "tri"}, )";
  auto s = parse_scene_json(head + R"({"type": "instance", "mesh": "tri", "transform": {"translate": [3, 0, 0]},
      "motion": {"type": "keyframes", "keys": [{"time": 0, "translate": [0, 0, 0]}, {"time": 2, "translate": [0, 4, 0]}]}}]})",
                            "m.json", ".");
  ASSERT_TRUE(s) << s.error().message;
  ASSERT_EQ((*s)->instance_motions.size(), 1u);
  EXPECT_EQ((*s)->instance_motions[0].index, 1u);
  EXPECT_EQ(motion_offset((*s)->instance_motions[0].motion, 1.0).y, 2.0f);
  auto bad = parse_scene_json(head + R"({"type": "instance", "mesh": "tri", "motion": {"type": "physics"}}]})",
                              "m.json", ".");
  ASSERT_FALSE(bad);
  EXPECT_NE(bad.error().message.find("objects[1].motion.type"), std::string::npos) << bad.error().message;
  EXPECT_EQ(bad.error().message.find('\n'), std::string::npos);
}

}  // namespace
}  // namespace frameless
