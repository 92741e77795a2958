// Staleness after a camera change (issue 5): every pixel shows the new camera within the bound the
// update percentage implies. Deterministic runs, fixed seeds.
#include <string>

#include <gtest/gtest.h>

#include "core/scene/scene.h"
#include "core/scene/scene_finalize.h"
#include "frameless/stats_analysis.h"
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

UpdateTrace run(int threads, double percent, PixelOrder order) {
  StatsRunConfig c;
  c.width = 97;
  c.height = 61;
  c.chunk_size = 16;
  c.threads = threads;
  c.order = order;
  c.update_percent = percent;
  c.sweeps = 2.0;
  c.change_at = 0.7;  // mid-sweep, so threads are at arbitrary points of their lists
  c.shader = flat_shader();
  return run_for_stats(empty_scene(), empty_scene().camera, c);
}

// A thread re-reads the camera within ceil(p% of its n_t pixels) visits, then needs n_t visits to
// reach all its pixels: (1 + p/100) sweeps, plus one visit of budget rounding each side.
double slack(const UpdateTrace& t) {
  uint64_t fewest = t.thread_pixels[0];
  for (uint64_t n : t.thread_pixels) fewest = std::min(fewest, n);
  return 3.0 / double(fewest);
}

TEST(StatsStaleness, EveryPixelShowsTheNewCameraWithinTheBound) {
  for (int threads : {1, 2, 3, 7})
    for (double percent : {1.0, 5.0, 25.0, 100.0})
      for (PixelOrder order : {PixelOrder::hilbert_shuffled, PixelOrder::scanline}) {
        SCOPED_TRACE(std::string(to_string(order)) + " threads " + std::to_string(threads) +
                     " percent " + std::to_string(percent));
        const UpdateTrace t = run(threads, percent, order);
        const StalenessStats s = analyze_staleness(t, analyze_temporal(t));
        ASSERT_TRUE(s.measured);
        EXPECT_EQ(s.never, 0u);
        EXPECT_LE(s.t100_sweeps, s.bound_sweeps + slack(t));
        EXPECT_LE(s.t50_sweeps, s.t95_sweeps);
        EXPECT_LE(s.t95_sweeps, s.t100_sweeps);
        // The curve rises from (almost) nothing to everything.
        EXPECT_LT(s.curve_fraction.front(), 0.05);
        EXPECT_EQ(s.curve_fraction.back(), 1.0);
        // Steady state: no pixel waits more than one sweep (plus rounding) between updates.
        EXPECT_LE(s.max_age_sweeps, 1.0 + slack(t));
      }
}

// The bound bites: a slow camera re-read (25%) measured against the 1% bound fails, and a pixel
// that never sees the new camera makes the time to 100% infinite.
TEST(StatsStaleness, BoundBitesOnSlowPickupAndOnAMissedPixel) {
  const UpdateTrace t = run(3, 25.0, PixelOrder::hilbert_shuffled);
  const StalenessStats slow = analyze_staleness(t, analyze_temporal(t));
  EXPECT_GT(slow.t100_sweeps, 1.01 + slack(t));

  UpdateTrace missed = run(2, 1.0, PixelOrder::hilbert_shuffled);
  const uint32_t victim = missed.logs[0].front().pixel;
  for (UpdateRecord& r : missed.logs[0])
    if (r.pixel == victim) r.epoch = 0;  // as if this pixel kept the old camera
  const StalenessStats s = analyze_staleness(missed, analyze_temporal(missed));
  EXPECT_EQ(s.never, 1u);
  EXPECT_FALSE(s.t100_sweeps <= s.bound_sweeps + slack(missed));
}

}  // namespace
}  // namespace frameless
