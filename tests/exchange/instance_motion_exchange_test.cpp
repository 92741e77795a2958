// Instances moved at 500 Hz by the application while 3 render threads and a 240 Hz display run:
// the top-level pick-up (a pointer copy under a mutex at the update percentage, never per
// sample) is race-free (CI runs this suite under ThreadSanitizer) and keeps rendering.
#include <gtest/gtest.h>

#include <chrono>
#include <cmath>
#include <thread>

#include "core/scenes/scene_load.h"
#include "display/display_thread.h"
#include "frameless/engine.h"

namespace frameless {
namespace {

constexpr const char* kScene = R"({
  "camera": {"eye": [0, 3, 7], "look": [0, 0.5, 0], "up": [0, 1, 0], "fov": 45},
  "lights": [{"type": "point", "position": [3, 6, 4], "color": [1, 1, 1]}],
  "materials": {"floor": {"class": "diffuse", "kd": [0.6, 0.6, 0.6]},
                "red": {"class": "diffuse", "kd": [0.7, 0.1, 0.1]}},
  "meshes": {"tetra": {"type": "triangles", "material": "red",
      "vertices": [[-0.8, 0, -0.8], [0.8, 0, -0.8], [0, 0, 0.8], [0, 1.4, 0]],
      "indices": [[0, 2, 1], [0, 1, 3], [1, 2, 3], [2, 0, 3]]}},
  "objects": [
    {"type": "plane", "point": [0, 0, 0], "normal": [0, 1, 0], "size": 20, "material": "floor"},
    {"type": "instance", "mesh": "tetra", "transform": {"translate": [-2, 0, 0]}},
    {"type": "instance", "mesh": "tetra"},
    {"type": "instance", "mesh": "tetra", "transform": {"translate": [2, 0, 0]}}
  ]})";

TEST(InstanceMotionExchange, MovingInstancesAt500HzWhileRenderingAndDisplaying) {
  auto s = parse_scene_json(kScene, "t.json", ".");
  ASSERT_TRUE(s) << s.error().message;
  EngineConfig c;
  c.width = 48;
  c.height = 36;
  c.threads = 3;
  c.update_percent = 2.0;
  Engine e(**s, c, (*s)->camera);
  DisplayConfig dc;
  dc.refresh_hz = 240;
  DisplayThread d(e, dc);
  e.start();
  d.start();
  const auto begin = std::chrono::steady_clock::now();
  auto next = begin;
  uint32_t epoch = 0;
  for (int k = 0; std::chrono::steady_clock::now() - begin < std::chrono::milliseconds(1200); ++k) {
    next += std::chrono::milliseconds(2);
    std::this_thread::sleep_until(next);
    Affine a = e.instance_transform(uint32_t(k % 3));
    a.t.z = 0.5f * std::sin(0.05f * float(k));
    epoch = e.move_instances({{uint32_t(k % 3), a}});
  }
  d.stop();
  e.stop();
  EXPECT_FALSE(e.error()) << *e.error();
  EXPECT_GT(epoch, 100u);
  EXPECT_GT(e.stats().samples, 1000u);
}

}  // namespace
}  // namespace frameless
