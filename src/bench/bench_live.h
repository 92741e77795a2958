// Live wall-clock runs of the real Engine + DisplayThread for the error and motion benchmarks:
// a camera schedule is published from the caller's thread while the display thread scores every
// displayed image against the reference of the camera in effect at that tick.
#pragma once
#include <cstdint>
#include <string>
#include <vector>

#include "core/scene/camera.h"
#include "core/scene/scene.h"
#include "display/display_thread.h"
#include "frameless/engine_config.h"

namespace frameless::bench {

// One mode to run: a label, the engine settings and the display settings.
struct LiveMode {
  std::string name;     // e.g. "frameless a=0.5 p=1"
  std::string kind;     // "frameless", "conventional" or "adaptive"
  EngineConfig engine;  // size, threads, mode, update percent, ...
  DisplayConfig display;
};

// The camera schedule: pose 0 from the start; pose k (k >= 1) is published at
// hold_seconds + (k - 1) * pose_interval. One reference image per pose.
struct LiveSchedule {
  std::vector<Camera> poses;
  std::vector<const std::vector<float>*> references;  // 3 floats per pixel each
  std::vector<double> noise_mse;                      // each reference's own noise floor
  double hold_seconds = 0;                            // pose 0 holds still this long
  double pose_interval = 0.1;                         // seconds between later poses
  double duration = 1;                                // total run length in seconds
};

// What the display showed at one tick.
struct TickRecord {
  double t = 0;          // seconds since the display thread started (steady clock)
  uint64_t samples = 0;  // samples traced since the start, all threads
  int pose = 0;          // index of the newest published pose at this tick
  double rmse = 0, rel_mse = 0, mse = 0;
  double rmse_debiased = 0;  // RMSE with the reference's noise floor taken out
  double coverage = 0;       // fraction of pixels showing the newest camera
};

struct LiveResult {
  std::vector<TickRecord> ticks;
  double samples_per_s = 0;  // engine samples / engine seconds
  double seconds = 0;        // wall time of the run
  uint64_t dropped = 0;
  ReprojectTotals reproject;         // what the display's reprojection did
  double display_cpu_seconds = 0;    // display-thread CPU (scoring every image included)
};

// Runs `mode` for schedule.duration seconds; throws std::runtime_error on an engine or display
// error.
LiveResult run_live(const Scene& scene, const LiveMode& mode, const LiveSchedule& schedule);

// Time-average of a per-tick value over ticks with t in [t0, t1] (each tick weighted by the
// interval until the next one, so an irregular display rate does not bias it).
double time_average(const std::vector<TickRecord>& ticks, double t0, double t1,
                    double TickRecord::*field);

}  // namespace frameless::bench
