// Conventional-mode jobs: decreasing sizes, whole tiles, every tile and pixel exactly once.
#include "frameless/conventional_jobs.h"

#include <gtest/gtest.h>

namespace frameless {
namespace {

TEST(ConventionalJobs, DecreasingAndCovering) {
  for (auto [w, h] : {std::pair{1, 1}, {33, 5}, {640, 480}, {1280, 720}, {333, 777}})
    for (int threads : {1, 2, 4, 16}) {
      const auto jobs = make_tile_jobs(w, h, threads);
      const uint32_t tiles = uint32_t((w + 31) / 32) * uint32_t((h + 3) / 4);
      uint32_t next = 0;
      for (size_t j = 0; j < jobs.size(); ++j) {
        EXPECT_EQ(jobs[j].first_tile, next);
        EXPECT_GE(jobs[j].tiles, 1u);
        if (j) {
          EXPECT_LE(jobs[j].tiles, jobs[j - 1].tiles) << w << "x" << h << " job " << j;
        }
        next += jobs[j].tiles;
      }
      EXPECT_EQ(next, tiles);
      EXPECT_EQ(jobs.back().tiles, 1u);
      const auto pixels = tile_job_pixels(w, h, jobs);
      std::vector<int> seen(size_t(w) * size_t(h), 0);
      for (uint32_t p : pixels) ++seen[p];
      EXPECT_EQ(std::count(seen.begin(), seen.end(), 1), long(seen.size()));
    }
}

TEST(ConventionalJobs, FirstJobsAreLargeForBigImages) {
  const auto jobs = make_tile_jobs(1280, 720, 2);
  EXPECT_GT(jobs.front().tiles, 100u);  // 7200 tiles / (8 * 2 threads)
  EXPECT_GT(jobs.size(), 10u);
}

}  // namespace
}  // namespace frameless
