// Reconfiguring a stopped engine: the display side keeps working before the next start().
#include <gtest/gtest.h>

#include "collecting_sink.h"
#include "frameless/engine.h"
#include "test_shaders.h"

namespace frameless::testing {
namespace {

TEST(EngineReconfigure, MoreThreadsWhileStoppedThenCollectAndRestart) {
  const Scene scene;
  EngineConfig c = test_config(40, 30, 2, noisy_shader);
  c.deterministic = true;
  Engine e(scene, c, camera_at(0));
  e.start();
  e.advance(0.01);
  e.stop();
  e.set_threads(5);  // stopped: the counters still describe 2 threads
  EXPECT_EQ(e.thread_count(), 5);
  UpdateCursor cursor;
  CollectingSink sink;
  const CollectResult r = e.collect(cursor, sink);
  EXPECT_EQ(r.width, 40);
  EXPECT_FALSE(sink.updates.empty());  // what was rendered before the change is still collected
  EXPECT_LE(e.stats().threads.size(), 5u);
  e.start();  // the new thread count takes effect and every thread renders
  e.advance(0.01);
  e.advance(0.01);
  const EngineStats s = e.stats();
  ASSERT_EQ(s.threads.size(), 5u);
  for (const ThreadStats& t : s.threads) EXPECT_GT(t.samples, 0u);
  e.collect(cursor, sink);
  EXPECT_FALSE(sink.updates.empty());
}

}  // namespace
}  // namespace frameless::testing

namespace frameless::testing {
namespace {

// Busy time feeds the balance statistics: every thread that rendered reports CPU time, and
// no thread reports more CPU time than the run lasted (plus scheduling slack).
TEST(EngineInstrumentation, BusyTimePerThreadInDeterministicMode) {
  const Scene scene;
  EngineConfig c = test_config(64, 48, 3, noisy_shader);
  c.deterministic = true;
  c.samples_per_tick = 20000;
  Engine e(scene, c, camera_at(0));
  e.start();
  for (int k = 0; k < 20; ++k) e.advance(0.01);
  const EngineStats s = e.stats();
  ASSERT_EQ(s.threads.size(), 3u);
  for (const ThreadStats& t : s.threads) {
    EXPECT_GT(t.samples, 0u);
    EXPECT_GT(t.busy_seconds, 0.0);
  }
}

}  // namespace
}  // namespace frameless::testing
