// Statistics of a recorded run of pixel updates (issue 5): uniformity, structure, temporal
// regularity, staleness after a camera change, balance; pure functions on the control thread.
#pragma once
#include <cstdint>
#include <limits>
#include <string>
#include <vector>

#include "frameless/partition.h"
#include "frameless/stats_math.h"
#include "frameless/stats_spectrum.h"
#include "frameless/update_log.h"

namespace frameless {

// What a stats run recorded (filled by run_for_stats in stats_run.h, or by hand in tests).
struct UpdateTrace {
  int width = 0;
  int height = 0;
  int chunk_size = 64;
  PixelOrder order = PixelOrder::hilbert_shuffled;
  uint64_t seed = 1;                      // partition seed
  double update_percent = 1.0;            // camera re-read period, % of a thread's pixels
  std::vector<std::vector<UpdateRecord>> logs;  // per render thread, in update order
  uint64_t overflow = 0;                  // updates that did not fit the logs
  std::vector<uint64_t> thread_pixels;    // pixels owned per thread (the partition)
  std::vector<double> thread_samples_per_s;  // engine counters, per thread
  std::vector<double> thread_busy_s;         // render-thread CPU seconds, per thread
  double sweep_seconds = 0;               // engine seconds for one update of every pixel
  double run_seconds = 0;                 // engine seconds the run lasted
  double samples_per_s = 0;               // whole engine, this run
  uint32_t mask_ticks_begin = 0;          // display ticks [begin, end) analysed as masks
  uint32_t mask_ticks_end = 0;
  double change_time = -1;                // engine seconds of the camera change (< 0: none)
  uint32_t change_epoch = 0;              // its epoch
};

// The units `order` deals out, rebuilt from the partition rules (same seed => same chunks).
ChunkLayout make_chunk_layout(int width, int height, int chunk_size, PixelOrder order, uint64_t seed);

struct UniformityStats {
  uint32_t min = 0, max = 0;  // per-pixel update counts over the run
  double mean = 0;
  double cv = 0;              // standard deviation / mean
  ChiSquareTest chi2;         // against equal rates
};
UniformityStats analyze_uniformity(const std::vector<uint32_t>& counts);

struct TemporalStats {
  uint64_t intervals = 0;        // consecutive-update gaps measured (all pixels)
  double mean_seconds = 0;
  double cv = 0;                 // standard deviation / mean over all gaps
  double max_seconds = 0;
  double mean_sweeps = 0;        // same in sweeps
  double max_sweeps = 0;
};

struct StalenessStats {
  bool measured = false;         // a camera change happened inside the run
  uint64_t never = 0;            // pixels that never showed the new camera before the run ended
  double t50_sweeps = 0;         // time after the change until 50% / 95% / 100% show it
  double t95_sweeps = 0;
  double t100_sweeps = std::numeric_limits<double>::infinity();
  double max_age_sweeps = 0;     // longest any pixel went without an update (steady state)
  double bound_sweeps = 0;       // 1 + update_percent / 100: what the camera re-read period implies
  std::vector<double> curve_sweeps;    // time since the change
  std::vector<double> curve_fraction;  // fraction of pixels showing the new camera by then
};

struct BalanceStats {
  std::vector<uint64_t> pixels;       // per thread
  std::vector<uint64_t> updates;      // per thread (logged + overflow share unknown: logged only)
  std::vector<double> samples_per_s;  // per thread
  std::vector<double> busy_s;         // per thread: CPU seconds the render thread ran
  uint64_t pixel_spread = 0;          // max - min pixels
  bool within_one_chunk = true;       // pixel_spread <= chunk_size
};

struct OrderStats {
  UniformityStats uniformity;
  StructureStats structure;
  TemporalStats temporal;
  StalenessStats staleness;
  BalanceStats balance;
  std::vector<uint8_t> typical_mask;  // one analysed mask (width x height, 1 = updated)
  uint32_t typical_mask_tick = 0;
};

// Per-interval masks of display ticks [begin, end): masks[k][pixel] = 1 if updated in tick begin+k.
std::vector<std::vector<uint8_t>> interval_masks(const UpdateTrace& trace, uint32_t begin, uint32_t end);
// `temporal`: analyze_temporal(trace), passed in so the trace is not walked twice.
StalenessStats analyze_staleness(const UpdateTrace& trace, const TemporalStats& temporal,
                                 int curve_points = 81);
TemporalStats analyze_temporal(const UpdateTrace& trace);
BalanceStats analyze_balance(const UpdateTrace& trace);

// Everything at once.
OrderStats analyze_trace(const UpdateTrace& trace, const StructureOptions& options = {});

}  // namespace frameless
