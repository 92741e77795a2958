// Closed-loop sampling: runs the display asks for are rendered soon, out of walk order, and
// the display learns of them through collect(); every pixel is still updated within twice its
// thread's list length of updates (no starvation), and deterministic runs stay bit-identical.
#include <gtest/gtest.h>

#include <algorithm>
#include <map>
#include <set>

#include "../engine/collecting_sink.h"
#include "../engine/test_shaders.h"
#include "frameless/engine.h"
#include "frameless/stats_closed_loop.h"

namespace frameless {
namespace {

using namespace frameless::testing;

constexpr int kW = 64, kH = 48, kThreads = 2;

EngineConfig config(bool closed_loop) {
  EngineConfig c = test_config(kW, kH, kThreads, noisy_shader);
  c.deterministic = true;
  c.seed = 3;
  c.samples_per_tick = 2 * 400;  // 400 pixel updates per tick over both threads
  c.update_percent = 2;
  c.closed_loop = closed_loop;
  c.update_log_capacity = 200000;
  return c;
}

// A display stand-in: collects like CollectingSink and asks for the runs holding `ask` pixels
// (all of them at every collection while asking, as a display seeing them change would).
class AskingSink final : public UpdateSink {
 public:
  std::vector<uint32_t> ask;  // pixels
  bool asking = true;
  std::set<uint32_t> seen;    // pixels whose new samples this collection offered
  bool wanted_available = false;
  std::vector<uint32_t> slot_pixel;  // the layout of the last collection
  void begin(const CollectResult& r) override {
    inner_.begin(r);
    if (r.slot_pixel) slot_pixel = *r.slot_pixel;
    seen.clear();
    wanted_available = r.wanted != nullptr;
    if (!r.wanted || !asking) return;
    std::vector<uint32_t> slot_of(r.slot_pixel->size());
    for (size_t s = 0; s < slot_of.size(); ++s) slot_of[(*r.slot_pixel)[s]] = uint32_t(s);
    for (uint32_t p : ask) r.wanted->want(slot_of[p]);
    r.wanted->publish();
  }
  void slots(size_t first, const PixelState* states, size_t count) override {
    inner_.slots(first, states, count);
    for (const CollectedPixel& c : inner_.updates) seen.insert(c.pixel);
  }
  void frame(const std::vector<PixelSnapshot>& p) override { inner_.frame(p); }

