// Drives an Engine with an update log to record an UpdateTrace for the statistics of issue 5;
// runs on the control thread (the engine's render threads do the work).
#pragma once
#include "core/scene/camera.h"
#include "core/scene/scene.h"
#include "frameless/engine_config.h"
#include "frameless/stats_analysis.h"

namespace frameless {

struct StatsRunConfig {
  int width = 128;
  int height = 96;
  int threads = 1;
  int chunk_size = 64;
  double update_percent = 1.0;
  PixelOrder order = PixelOrder::hilbert_shuffled;
  uint64_t seed = 1;
  bool deterministic = true;   // virtual clock (reproducible); false: wall clock
  double sweeps = 4.0;         // deterministic: run length in sweeps (extended to cover staleness)
  double duration = 2.0;       // wall clock: run length in seconds
  int ticks_per_sweep = 8;     // deterministic: display intervals per sweep (mask density 1/this)
  double refresh_hz = 30.0;    // display ticks per second (virtual in deterministic mode)
  double change_at = 1.0;      // camera change after this many sweeps (deterministic; wall
                               // clock: at a third of the duration); < 0: no change
  size_t max_log_records = size_t(1) << 23;  // wall clock: log capacity over all threads
  SampleShader shader;         // null: the real ray tracer
};

// The engine settings of a stats run (size, threads, chunks, order, seed, clock, shader).
EngineConfig engine_config(const StatsRunConfig& config);

// A cheap synthetic shader (constant grey): in deterministic mode where pixels are updated does
// not depend on what is shaded, so the distribution statistics use it to run fast.
SampleShader flat_shader();

// A camera visibly different from `camera` (the eye moved sideways), for the staleness change.
Camera moved_camera(const Camera& camera);

// Runs the engine and returns its trace. Throws std::runtime_error on an engine error.
UpdateTrace run_for_stats(const Scene& scene, const Camera& camera, const StatsRunConfig& config);

// Wall-clock samples per second of `config` (its shader; null = real ray tracer) over `seconds`.
double measure_samples_per_s(const Scene& scene, const Camera& camera, const StatsRunConfig& config,
                             double seconds);

}  // namespace frameless
