// Structure and uniformity of the pixel-update distribution per order (issue 5). Deterministic
// runs with fixed seeds; every test uses significance level alpha = 0.001.
#include "frameless/stats_spectrum.h"

#include <cstdlib>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "core/base/rng.h"
#include "core/scene/scene.h"
#include "core/scene/scene_finalize.h"
#include "frameless/stats_analysis.h"
#include "frameless/stats_run.h"

namespace frameless {
namespace {

constexpr double kAlpha = 0.001;

bool long_tests() {
  const char* v = std::getenv("FRAMELESS_LONG_TESTS");
  return v && std::string(v) == "1";
}

const Scene& empty_scene() {
  static const Scene scene = [] {
    Scene s;
    finalize_scene(s);
    return s;
  }();
  return scene;
}

OrderStats run_order(int w, int h, int chunk, int threads, PixelOrder order) {
  StatsRunConfig c;
  c.width = w;
  c.height = h;
  c.chunk_size = chunk;
  c.threads = threads;
  c.order = order;
  c.seed = 1;
  c.update_percent = 5.0;
  c.sweeps = 2.0;
  c.change_at = -1;  // staleness has its own test
  c.shader = flat_shader();
  return analyze_trace(run_for_stats(empty_scene(), empty_scene().camera, c));
}

struct Case {
  int w, h, chunk;
};
// 333 x 777 runs only with FRAMELESS_LONG_TESTS=1; by default it is scaled down by 3 per side.
std::vector<Case> sizes() {
  std::vector<Case> s = {{96, 64, 16}, {111, 259, 32}};
  if (long_tests()) s.push_back({333, 777, 64});
  return s;
}

TEST(StatsStructure, ShuffledHilbertIsUniformAndUnstructured) {
  for (const Case& c : sizes())
    for (int threads : {1, 2, 3, 7}) {
      SCOPED_TRACE(std::to_string(c.w) + "x" + std::to_string(c.h) + " threads " + std::to_string(threads));
      const OrderStats s = run_order(c.w, c.h, c.chunk, threads, PixelOrder::hilbert_shuffled);
      EXPECT_GT(s.uniformity.chi2.p_value, kAlpha);
      EXPECT_EQ(s.structure.masks, 8);
      EXPECT_GT(s.structure.lowfreq_terms, 100u);
      EXPECT_GT(s.structure.lowfreq_p_value, kAlpha) << "ratio " << s.structure.lowfreq_ratio;
    }
}

TEST(StatsStructure, RandomOrderIsUnstructured) {
  const OrderStats s = run_order(111, 259, 32, 3, PixelOrder::random);
  EXPECT_GT(s.uniformity.chi2.p_value, kAlpha);
  EXPECT_GT(s.structure.lowfreq_p_value, kAlpha);
  EXPECT_LT(s.structure.morans_i_z, 3.29);  // pixel-level white noise: no clumping either
}

// Power: the same test rejects the orders that sweep across the screen.
TEST(StatsStructure, ScanlineAndUnshuffledHilbertFail) {
  for (const Case& c : sizes())
    for (int threads : {1, 7})
      for (PixelOrder order : {PixelOrder::scanline, PixelOrder::hilbert}) {
        SCOPED_TRACE(std::string(to_string(order)) + " " + std::to_string(c.w) + "x" +
                     std::to_string(c.h) + " threads " + std::to_string(threads));
        const OrderStats s = run_order(c.w, c.h, c.chunk, threads, order);
        EXPECT_LT(s.structure.lowfreq_p_value, kAlpha) << "ratio " << s.structure.lowfreq_ratio;
        EXPECT_GT(s.structure.lowfreq_ratio, 1.1);  // and clearly above the null mean of 1
      }
}

// The null is calibrated: masks made of uniformly random chunks (seeded) are rejected about
// alpha of the time. 40 replicates at alpha = 0.05: P(8 or more rejections) < 0.001.
TEST(StatsStructure, RandomChunkMasksAreCalibrated) {
  const int w = 64, h = 48;
  const ChunkLayout layout = make_chunk_layout(w, h, 16, PixelOrder::hilbert_shuffled, 1);
  const ChunkNull null = make_chunk_null(layout);
  Rng rng(2024);
  int rejected = 0;
  for (int rep = 0; rep < 40; ++rep) {
    std::vector<std::vector<uint8_t>> masks;
    for (int m = 0; m < 4; ++m) {
      std::vector<uint8_t> mask(size_t(w * h), 0);
      for (const auto& chunk : layout.chunks)
        if (rng.next_float() < 0.125f)
          for (uint32_t p : chunk) mask[p] = 1;
      masks.push_back(mask);
    }
    if (analyze_structure(masks, null).lowfreq_p_value < 0.05) ++rejected;
  }
  EXPECT_LT(rejected, 8);
}

// The structure test bites on a plain pattern: a horizontal band per interval.
TEST(StatsStructure, BandMaskFails) {
  const int w = 64, h = 48;
  const ChunkNull null = make_chunk_null(make_chunk_layout(w, h, 16, PixelOrder::hilbert_shuffled, 1));
  std::vector<std::vector<uint8_t>> masks;
  for (int m = 0; m < 8; ++m) {
    std::vector<uint8_t> mask(size_t(w * h), 0);
    for (int y = m * 6; y < m * 6 + 6; ++y)
      for (int x = 0; x < w; ++x) mask[size_t(y * w + x)] = 1;
    masks.push_back(mask);
  }
  const StructureStats s = analyze_structure(masks, null);
  EXPECT_LT(s.lowfreq_p_value, kAlpha);
  EXPECT_GT(s.morans_i_coarse, 0.5);
}

// The uniformity test bites: a trace in which a region is updated twice as often fails.
TEST(StatsStructure, UniformityFailsOnDoubledRegion) {
  // (Pearson's test has little power at a handful of updates per pixel; 40 sweeps give plenty.)
  std::vector<uint32_t> counts(96 * 64, 40);
  EXPECT_GT(analyze_uniformity(counts).chi2.p_value, kAlpha);
  for (size_t i = 0; i < counts.size() / 8; ++i) counts[i] = 80;
  const UniformityStats u = analyze_uniformity(counts);
  EXPECT_LT(u.chi2.p_value, kAlpha);
  EXPECT_EQ(u.min, 40u);
  EXPECT_EQ(u.max, 80u);
  EXPECT_GT(u.cv, 0.25);
}

}  // namespace
}  // namespace frameless
