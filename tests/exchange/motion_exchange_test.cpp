// Reprojection and closed-loop sampling with real threads (run under ThreadSanitizer in CI):
// 3 render threads walking and serving the display's asks, the display thread at 240 Hz moving
// its image at every camera change and asking for what it guessed, a consumer, a camera moving
// at 200 Hz and a layout change (thread count) and a resize while everything runs. A plane
// shader gives every sample a point, so every path of reprojection runs. And a consumer that
// asks after a quiet spell, while the display moves the image it took back.
#include <gtest/gtest.h>

#include <atomic>
#include <chrono>
#include <cmath>
#include <cstdlib>
#include <thread>

#include "../engine/test_shaders.h"
#include "display/display_thread.h"

namespace frameless {
namespace {

using namespace frameless::testing;
using Clock = std::chrono::steady_clock;

// The plane z = 0, striped in x (a colour that moves with the surface), and the sky above it.
SampleResult plane_shader(const void*, const CameraBasis& b, float px, float py, uint64_t) {
  const Ray r = camera_ray(b, px, py);
  SampleResult out;
  const float t = r.dir.z < 0.0f ? -r.org.z / r.dir.z : -1.0f;
  if (t > 0.0f) {
    out.position = r.org + t * r.dir;
    out.object = kPointStatic;
    out.depth = t;
    out.color = Vec3(0.5f + 0.5f * std::sin(4.0f * out.position.x));
  } else {
    out.position = r.dir;
    out.object = kPointSky;
    out.color = Vec3(0.2f, 0.3f, 0.9f);
  }
  return out;
}

Camera looking_down(float x) {
  Camera c;
  c.eye = Vec3(x, -3.0f, 4.0f);
  c.look = Vec3(x, 0.0f, 0.0f);
  c.up = Vec3(0.0f, 0.0f, 1.0f);
  return c;
}

TEST(MotionExchange, ReprojectionAndClosedLoopUnderACameraMoveAndLayoutChanges) {
  const double seconds = std::getenv("FRAMELESS_LONG_TESTS") ? 30.0 : 2.0;
  EngineConfig c = test_config(96, 64, 3, plane_shader);
  c.update_percent = 2;
  c.closed_loop = true;
  Engine e(kEmptyScene, c, looking_down(0.0f));
  DisplayConfig dc;
  dc.refresh_hz = 240;
  dc.blend.reproject = true;
  dc.blend.temporal = true;
  DisplayThread d(e, dc);
  std::atomic<bool> done{false};
  uint64_t consumed = 0, non_finite = 0;
  std::thread consumer([&] {
    while (!done.load()) {
      bool fresh = false;
      const DisplayImage& img = d.acquire_latest(&fresh);
      if (fresh) {
        ++consumed;
        for (float v : img.rgb) non_finite += !std::isfinite(v);
      }
      std::this_thread::sleep_for(std::chrono::milliseconds(2));
    }
  });
  e.start();
  d.start();
  const auto begin = Clock::now();
  const auto end = begin + std::chrono::duration<double>(seconds);
  auto next = begin;
  int k = 0, third = 0;
  while (Clock::now() < end) {
    next += std::chrono::milliseconds(5);
    std::this_thread::sleep_until(next);
    e.publish_camera(looking_down(0.01f * float(++k)));
    const int q = int(3.0 * std::chrono::duration<double>(Clock::now() - begin).count() / seconds);
    if (q == third) continue;
    third = q;
    if (q == 1) e.set_threads(2);    // new partition: new slots, new rings
    if (q == 2) e.resize(80, 48);    // the display's points start over
  }
  d.stop();
  done = true;
  consumer.join();
  e.stop();
  EXPECT_FALSE(e.error());
  EXPECT_FALSE(d.error());
  const DisplayStats s = d.stats();
  EXPECT_GT(s.ticks, 20u);
  EXPECT_GT(s.reproject.reprojections, 5u);
  EXPECT_GT(s.reproject.moved, 0u);
  EXPECT_GT(consumed, 0u);
  EXPECT_EQ(non_finite, 0u);
  EXPECT_EQ(s.rejected, 0u);
}

// A consumer that asks after a quiet spell (the display has been blending into its untaken newest
// image, as in a headless run) still gets that image, even while the display holds it to move it
// (a camera change): the call waits for that tick's publish instead of returning an older image
// or, on a first call, none at all.
TEST(MotionExchange, AConsumerAfterAQuietSpellGetsTheNewestImage) {
#if defined(__SANITIZE_THREAD__) || (defined(__has_feature) && __has_feature(thread_sanitizer))
  const int width = 256, height = 144;  // instrumented: a move still spans several display periods
#else
  const int width = 1280, height = 720;  // a move of 10 ms or so: most calls land inside one
#endif
  EngineConfig c = test_config(width, height, 2, plane_shader);
  Engine e(kEmptyScene, c, looking_down(0.0f));
  DisplayConfig dc;
  dc.refresh_hz = 240;
  dc.blend.reproject = true;
  DisplayThread d(e, dc);
  e.start();
  d.start();
  int stale = 0, rounds = 0;
  uint64_t last = 0;
  for (; rounds < 20; ++rounds) {
    while (d.stats().ticks < last + 12) std::this_thread::sleep_for(std::chrono::milliseconds(1));
    e.publish_camera(looking_down(0.01f * float(rounds + 1)));  // the next tick moves the image
    std::this_thread::sleep_for(std::chrono::milliseconds(1 + 5 * rounds % 12));  // spread over the move
    const uint64_t published = d.stats().ticks;  // ticks 0 .. published - 1 are out
    bool fresh = false;
    const DisplayImage& img = d.acquire_latest(&fresh);
    stale += !fresh || img.width != width || img.info.index + 1 < published;
    last = d.stats().ticks;
  }
  const DisplayStats s = d.stats();
  d.stop();
  e.stop();
  EXPECT_FALSE(d.error());
  EXPECT_GT(s.reclaimed, 0u);  // the quiet spells did take images back
  EXPECT_GT(s.reproject.reprojections, 0u);
  EXPECT_EQ(stale, 0) << stale << " stale of " << rounds << " calls";
}

}  // namespace
}  // namespace frameless
