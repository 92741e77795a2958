// The engine's per-pixel reflection/refraction levels (the reflection depth view, issue 12): a
// pixel that sees a mirror reports the levels its rays went through, a diffuse surface reports
// none, in both modes, and read_pixel and copy_levels agree.
#include <gtest/gtest.h>

#include <cmath>

#include "core/scenes/scene_load.h"
#include "frameless/engine.h"

namespace frameless {
namespace {

// Two facing mirrors 10 apart with the camera between them, looking straight at one; a diffuse
// ball left of the view's centre. A ray near the axis bounces between the mirrors until the
// depth limit (25 by default); a ray that meets the ball stops there.
constexpr const char* kMirrorScene = R"({
  "camera": {"eye": [0, 0, 0], "look": [0, 0, -1], "fov": 60},
  "materials": {"mirror": {"class": "metal", "ks": [0.95, 0.95, 0.95]},
                "chalk": {"class": "diffuse", "kd": [0.8, 0.8, 0.8]}},
  "objects": [
    {"type": "plane", "point": [0, 0, -5], "normal": [0, 0, 1], "size": 60, "material": "mirror"},
    {"type": "plane", "point": [0, 0, 5], "normal": [0, 0, -1], "size": 60, "material": "mirror"},
    {"type": "sphere", "center": [-0.8, 0, -3], "radius": 0.5, "material": "chalk"}
  ]
})";

constexpr int kSize = 32;
constexpr int kRow = 16;
constexpr int kMirrorX = 16;  // just right of the axis: the mirrors, nearly head-on
constexpr int kBallX = 8;     // the diffuse ball

// Whether every corner ray of pixel (x, y) meets the ball (so any jittered sample does).
bool pixel_sees_ball(const Scene& s, int x, int y) {
  const CameraBasis b = make_camera_basis(s.camera, kSize, kSize);
  for (float dx : {0.0f, 1.0f})
    for (float dy : {0.0f, 1.0f}) {
      const Ray r = camera_ray(b, float(x) + dx, float(y) + dy);
      const Vec3 oc = r.org - Vec3(-0.8f, 0.0f, -3.0f);
      const float h = glm::dot(oc, r.dir), c = glm::dot(oc, oc) - 0.25f;
      if (h * h - c <= 0.0f) return false;
    }
  return true;
}

EngineConfig config(RenderMode mode) {
  EngineConfig c;
  c.width = c.height = kSize;
  c.threads = 2;
  c.chunk_size = 16;
  c.deterministic = true;
  c.mode = mode;
  c.samples_per_tick = kSize * kSize * 2 * 2;  // two updates of every pixel per tick
  return c;
}

TEST(EngineLevels, MirrorsReportTheirLevelsAndDiffuseSurfacesNone) {
  auto scene = parse_scene_json(kMirrorScene, "mirrors.json", ".");
  ASSERT_TRUE(scene) << scene.error().message;
  const Scene& s = **scene;
  ASSERT_TRUE(pixel_sees_ball(s, kBallX, kRow));
  ASSERT_FALSE(pixel_sees_ball(s, kMirrorX, kRow));
  for (RenderMode mode : {RenderMode::frameless, RenderMode::conventional}) {
    Engine e(s, config(mode), s.camera);
    for (int k = 0; k < 4; ++k) e.advance(0.05);
    PixelSnapshot mirror, ball;
    ASSERT_TRUE(e.read_pixel(kMirrorX, kRow, mirror));
    ASSERT_TRUE(e.read_pixel(kBallX, kRow, ball));
    ASSERT_GT(mirror.epoch, 0u);
    ASSERT_GT(ball.epoch, 0u);
    // Between facing mirrors the rays go as deep as the scene allows.
    EXPECT_EQ(mirror.levels, uint8_t(s.settings.max_depth)) << to_string(mode);
    EXPECT_EQ(ball.levels, 0u) << to_string(mode);
    // The whole array says the same, by pixel index.
    std::vector<uint8_t> levels;
    e.copy_levels(levels);
    ASSERT_EQ(levels.size(), size_t(kSize * kSize));
    EXPECT_EQ(levels[kRow * kSize + kMirrorX], mirror.levels);
    EXPECT_EQ(levels[kRow * kSize + kBallX], 0u);
    int deep = 0;
    for (uint8_t l : levels) deep += l > 0;
    EXPECT_GT(deep, kSize * kSize / 2) << "most of the view is mirror";
  }
}

// A lower depth limit caps the levels: they count the rays actually traced.
TEST(EngineLevels, LevelsFollowTheDepthLimit) {
  auto scene = parse_scene_json(kMirrorScene, "mirrors.json", ".");
  ASSERT_TRUE(scene) << scene.error().message;
  Scene& s = **scene;
  s.settings.max_depth = 7;
  Engine e(s, config(RenderMode::frameless), s.camera);
  for (int k = 0; k < 4; ++k) e.advance(0.05);
  PixelSnapshot mirror;
  ASSERT_TRUE(e.read_pixel(kMirrorX, kRow, mirror));
  EXPECT_EQ(mirror.levels, 7u);
}

}  // namespace
}  // namespace frameless
