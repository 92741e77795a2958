// One camera-change latency trial shared by `bench engine` and `bench latency`: after a warm-up,
// a small dolly is published and the display (wall clock) records, per tick, the fraction of
// pixels showing the new camera.
#pragma once
#include <utility>
#include <vector>

#include "core/scene/camera.h"
#include "core/scene/scene.h"
#include "frameless/engine_config.h"

namespace frameless::bench {

struct LatencyTrial {
  double p50 = 0, p95 = 0, p100 = 0;  // ms from the change to 50/95/100 % coverage (NaN: not reached)
  double ideal = 0;                   // ms to update every pixel once at the measured update rate
  std::vector<std::pair<double, double>> curve;  // (ms since the change, coverage) per tick
};

// p50/p95/p100 and the curve from the display's (engine seconds, coverage of the new camera)
// ticks after a change published at engine time t0 (ideal left 0).
LatencyTrial latency_from(const std::vector<std::pair<double, double>>& series, double t0);

// Throws std::runtime_error if a render thread fails. Gives up after `max_seconds`.
LatencyTrial measure_latency(const Scene& scene, const EngineConfig& config, const Camera& camera,
                             double refresh_hz, double max_seconds = 15.0);

}  // namespace frameless::bench
