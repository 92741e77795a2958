// Linearly decreasing job sizes: big jobs first amortise the atomic counter, small ones last
// balance the load before the barrier.
#include "frameless/conventional_jobs.h"

#include <algorithm>
#include <cmath>

namespace frameless {

std::vector<TileJob> make_tile_jobs(int width, int height, int threads) {
  const uint32_t tx = uint32_t((width + kTileWidth - 1) / kTileWidth);
  const uint32_t ty = uint32_t((height + kTileHeight - 1) / kTileHeight);
  const uint32_t total = tx * ty;
  std::vector<TileJob> jobs;
  const double first = std::max(1.0, std::floor(double(total) / (8.0 * std::max(1, threads))));
  // A ramp from `first` down to 1 holds about (first + 1) / 2 tiles per job.
  const double count = std::max(1.0, std::ceil(2.0 * total / (first + 1.0)));
  const double step = count > 1 ? (first - 1.0) / (count - 1.0) : 0.0;
  // Built from the small end (1, 1 + step, ...) so the frame always ends with one-tile jobs;
  // a short leftover is merged into the largest job so sizes stay non-increasing.
  std::vector<uint32_t> sizes;
  uint32_t sum = 0;
  for (uint32_t i = 0; sum < total; ++i) {
    const uint32_t n = std::min(total - sum, uint32_t(std::max(1.0, std::round(1.0 + step * i))));
    if (!sizes.empty() && n < sizes.back())
      sizes.back() += n;
    else
      sizes.push_back(n);
    sum += n;
  }
  uint32_t next = 0;
  for (auto it = sizes.rbegin(); it != sizes.rend(); ++it) {
    jobs.push_back({next, *it});
    next += *it;
  }
  return jobs;
}

std::vector<uint32_t> tile_job_pixels(int width, int height, const std::vector<TileJob>& jobs) {
  const uint32_t tx = uint32_t((width + kTileWidth - 1) / kTileWidth);
  std::vector<uint32_t> out;
  out.reserve(size_t(width) * size_t(height));
  for (const TileJob& j : jobs)
    for (uint32_t t = j.first_tile; t < j.first_tile + j.tiles; ++t) {
      const int x0 = int(t % tx) * kTileWidth, y0 = int(t / tx) * kTileHeight;
      for (int y = y0; y < std::min(height, y0 + kTileHeight); ++y)
        for (int x = x0; x < std::min(width, x0 + kTileWidth); ++x)
          out.push_back(uint32_t(y) * uint32_t(width) + uint32_t(x));
    }
  return out;
}

}  // namespace frameless