 private:
  CollectingSink inner_;
};

// Per thread, the update index of each visit of each pixel.
std::map<uint32_t, std::vector<size_t>> visits(const Engine& e, int thread) {
  std::map<uint32_t, std::vector<size_t>> v;
  const UpdateLog& log = e.update_log(thread);
  for (size_t k = 0; k < log.records.size(); ++k) v[log.records[k].pixel].push_back(k);
  return v;
}

TEST(ClosedLoop, AskedRunsAreRenderedSoonAndTheDisplayIsTold) {
  Engine e(kEmptyScene, config(true), camera_at(0));
  e.start();
  UpdateCursor cursor;
  AskingSink sink;
  e.collect(cursor, sink);
  ASSERT_TRUE(sink.wanted_available);
  e.advance(0.1);  // the walk is under way
  e.collect(cursor, sink);
  // Ask for a pixel the walk just left behind (it will not come round again for a whole list).
  const UpdateLog& log0 = e.update_log(0);
  const uint32_t asked = log0.records.back().pixel;
  sink.ask = {asked};
  e.collect(cursor, sink);
  const size_t before = log0.records.size();
  e.advance(0.1);
  sink.asking = false;
  e.collect(cursor, sink);
  // Rendered again within this tick (one pick-up interval plus a batch), and offered to the display.
  size_t again = 0;
  for (size_t k = before; k < log0.records.size(); ++k) again += log0.records[k].pixel == asked;
  EXPECT_GE(again, 1u);
  EXPECT_TRUE(sink.seen.count(asked));
  // Without closed loop the pixel waits for the walk to come round.
  Engine plain(kEmptyScene, config(false), camera_at(0));
  plain.start();
  UpdateCursor c2;
  AskingSink s2;
  plain.collect(c2, s2);
  EXPECT_FALSE(s2.wanted_available);
  plain.advance(0.1);
  const uint32_t left = plain.update_log(0).records.back().pixel;
  const size_t b2 = plain.update_log(0).records.size();
  plain.advance(0.1);
  size_t again2 = 0;
  for (size_t k = b2; k < plain.update_log(0).records.size(); ++k) again2 += plain.update_log(0).records[k].pixel == left;
  EXPECT_EQ(again2, 0u);
}

// Thread lists need not start on a run boundary. A run that spans two threads' lists is served
// by both, each rendering its own part of it and nothing beyond.
TEST(ClosedLoop, ARunAcrossTwoThreadsIsServedByBothAndNoFurther) {
  EngineConfig c = config(true);
  c.chunk_size = 13;  // lists of whole 13-pixel chunks: the second one starts inside a run
  Engine e(kEmptyScene, c, camera_at(0));
  e.start();
  UpdateCursor cursor;
  AskingSink sink;
  sink.asking = false;
  e.collect(cursor, sink);
  for (int k = 0; k < 3; ++k) {  // both walks are mid-list, far from the run asked for below
    e.advance(0.1);
    e.collect(cursor, sink);
  }
  std::vector<uint32_t> slot_of(size_t(c.width) * size_t(c.height));
  for (size_t s = 0; s < sink.slot_pixel.size(); ++s) slot_of[sink.slot_pixel[s]] = uint32_t(s);
  const uint32_t first1 = slot_of[e.update_log(1).records.front().pixel];  // thread 1 walks from its first slot
  const uint32_t head = first1 % kRunLength;
  ASSERT_NE(head, 0u) << "the test needs a thread list starting inside a run";
  sink.ask = {sink.slot_pixel[first1]};
  sink.asking = true;
  e.collect(cursor, sink);
  sink.asking = false;
  const size_t before0 = e.update_log(0).records.size(), before1 = e.update_log(1).records.size();
  e.advance(0.1);
  e.collect(cursor, sink);
  // The consecutive slots a thread rendered from `start` on, after `before`.
  const auto served = [&](int t, size_t before, uint32_t start) {
    const UpdateLog& log = e.update_log(t);
    for (size_t k = before; k < log.records.size(); ++k) {
      if (slot_of[log.records[k].pixel] != start) continue;
      uint32_t n = 0;
      while (k + n < log.records.size() && slot_of[log.records[k + n].pixel] == start + n) ++n;
      return n;
    }
    return 0u;
  };
  EXPECT_EQ(served(0, before0, first1 - head), head);               // thread 0: the run's head
  EXPECT_EQ(served(1, before1, first1), kRunLength - head);         // thread 1: the rest, no further
}

TEST(ClosedLoop, EveryPixelWithinTwiceItsListEvenWhenHalfTheImageIsAskedForForever) {
  Engine e(kEmptyScene, config(true), camera_at(0));
  e.start();
  UpdateCursor cursor;
  AskingSink sink;
  for (uint32_t p = 0; p < uint32_t(kW * kH / 2); ++p) sink.ask.push_back(p);  // the top half
  const int ticks = 60;
  for (int k = 0; k < ticks; ++k) {
    e.collect(cursor, sink);
    e.advance(0.05);
  }
  for (int t = 0; t < kThreads; ++t) {
    const size_t list = e.partition().pixels[size_t(t)].size();
    const auto v = visits(e, t);
    ASSERT_EQ(v.size(), list);  // every pixel of the thread was updated
    size_t worst = 0, asked_visits = 0, other_visits = 0;
    for (const auto& [pixel, at] : v) {
      worst = std::max(worst, at.front());  // the first visit counts from the start
      for (size_t i = 1; i < at.size(); ++i) worst = std::max(worst, at[i] - at[i - 1]);
      (pixel < uint32_t(kW * kH / 2) ? asked_visits : other_visits) += at.size();
    }
    // The bound the walk guarantees: at least every other update belongs to the walk.
    EXPECT_LE(worst, 2 * list + 2 * kRunLength) << "thread " << t;
    EXPECT_GT(asked_visits, other_visits) << "thread " << t;  // the asks do get more
  }
}

TEST(ClosedLoop, DeterministicRunsStayBitIdentical) {
  auto run = [] {
    Engine e(kEmptyScene, config(true), camera_at(0));
    e.start();
    UpdateCursor cursor;
    AskingSink sink;
    for (uint32_t p = 0; p < uint32_t(kW * kH); p += 7) sink.ask.push_back(p);
    std::vector<PixelSnapshot> out;
    for (int k = 0; k < 12; ++k) {
      e.collect(cursor, sink);
      e.advance(0.05);
      if (k == 6) e.publish_camera(camera_at(0.2f));
    }
    for (int y = 0; y < kH; ++y)
      for (int x = 0; x < kW; ++x) {
        PixelSnapshot s;
        e.read_pixel(x, y, s);
        out.push_back(s);
      }
    return out;
  };
  const auto a = run(), b = run();
  ASSERT_EQ(a.size(), b.size());
  size_t differ = 0;
  for (size_t i = 0; i < a.size(); ++i)
    differ += a[i].seq != b[i].seq || a[i].mean != b[i].mean || a[i].count != b[i].count;
  EXPECT_EQ(differ, 0u);
}

// What `frameless stats` reports for the closed-loop order.
TEST(ClosedLoop, StatsReportTheBoundAndTheShareOfTheAsks) {
  StatsRunConfig c;
  c.width = 96;
  c.height = 64;
  c.threads = 3;
  const ClosedLoopStats s = closed_loop_stats(kEmptyScene, camera_at(0), c);
  ASSERT_EQ(s.threads.size(), 3u);
  EXPECT_TRUE(s.bound_holds);
  for (const ClosedLoopStats::Thread& t : s.threads) {
    EXPECT_EQ(t.never_updated, 0u);
    EXPECT_LE(t.worst_gap, t.bound);
    EXPECT_GT(t.worst_gap, t.pixels);  // the asks do delay the walk
    EXPECT_GT(t.asked_share, 0.6);     // half the image gets most of the updates
    EXPECT_LT(t.asked_share, 0.8);     // but never more than the interleaving allows
  }
}

}  // namespace
}  // namespace frameless
