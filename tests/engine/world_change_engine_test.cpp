// A light or material changed while the engine runs (the world channel): the pixels it affects
// restart their statistics, the others keep theirs, and every mean then converges to the changed
// world without the cap that moving objects put on it (frameless/engine_impl.h, FramelessWorker).
#include <gtest/gtest.h>

#include "core/scenes/scene_load.h"
#include "frameless/engine.h"

namespace frameless {
namespace {

// A grey square lit from above, seen from above; the corners of the image see the black sky.
constexpr const char* kLitFloor = R"({
  "camera": {"eye": [0, 10, 0.001], "look": [0, 0, 0], "fov": 60},
  "ambient": {"type": "constant", "color": [0.1, 0.1, 0.1]},
  "lights": [{"type": "point", "position": [0, 8, 0], "color": [1, 1, 1]}],
  "materials": {"floor": {"class": "diffuse", "kd": [0.5, 0.5, 0.5]}},
  "objects": [{"type": "plane", "point": [0, 0, 0], "normal": [0, 1, 0], "size": 4, "material": "floor"}]
})";

constexpr int kSize = 32;

struct Probe {
  PixelSnapshot floor, sky;  // the image's centre and its corner
};

// Renders `before` ticks (every pixel once per tick), optionally brightens the light, then `after`.
Probe run(const Scene& s, RenderMode mode, int before, int after, float light_scale) {
  EngineConfig c;
  c.width = c.height = kSize;
  c.threads = 2;
  c.mode = mode;
  c.deterministic = true;
  c.samples_per_tick = kSize * kSize * 2;
  c.motion_history = 8;
  Engine e(s, c, s.camera);
  for (int k = 0; k < before; ++k) e.advance(0.05);
  if (light_scale != 1.0f) {
    WorldState w = e.world();
    w.lights[0].color *= light_scale;
    e.publish_world(w);
  }
  for (int k = 0; k < after; ++k) e.advance(0.05);
  Probe p;
  e.read_pixel(kSize / 2, kSize / 2, p.floor);
  e.read_pixel(0, 0, p.sky);
  return p;
}

std::unique_ptr<Scene> lit_floor() {
  auto scene = parse_scene_json(kLitFloor, "floor.json", ".");
  EXPECT_TRUE(scene) << scene.error().message;
  return scene ? std::move(*scene) : nullptr;
}

void expect_restart_where_affected(RenderMode mode) {
  auto scene = lit_floor();
  ASSERT_TRUE(scene);
  const Probe before = run(*scene, mode, 20, 0, 1.0f);
  const Probe changed = run(*scene, mode, 20, 20, 2.0f);
  // The reference: a scene whose light was twice as bright from the start.
  auto bright = lit_floor();
  bright->lights[0].color *= 2.0f;
  const Probe reference = run(*bright, mode, 0, 20, 1.0f);

  ASSERT_GT(before.floor.count, 8u);
  ASSERT_GT(reference.floor.mean.x, 1.5f * before.floor.mean.x);  // the change is visible
  // The lit floor restarted at the change: only samples of the brighter world are in its mean,
  // which equals the reference's (a mix with the old samples would sit well below it)...
  EXPECT_LE(changed.floor.count, reference.floor.count);
  EXPECT_NEAR(changed.floor.mean.x, reference.floor.mean.x, 0.01f * reference.floor.mean.x);
  // ...and it keeps converging after the change: its count is not capped at motion_history.
  EXPECT_GT(changed.floor.count, 8u * 2u);
  // The sky did not change: it kept (a short) history instead of restarting.
  EXPECT_GT(changed.sky.count, reference.sky.count);
  EXPECT_EQ(changed.sky.mean.x, reference.sky.mean.x);
}

TEST(WorldChange, FramelessRestartsTheAffectedPixelsAndConvergesAfterwards) {
  expect_restart_where_affected(RenderMode::frameless);
}

TEST(WorldChange, ConventionalFramesDoTheSame) { expect_restart_where_affected(RenderMode::conventional); }

}  // namespace
}  // namespace frameless
