// OpenRT's task distribution (cluster/tile_scheduler.h): on demand, affinity frame after frame,
// stealing when a client runs dry, pixel states handed over when a job changes client, and the
// next frame's jobs going out while the current one finishes, never ahead of their predecessor.
#include <gtest/gtest.h>

#include <map>
#include <set>

#include "cluster/tile_scheduler.h"

namespace frameless::cluster {
namespace {

using Assigned = std::vector<TileScheduler::Assignment>;

Assigned dispatch(TileScheduler& s) {
  Assigned out;
  s.dispatch(out);
  return out;
}

TEST(TileScheduler, HandsOutOnDemandOnlyWhatIsAskedFor) {
  TileScheduler s(10, 2);
  s.begin_frame(1);
  EXPECT_TRUE(dispatch(s).empty());  // nobody asked yet
  s.want(0, 3);
  s.want(1, 2);
  const Assigned a = dispatch(s);
  ASSERT_EQ(a.size(), 5u);
  std::map<int, int> per;
  std::set<uint32_t> jobs;
  for (const auto& x : a) {
    ++per[x.client];
    jobs.insert(x.job);
    EXPECT_FALSE(x.handoff);
  }
  EXPECT_EQ(per[0], 3);
  EXPECT_EQ(per[1], 2);
  EXPECT_EQ(jobs.size(), 5u);  // each job once
  EXPECT_TRUE(dispatch(s).empty());
  EXPECT_FALSE(s.may_begin_next());  // 5 of 10 out
}

// Runs frames with clients asking `depth` at a time, returning each job as soon as it is
// handed out; `slow` returns its jobs only every other round. Returns per frame the client of
// each job.
std::vector<std::vector<int>> run(TileScheduler& s, int frames, int clients, uint32_t depth, int slow = -1) {
  std::vector<std::vector<int>> who;
  s.begin_frame(1);
  who.assign(1, std::vector<int>(s.jobs(), -1));
  for (int c = 0; c < clients; ++c) s.want(c, depth);
  std::vector<TileScheduler::Assignment> held;
  for (int round = 0; round < 10000 && who.size() <= size_t(frames); ++round) {
    Assigned a = dispatch(s);
    for (const auto& x : a) {
      while (who.size() < x.serial) who.emplace_back(s.jobs(), -1);
      who[x.serial - 1][x.job] = x.client;
    }
    held.insert(held.end(), a.begin(), a.end());
    std::vector<TileScheduler::Assignment> keep;
    for (const auto& x : held) {
      if (x.client == slow && round % 2) {
        keep.push_back(x);
        continue;
      }
      s.complete(x.client, x.serial, x.job);
      s.want(x.client, 1);
    }
    held = keep;
    while (s.may_begin_next() && s.newest() < uint64_t(frames)) s.begin_frame(s.newest() + 1);
  }
  who.resize(size_t(frames));
  return who;
}

TEST(TileScheduler, SameJobsGoToTheSameClientFrameAfterFrame) {
  TileScheduler s(40, 4);
  const auto who = run(s, 6, 4, 3);
  for (size_t f = 1; f < who.size(); ++f)
    for (uint32_t j = 0; j < 40; ++j) {
      EXPECT_GE(who[f][j], 0) << "frame " << f + 1 << " job " << j << " never handed out";
      EXPECT_EQ(who[f][j], who[f - 1][j]) << "frame " << f + 1 << " job " << j;
    }
  EXPECT_EQ(s.steals(), 0u);
  EXPECT_EQ(s.handoffs(), 0u);
}

TEST(TileScheduler, AClientThatRunsDryStealsAndStatesAreHandedOver) {
  TileScheduler s(40, 3);
  run(s, 8, 3, 2, /*slow=*/1);
  EXPECT_GT(s.steals(), 0u);
  EXPECT_GT(s.handoffs(), 0u);  // a stolen job comes with its pixel states
  EXPECT_EQ(s.handed_out(), 8u * 40u);
}

TEST(TileScheduler, NextFrameGoesOutWhileTheCurrentFinishesButNeverAheadOfItsJob) {
  TileScheduler s(4, 1);
  s.begin_frame(1);
  s.want(0, 8);
  Assigned a = dispatch(s);
  ASSERT_EQ(a.size(), 4u);
  EXPECT_TRUE(s.may_begin_next());  // all of frame 1 out: frame 2 may begin (asynchronous)
  s.begin_frame(2);
  EXPECT_TRUE(dispatch(s).empty());  // no job of frame 2 before the same job of frame 1 is back
  EXPECT_FALSE(s.complete(0, 1, 2));
  a = dispatch(s);
  ASSERT_EQ(a.size(), 1u);
  EXPECT_EQ(a[0].serial, 2u);
  EXPECT_EQ(a[0].job, 2u);
  EXPECT_FALSE(s.may_begin_next());  // frame 1 incomplete: never three frames in flight
  EXPECT_THROW(s.begin_frame(3), std::logic_error);
  EXPECT_FALSE(s.complete(0, 1, 0));
  EXPECT_FALSE(s.complete(0, 1, 1));
  EXPECT_TRUE(s.complete(0, 1, 3));  // frame 1 complete
}

TEST(TileScheduler, ResultsForJobsNotHandedOutAreRefused) {
  TileScheduler s(4, 2);
  s.begin_frame(1);
  s.want(0, 1);
  const Assigned a = dispatch(s);
  ASSERT_EQ(a.size(), 1u);
  EXPECT_THROW(s.complete(1, 1, a[0].job), std::invalid_argument);      // another client
  EXPECT_THROW(s.complete(0, 2, a[0].job), std::invalid_argument);      // another frame
  EXPECT_THROW(s.complete(0, 1, a[0].job + 1), std::invalid_argument);  // not handed out
  EXPECT_THROW(s.complete(0, 1, 99), std::invalid_argument);            // no such job
  s.complete(0, 1, a[0].job);
  EXPECT_THROW(s.complete(0, 1, a[0].job), std::invalid_argument);      // twice
}

}  // namespace
}  // namespace frameless::cluster
