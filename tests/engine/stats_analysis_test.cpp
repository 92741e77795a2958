// Balance and temporal regularity of the update distribution (issue 5); deterministic runs.
#include "frameless/stats_analysis.h"

#include <string>

#include <gtest/gtest.h>

#include "core/scene/scene.h"
#include "core/scene/scene_finalize.h"
#include "frameless/stats_run.h"

namespace frameless {
namespace {

const Scene& empty_scene() {
  static const Scene scene = [] {
    Scene s;
    finalize_scene(s);
    return s;
  }();
  return scene;
}

TEST(StatsBalance, PerThreadPixelCountsWithinOneChunk) {
  for (PixelOrder order : {PixelOrder::hilbert_shuffled, PixelOrder::hilbert, PixelOrder::scanline,
                           PixelOrder::random})
    for (int threads : {1, 2, 3, 7})
      for (int chunk : {1, 16, 64}) {
        SCOPED_TRACE(std::string(to_string(order)) + " threads " + std::to_string(threads) +
                     " chunk " + std::to_string(chunk));
        StatsRunConfig c;
        c.width = 97;
        c.height = 61;
        c.chunk_size = chunk;
        c.threads = threads;
        c.order = order;
        c.sweeps = 1.0;
        c.change_at = -1;
        c.shader = flat_shader();
        const UpdateTrace t = run_for_stats(empty_scene(), empty_scene().camera, c);
        const BalanceStats b = analyze_balance(t);
        ASSERT_EQ(b.pixels.size(), size_t(threads));
        uint64_t total = 0, updates = 0;
        for (uint64_t p : b.pixels) total += p;
        for (uint64_t u : b.updates) updates += u;
        EXPECT_EQ(total, 97u * 61u);
        EXPECT_LE(b.pixel_spread, uint64_t(chunk));
        EXPECT_TRUE(b.within_one_chunk);
        // Deterministic budgets follow pixel counts: every thread sweeps its share at the same pace.
        const double rate = double(updates) / double(total);
        EXPECT_GE(rate, 1.0);
        for (int i = 0; i < threads; ++i)
          EXPECT_NEAR(double(b.updates[size_t(i)]), rate * double(b.pixels[size_t(i)]), 1.5);
      }
}

TEST(StatsBalance, BitesOnAnUnevenPartition) {
  UpdateTrace t;
  t.chunk_size = 16;
  t.thread_pixels = {100, 117};
  EXPECT_FALSE(analyze_balance(t).within_one_chunk);
  t.thread_pixels = {100, 116};
  EXPECT_TRUE(analyze_balance(t).within_one_chunk);
}

TEST(StatsTemporal, EveryPixelIsRevisitedOncePerSweep) {
  StatsRunConfig c;
  c.width = 64;
  c.height = 40;
  c.chunk_size = 16;
  c.threads = 3;
  c.sweeps = 3.0;
  c.change_at = -1;
  c.shader = flat_shader();
  const UpdateTrace t = run_for_stats(empty_scene(), empty_scene().camera, c);
  const TemporalStats s = analyze_temporal(t);
  EXPECT_GT(s.intervals, 64u * 40u);
  EXPECT_NEAR(s.mean_sweeps, 1.0, 0.01);
  EXPECT_LT(s.cv, 0.01);
  EXPECT_LE(s.max_sweeps, 1.01);
}

TEST(StatsTemporal, IrregularGapsShowInTheCoefficientOfVariation) {
  UpdateTrace t;
  t.width = 2;
  t.height = 1;
  t.sweep_seconds = 1.0;
  t.logs = {{{0, 1, 0, 0.0f}, {0, 1, 0, 1.0f}, {0, 1, 0, 4.0f}, {1, 1, 0, 0.5f}, {1, 1, 0, 1.5f}}};
  const TemporalStats s = analyze_temporal(t);
  EXPECT_EQ(s.intervals, 3u);
  EXPECT_NEAR(s.mean_seconds, 5.0 / 3.0, 1e-6);
  EXPECT_NEAR(s.max_sweeps, 3.0, 1e-6);
  EXPECT_GT(s.cv, 0.5);
}

}  // namespace
}  // namespace frameless
