// Engine::ingest, the cluster master's way in for pixels rendered elsewhere: a valid batch reads
// back exactly as sent (every field, the reflection depth too) and moves the thread's counters;
// every malformed batch (a thread out of range or rendered here, a slot outside the thread's
// list, an epoch from the future or 0, a count of 0, a non-finite value, falling counters) is
// refused with one line and writes nothing. Also: owned thread shares and publish_camera_as.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include "frameless/engine.h"
#include "test_shaders.h"

namespace frameless {
namespace {

using testing::camera_at;
using testing::kEmptyScene;
using testing::noisy_shader;
using testing::test_config;

EngineConfig master_config() {
  EngineConfig c = test_config(32, 24, 4, noisy_shader);
  c.owned_count = 0;  // renders nothing: every thread is remote
  return c;
}

// A batch for `thread` with one record in its first slot.
RemoteBatch batch(const Engine& e, int thread) {
  size_t first = 0;
  for (int t = 0; t < thread; ++t) first += e.partition().pixels[size_t(t)].size();
  RemoteBatch b;
  b.thread = thread;
  b.updates = 10;
  b.samples = 20;
  b.busy_ns = 5000;
  RemoteSlot s;
  s.slot = uint32_t(first);
  s.state.sample = Vec3(0.25f, 0.5f, 1.5f);
  s.state.mean = Vec3(0.3f, 0.6f, 0.9f);
  s.state.variance = 0.0625f;
  s.state.count = 7;
  s.state.epoch = 1;
  s.state.time = 0.125f;
  s.state.levels = 3;
  b.slots.push_back(s);
  return b;
}

TEST(RemoteIngest, ValidBatchReadsBackExactly) {
  Engine e(kEmptyScene, master_config(), camera_at(0));
  e.start();
  const RemoteBatch b = batch(e, 2);
  e.ingest(b);
  const uint32_t pixel = e.partition().pixels[2][0];
  PixelSnapshot got;
  ASSERT_TRUE(e.read_pixel(int(pixel % 32), int(pixel / 32), got));
  const PixelSnapshot& want = b.slots[0].state;
  EXPECT_EQ(got.sample, want.sample);
  EXPECT_EQ(got.mean, want.mean);
  EXPECT_EQ(got.variance, want.variance);
  EXPECT_EQ(got.count, want.count);
  EXPECT_EQ(got.epoch, want.epoch);
  EXPECT_EQ(got.time, want.time);
  EXPECT_EQ(got.levels, want.levels);
  const EngineStats s = e.stats();
  EXPECT_EQ(s.threads[2].updates, 10u);
  EXPECT_EQ(s.threads[2].samples, 20u);
  EXPECT_EQ(s.samples, 20u);
  e.stop();
}

TEST(RemoteIngest, MalformedBatchesAreRefusedAndWriteNothing) {
  EngineConfig c = master_config();
  c.owned_first = 3;
  c.owned_count = 1;  // thread 3 renders here
  Engine e(kEmptyScene, c, camera_at(0));
  const float nan = std::numeric_limits<float>::quiet_NaN();
  struct Case {
    const char* what;
    std::function<void(RemoteBatch&)> spoil;
    const char* expect;
  };
  const std::vector<Case> cases = {
      {"thread -1", [](RemoteBatch& b) { b.thread = -1; }, "no such render thread"},
      {"thread 4", [](RemoteBatch& b) { b.thread = 4; }, "no such render thread"},
      {"own thread", [](RemoteBatch& b) { b.thread = 3; }, "renders that thread itself"},
      {"slot of another thread", [&](RemoteBatch& b) { b.slots[0].slot += uint32_t(e.partition().pixels[1].size()); },
       "is not its own"},
      {"slot past the end", [](RemoteBatch& b) { b.slots[0].slot = 1u << 30; }, "is not its own"},
      {"future epoch", [](RemoteBatch& b) { b.slots[0].state.epoch = 2; }, "camera epoch 2 out of range"},
      {"epoch 0", [](RemoteBatch& b) { b.slots[0].state.epoch = 0; }, "camera epoch 0 out of range"},
      {"count 0", [](RemoteBatch& b) { b.slots[0].state.count = 0; }, "without samples"},
      {"NaN sample", [&](RemoteBatch& b) { b.slots[0].state.sample.y = nan; }, "non-finite"},
      {"Inf mean", [](RemoteBatch& b) { b.slots[0].state.mean.x = kInfinity; }, "non-finite"},
      {"negative variance", [](RemoteBatch& b) { b.slots[0].state.variance = -1.0f; }, "non-finite"},
  };
  e.start();
  for (const Case& k : cases) {
    RemoteBatch b = batch(e, 1);
    k.spoil(b);
    try {
      e.ingest(b);
      ADD_FAILURE() << k.what << ": accepted";
    } catch (const std::invalid_argument& ex) {
      const std::string m = ex.what();
      EXPECT_NE(m.find(k.expect), std::string::npos) << k.what << ": " << m;
      EXPECT_EQ(m.find('\n'), std::string::npos) << m;
    }
  }
  EXPECT_EQ(e.stats().threads[1].samples, 0u);  // nothing of a refused batch was written
  PixelSnapshot got;
  const uint32_t pixel = e.partition().pixels[1][0];
  ASSERT_TRUE(e.read_pixel(int(pixel % 32), int(pixel / 32), got));
  EXPECT_EQ(got.epoch, 0u);
  // Counters never fall: a valid batch, then an older one.
  e.ingest(batch(e, 1));
  RemoteBatch older = batch(e, 1);
  older.updates = 9;
  EXPECT_THROW(e.ingest(older), std::invalid_argument);
  e.stop();
}

TEST(RemoteIngest, OwnedShareRendersOnlyItsThreadsAndCamerasKeepTheMastersEpochs) {
  EngineConfig c = test_config(32, 24, 4, noisy_shader);
  c.deterministic = true;
  c.owned_first = 1;
  c.owned_count = 2;
  Engine e(kEmptyScene, c, camera_at(0));
  EXPECT_EQ(e.publish_camera_as(camera_at(1), 5), 5u);  // the master skipped epochs 2..4
  EXPECT_EQ(e.publish_camera_as(camera_at(2), 5), 0u);  // repeated: ignored
  EXPECT_EQ(e.publish_camera_as(camera_at(2), 3), 0u);  // older: ignored
  EXPECT_EQ(e.camera_epoch(), 5u);
  for (int k = 0; k < 20; ++k) e.advance(1.0 / 30.0);
  const EngineStats s = e.stats();
  EXPECT_EQ(s.threads[0].samples, 0u);
  EXPECT_GT(s.threads[1].samples, 0u);
  EXPECT_GT(s.threads[2].samples, 0u);
  EXPECT_EQ(s.threads[3].samples, 0u);
  // Bad shares are refused by validate().
  EngineConfig bad = c;
  bad.owned_first = 3;  // 3 + 2 > 4 threads
  EXPECT_NE(validate(bad), "");
  EngineConfig conventional = c;  // a conventional share renders the pieces of a PieceFeed
  conventional.mode = RenderMode::conventional;
  EXPECT_EQ(validate(conventional), "");
  bad = c;
  bad.threads = 0;
  EXPECT_NE(validate(bad), "");
}

}  // namespace
}  // namespace frameless
