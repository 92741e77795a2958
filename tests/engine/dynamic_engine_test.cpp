// The engine with objects that move: samples see objects at their own instant, and a pixel
// whose content moved is blended anew instead of averaged forever with what was there before.
#include <gtest/gtest.h>

#include "core/scenes/scene_load.h"
#include "frameless/engine.h"

namespace frameless {
namespace {

// A red ball over a grey floor, seen from above; at t = 1 it jumps from x = -2 to x = +2.
constexpr const char* kJumpScene = R"({
  "camera": {"eye": [0, 10, 0.001], "look": [0, 0, 0], "fov": 60},
  "ambient": {"type": "constant", "color": [0.2, 0.2, 0.2]},
  "lights": [{"type": "point", "position": [0, 8, 0], "color": [1, 1, 1]}],
  "materials": {"floor": {"class": "diffuse", "kd": [0.5, 0.5, 0.5]},
                "ball": {"class": "diffuse", "kd": [0.9, 0.05, 0.05]}},
  "objects": [
    {"type": "plane", "point": [0, 0, 0], "normal": [0, 1, 0], "size": 40, "material": "floor"},
    {"type": "sphere", "center": [0, 1, 0], "radius": 1.2, "material": "ball",
     "motion": {"type": "keyframes", "loop": false,
                "keys": [{"time": 0, "translate": [-2, 0, 0]}, {"time": 1, "translate": [-2, 0, 0]},
                         {"time": 1.001, "translate": [2, 0, 0]}]}}
  ]
})";

// The pixel that sees world point (x, 0, 0) (the camera looks straight down, x to the right).
int pixel_x(const Scene& s, int w, float x) {
  const CameraBasis b = make_camera_basis(s.camera, w, w);
  int best = 0;
  float best_d = kInfinity;
  for (int px = 0; px < w; ++px) {
    const Ray r = camera_ray(b, float(px) + 0.5f, float(w) / 2);
    const float t = -r.org.y / r.dir.y;
    const float d = std::fabs(r.org.x + t * r.dir.x - x);
    if (d < best_d) best_d = d, best = px;
  }
  return best;
}

struct Pixels {
  PixelSnapshot left, right;  // the pixels under x = -2 and x = +2
};

Pixels run(const Scene& s, int motion_history) {
  EngineConfig c;
  c.width = c.height = 48;
  c.threads = 2;
  c.deterministic = true;
  c.samples_per_tick = 48 * 48 * 2;  // every pixel once per tick
  c.motion_history = motion_history;
  Engine e(s, c, s.camera);
  for (int k = 0; k < 40; ++k) e.advance(0.05);  // t = 0..2: 20 ticks before the jump, 20 after
  Pixels r;
  const int y = 24;
  e.read_pixel(pixel_x(s, 48, -2.0f), y, r.left);
  e.read_pixel(pixel_x(s, 48, 2.0f), y, r.right);
  return r;
}

TEST(DynamicEngine, MovedContentIsBlendedAnewNotAveragedForever) {
  auto scene = parse_scene_json(kJumpScene, "jump.json", ".");
  ASSERT_TRUE(scene) << scene.error().message;
  const Pixels r = run(**scene, 32);
  // After the jump the left pixel shows the floor again: its statistics restarted when the
  // samples stopped agreeing with the red mean, so the mean is grey, not a red-grey mix.
  EXPECT_NEAR(r.left.mean.x, r.left.mean.y, 0.02f) << r.left.mean.x << " " << r.left.mean.y;
  EXPECT_LE(r.left.count, 2u * 20u + 1u);
  // The right pixel now shows the ball.
  EXPECT_GT(r.right.mean.x, 3.0f * r.right.mean.y);
  // The count saturates at motion_history: the mean keeps forgetting while things move.
  const Pixels capped = run(**scene, 4);
  EXPECT_LE(capped.left.count, 4u);
  EXPECT_LE(capped.right.count, 4u);
}

TEST(DynamicEngine, ConventionalFramesSeeOneInstantAndRunsAreReproducible) {
  auto scene = parse_scene_json(kJumpScene, "jump.json", ".");
  ASSERT_TRUE(scene) << scene.error().message;
  const Pixels a = run(**scene, 32), b = run(**scene, 32);
  EXPECT_EQ(a.left.mean, b.left.mean);  // motion is a function of virtual time: bit-identical
  EXPECT_EQ(a.right.count, b.right.count);
  EngineConfig c;
  c.width = c.height = 48;
  c.threads = 2;
  c.deterministic = true;
  c.mode = RenderMode::conventional;
  c.samples_per_tick = 48 * 48 * 2;
  Engine e(**scene, c, (*scene)->camera);
  for (int k = 0; k < 40; ++k) e.advance(0.05);
  PixelSnapshot right;
  e.read_pixel(pixel_x(**scene, 48, 2.0f), 24, right);
  EXPECT_GT(right.mean.x, 3.0f * right.mean.y);  // the frames after the jump show the ball there
}

}  // namespace
}  // namespace frameless
