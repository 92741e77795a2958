// What moves while you look, with real threads (run under ThreadSanitizer in CI): the world
// channel never hands a reader a torn record, and the engine keeps rendering a scene whose
// application side moves objects, a light and a material at 1 kHz while 4 render threads and a
// 240 Hz display run.
#include <gtest/gtest.h>

#include <atomic>
#include <chrono>
#include <cstdlib>
#include <thread>

#include "core/scene/dynamic.h"
#include "core/scene/scene.h"
#include "core/scene/scene_finalize.h"
#include "core/scenes/builtin_scenes.h"
#include "display/display_thread.h"
#include "frameless/world_channel.h"

namespace frameless {
namespace {

using Clock = std::chrono::steady_clock;

TEST(WorldChannel, ReadersNeverSeeATornRecord) {
  // Record k holds k in every float: a torn read would mix two values.
  WorldChannel ch(std::vector<float>(257, 1.0f));
  std::atomic<bool> done{false};
  std::atomic<uint64_t> reads{0}, torn{0}, backwards{0};
  std::atomic<int> started{0};  // readers that have read once: the writer waits for all of them
  std::vector<std::thread> readers;
  for (int r = 0; r < 3; ++r)
    readers.emplace_back([&] {
      std::vector<float> buf;
      uint32_t last = 0;
      while (!done.load(std::memory_order_relaxed)) {
        const uint32_t ep = ch.read(buf);
        if (last == 0) ++started;  // this reader's first read (epochs start at 1)
        ++reads;
        for (float v : buf) torn += v != buf[0];
        backwards += ep < last;
        torn += buf[0] != float(ep);  // record k is published as epoch k
        last = ep;
      }
    });
  std::vector<float> rec(257);
  // On a loaded machine the readers may start late: publish only once they all read.
  const auto give_up = Clock::now() + std::chrono::seconds(20);
  while (started.load() < 3 && Clock::now() < give_up) std::this_thread::yield();
  for (uint32_t k = 2; k <= 20000; ++k) {
    std::fill(rec.begin(), rec.end(), float(k));
    ASSERT_EQ(ch.publish(rec.data(), rec.size()), k);
  }
  done = true;
  for (std::thread& t : readers) t.join();
  EXPECT_GT(reads.load(), 0u);
  EXPECT_EQ(torn.load(), 0u);
  EXPECT_EQ(backwards.load(), 0u);
  EXPECT_EQ(ch.publish(rec.data(), rec.size() - 1), 0u);  // wrong size: refused
}

TEST(WorldMotion, ApplicationMovesObjectsAt1kHzWhileRenderingAndDisplaying) {
  const double seconds = std::getenv("FRAMELESS_LONG_TESTS") ? 20.0 : 1.5;
  auto scene = make_balls();
  finalize_scene(*scene);
  ASSERT_GT(scene->dynamic.size(), 0u);
  EngineConfig c;
  c.width = 64;
  c.height = 48;
  c.threads = 4;
  c.update_percent = 2.0;
  Engine e(*scene, c, scene->camera);
  DisplayConfig dc;
  dc.refresh_hz = 240;
  DisplayThread d(e, dc);
  e.start();
  d.start();
  WorldState w = e.world();
  const auto begin = Clock::now();
  auto next = begin;
  uint32_t published = 0;
  while (Clock::now() - begin < std::chrono::duration<double>(seconds)) {
    next += std::chrono::milliseconds(1);
    std::this_thread::sleep_until(next);
    const float s = float(published % 100) * 0.01f;
    w.object_position[0].x = s;             // drag a ball
    w.lights[0].position.y = 9.0f + s;      // move the light
    w.materials[0].kd = Vec3(0.5f + 0.2f * s);  // and tint the floor
    published = e.publish_world(w);
  }
  // A world that does not fit the scene is refused without reaching the render threads.
  WorldState bad = w;
  bad.object_position.pop_back();
  EXPECT_THROW(e.publish_world(bad), std::invalid_argument);
  bad = w;
  bad.lights[0].position.x = std::numeric_limits<float>::quiet_NaN();
  EXPECT_THROW(e.publish_world(bad), std::invalid_argument);
  d.stop();
  e.stop();
  EXPECT_FALSE(e.error());
  EXPECT_FALSE(d.error());
  EXPECT_EQ(e.world_epoch(), published);
  EXPECT_EQ(e.world().lights[0].position.y, w.lights[0].position.y);
  const EngineStats st = e.stats();
  EXPECT_GT(st.samples, 0u);
  EXPECT_EQ(st.dropped, 0u);
  EXPECT_GT(d.stats().ticks, 5u);
}

}  // namespace
}  // namespace frameless
