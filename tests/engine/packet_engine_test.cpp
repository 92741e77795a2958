// Ray packets in the engine change speed, not images: deterministic runs with packets and ray by
// ray publish bit-identical pixels in both modes, with camera changes, adaptive skips, moving
// objects, and thread lists shorter than a packet.
#include <gtest/gtest.h>

#include <cstring>
#include <vector>

#include "core/scenes/scene_load.h"
#include "frameless/engine.h"

namespace frameless {
namespace {

struct Case {
  const char* scene;
  RenderMode mode;
  bool adaptive;
  bool jitter;
  int width, height, threads;
};

std::vector<PixelSnapshot> run(const Scene& s, const Case& k, bool packets, uint64_t seed = 1) {
  EngineConfig c;
  c.width = k.width;
  c.height = k.height;
  c.threads = k.threads;
  c.mode = k.mode;
  c.deterministic = true;
  c.seed = seed;
  c.jitter = k.jitter;
  c.packets = packets;
  c.update_percent = 7.0;  // camera pick-ups fall inside packets' gathering
  c.adaptive.enabled = k.adaptive;
  c.samples_per_tick = uint64_t(k.width) * k.height;
  Engine e(s, c, s.camera);
  Camera moved = s.camera;
  moved.eye += 0.3f * (s.camera.look - s.camera.eye);
  for (int t = 0; t < 14; ++t) {
    if (t == 6) e.publish_camera(moved);
    e.advance(1.0 / 30);
  }
  std::vector<PixelSnapshot> out(size_t(k.width) * k.height);
  for (int y = 0; y < k.height; ++y)
    for (int x = 0; x < k.width; ++x) e.read_pixel(x, y, out[size_t(y) * k.width + x]);
  return out;
}

bool same(const std::vector<PixelSnapshot>& a, const std::vector<PixelSnapshot>& b) {
  for (size_t i = 0; i < a.size(); ++i) {
    const PixelSnapshot &p = a[i], &q = b[i];
    if (std::memcmp(&p.sample, &q.sample, sizeof p.sample) || std::memcmp(&p.mean, &q.mean, sizeof p.mean) ||
        std::memcmp(&p.variance, &q.variance, sizeof p.variance) || p.count != q.count ||
        p.epoch != q.epoch || std::memcmp(&p.time, &q.time, sizeof p.time))
      return false;
  }
  return true;
}

TEST(PacketEngine, PacketsGiveTheSameImagesAsSingleRays) {
  const Case cases[] = {
      {"default", RenderMode::frameless, false, true, 40, 30, 3},
      {"default", RenderMode::conventional, false, true, 40, 30, 2},
      {"default", RenderMode::frameless, true, false, 36, 28, 2},   // adaptive skips
      {"balls", RenderMode::frameless, false, true, 32, 24, 2},     // moving objects, per-sample time
      {"balls", RenderMode::conventional, false, false, 32, 24, 3},
      {"default", RenderMode::frameless, false, true, 3, 5, 4},     // 3-4 pixels per thread
  };
  for (const Case& k : cases) {
    auto scene = make_builtin_scene(k.scene);
    ASSERT_TRUE(scene) << scene.error().message;
    const auto packets = run(**scene, k, true);
    EXPECT_TRUE(same(packets, run(**scene, k, false)))
        << k.scene << " " << to_string(k.mode) << (k.adaptive ? " adaptive" : "");
    // The comparison can fail: another seed jitters other sample positions.
    if (k.jitter) {
      EXPECT_FALSE(same(packets, run(**scene, k, true, 2))) << k.scene;
    }
  }
}

}  // namespace
}  // namespace frameless
