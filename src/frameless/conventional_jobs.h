// Job list of the conventional (synchronous) mode: linearly decreasing job sizes in multiples of
// a 32x4 tile (Parker et al. 1999, section 2.1); built on the control thread, then read-only.
#pragma once
#include <cstdint>
#include <vector>

namespace frameless {

inline constexpr int kTileWidth = 32;
inline constexpr int kTileHeight = 4;

struct TileJob {
  uint32_t first_tile = 0;  // index into row-major tiles
  uint32_t tiles = 0;       // number of consecutive tiles (>= 1)
};

// Jobs covering every tile once, in order, sizes non-increasing from about tiles / (8 threads)
// down to one tile (the first job holds about 1/8 of a thread's share).
std::vector<TileJob> make_tile_jobs(int width, int height, int threads);

// The pixels of the jobs in job order (each pixel once): the order a frame is rendered in.
std::vector<uint32_t> tile_job_pixels(int width, int height, const std::vector<TileJob>& jobs);

}  // namespace frameless
