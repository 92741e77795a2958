// Instances moved while the engine renders: after the pick-up every pixel's newest sample is
// bit for bit the sample of a scene that declared the instance where it was moved to (both
// modes, deterministic); bad moves are refused; animated instances follow their motion.
#include <gtest/gtest.h>

#include <cstring>

#include "core/scenes/scene_load.h"
#include "frameless/engine.h"
#include "frameless/tile_render.h"

namespace frameless {
namespace {

// A floor and three placements of a shared tetrahedron; the second placed at `x2`.
std::string scene_text(float x2, bool moving = false) {
  return R"({
  "camera": {"eye": [0, 3, 7], "look": [0, 0.5, 0], "up": [0, 1, 0], "fov": 45},
  "lights": [{"type": "point", "position": [3, 6, 4], "color": [1, 1, 1]}],
  "materials": {"floor": {"class": "diffuse", "kd": [0.6, 0.6, 0.6]},
                "red": {"class": "polished", "kd": [0.7, 0.1, 0.1], "r0": 0.05, "phong_exponent": 40}},
  "meshes": {"tetra": {"type": "triangles", "material": "red",
      "vertices": [[-0.8, 0, -0.8], [0.8, 0, -0.8], [0, 0, 0.8], [0, 1.4, 0]],
      "indices": [[0, 2, 1], [0, 1, 3], [1, 2, 3], [2, 0, 3]]}},
  "objects": [
    {"type": "plane", "point": [0, 0, 0], "normal": [0, 1, 0], "size": 20, "material": "floor"},
    {"type": "instance", "mesh": "tetra", "transform": {"translate": [-2, 0, 0]}},
    {"type": "instance", "mesh": "tetra", "transform": {"translate": [)" +
         std::to_string(x2) + R"(, 0, 0], "scale": [1, 1.5, -1]})" +
         (moving ? R"(, "motion": {"type": "keyframes", "keys": [{"time": 0, "translate": [0, 0, 0]},
                                                      {"time": 1, "translate": [2, 0, 0]}]})"
                 : "") +
         R"(},
    {"type": "instance", "mesh": "tetra", "transform": {"translate": [2, 0, 1], "rotate": {"axis": [0, 1, 0], "degrees": 40}}}
  ]})";
}

std::unique_ptr<Scene> load(float x2, bool moving = false) {
  auto s = parse_scene_json(scene_text(x2, moving), "t.json", ".");
  EXPECT_TRUE(s) << s.error().message;
  return s ? std::move(*s) : nullptr;
}

// Newest samples after 10 ticks; the instance is moved to x = 1.1 after tick `move_at` (-1: never).
std::vector<PixelSnapshot> run(const Scene& s, RenderMode mode, int move_at) {
  EngineConfig c;
  c.width = 40;
  c.height = 30;
  c.threads = 3;
  c.mode = mode;
  c.deterministic = true;
  c.update_percent = 5.0;
  c.samples_per_tick = uint64_t(c.width) * c.height;
  Engine e(s, c, s.camera);
  for (int t = 0; t < 10; ++t) {
    e.advance(1.0 / 30);
    if (t == move_at) {
      Affine a = e.instance_transform(1);
      a.t.x = 1.1f;
      InstanceUpdate u;
      EXPECT_EQ(e.move_instances({{1, a}}, &u), 2u);
      EXPECT_EQ(u.moved, 1u);
    }
  }
  std::vector<PixelSnapshot> out(size_t(c.width) * c.height);
  for (int y = 0; y < c.height; ++y)
    for (int x = 0; x < c.width; ++x) e.read_pixel(x, y, out[size_t(y) * c.width + x]);
  return out;
}

size_t differing_samples(const std::vector<PixelSnapshot>& a, const std::vector<PixelSnapshot>& b) {
  size_t n = 0;
  for (size_t i = 0; i < a.size(); ++i) n += std::memcmp(&a[i].sample, &b[i].sample, sizeof a[i].sample) != 0;
  return n;
}

TEST(InstanceMotionEngine, MovedInstanceRendersLikeOneDeclaredThere) {
  auto at_start = load(-0.2f), there = load(1.1f);
  ASSERT_TRUE(at_start && there);
  for (RenderMode mode : {RenderMode::frameless, RenderMode::conventional}) {
    const auto moved = run(*at_start, mode, 3);
    EXPECT_EQ(differing_samples(moved, run(*there, mode, -1)), 0u) << to_string(mode);
    // It bites: without the move the images differ where the instance was and is.
    EXPECT_GT(differing_samples(run(*at_start, mode, -1), run(*there, mode, -1)), 20u);
  }
}

TEST(InstanceMotionEngine, BadMovesThrowAndPublishNothing) {
  auto s = load(0.0f);
  ASSERT_TRUE(s);
  EngineConfig c;
  c.width = 8;
  c.height = 8;
  c.threads = 1;
  Engine e(*s, c, s->camera);
  EXPECT_THROW(e.move_instances({{3, Affine{}}}), std::invalid_argument);
  Affine singular;
  singular.m = glm::mat3(0.0f);
  EXPECT_THROW(e.move_instances({{0, singular}}), std::invalid_argument);
  EXPECT_THROW(e.instance_transform(3), std::out_of_range);
  EXPECT_EQ(e.instances_epoch(), 1u);
  EXPECT_EQ(e.animate_instances(0.5), 0u);  // no instance has a motion
}

TEST(InstanceMotionEngine, AnimatedInstancesFollowTheirMotion) {
  auto s = load(0.0f, true);
  ASSERT_TRUE(s);
  EngineConfig c;
  c.width = 8;
  c.height = 8;
  c.threads = 1;
  Engine e(*s, c, s->camera);
  EXPECT_EQ(e.animate_instances(0.25), 2u);
  EXPECT_FLOAT_EQ(e.instance_transform(1).t.x, 0.5f);
  EXPECT_FLOAT_EQ(e.instance_transform(0).t.x, -2.0f);  // no motion: stays
}

TEST(InstanceMotionEngine, RenderAtATimePlacesAnimatedInstances) {
  // `frameless render --time 0.5`: the keyframed instance has moved by 1 along x.
  auto animated = load(0.0f, true), there = load(1.0f);
  ASSERT_TRUE(animated && there);
  TileRenderOptions o;
  o.spp = 1;
  o.threads = 2;
  o.time = 0.5;
  const CameraBasis b = make_camera_basis(animated->camera, 40, 30);
  const RenderedImage moved = render_tiles(*animated, b, o);
  EXPECT_EQ(moved.rgb, render_tiles(*there, b, o).rgb);
  o.time = 0.0;  // and at time 0 it is still where it was declared
  EXPECT_NE(render_tiles(*animated, b, o).rgb, moved.rgb);
}

}  // namespace
}  // namespace frameless
