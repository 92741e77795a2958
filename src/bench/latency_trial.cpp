// Camera-change latency: see latency_trial.h.
#include "bench/latency_trial.h"

#include <algorithm>
#include <cmath>
#include <mutex>
#include <stdexcept>

#include "bench/bench_report.h"
#include "display/display_thread.h"
#include "frameless/engine.h"

namespace frameless::bench {

LatencyTrial latency_from(const std::vector<std::pair<double, double>>& series, double t0) {
  LatencyTrial t;
  t.p50 = t.p95 = t.p100 = NAN;
  for (const auto& [time, cov] : series) {
    const double ms = (time - t0) * 1e3;
    t.curve.push_back({ms, cov});
    if (std::isnan(t.p50) && cov >= 0.5) t.p50 = ms;
    if (std::isnan(t.p95) && cov >= 0.95) t.p95 = ms;
    if (std::isnan(t.p100) && cov >= 1.0) t.p100 = ms;
  }
  return t;
}

LatencyTrial measure_latency(const Scene& scene, const EngineConfig& config, const Camera& camera,
                             double refresh_hz, double max_seconds) {
  Engine e(scene, config, camera);
  DisplayConfig dc;
  dc.refresh_hz = refresh_hz;
  DisplayThread d(e, dc);
  std::mutex m;
  std::vector<std::pair<double, double>> series;  // (engine seconds, coverage)
  uint32_t watched = 0;
  d.set_on_tick_info([&](const FrameInfo& info) {
    std::lock_guard<std::mutex> lock(m);
    if (watched && info.newest_epoch == watched)
      series.push_back({info.virtual_time, info.coverage});
  });
  e.start();
  d.start();
  sleep_s(0.4);  // warm-up: threads running, display ticking
  Camera moved = camera;
  moved.eye += 0.05f * (camera.look - camera.eye);
  const EngineStats s0 = e.stats();
  double t0;
  {
    std::lock_guard<std::mutex> lock(m);
    t0 = e.now();
    watched = e.publish_camera(moved);
  }
  for (int k = 0; k < int(max_seconds / 0.005); ++k) {
    sleep_s(0.005);
    std::lock_guard<std::mutex> lock(m);
    if (!series.empty() && series.back().second >= 1.0) break;
  }
  const EngineStats s1 = e.stats();
  d.stop();
  e.stop();
  if (e.error()) throw std::runtime_error(*e.error());
  LatencyTrial t = latency_from(series, t0);
  const double updates_per_s =
      double(s1.updates - s0.updates) / std::max(1e-9, s1.seconds - s0.seconds);
  t.ideal = double(config.width) * config.height / std::max(1.0, updates_per_s) * 1e3;
  return t;
}

}  // namespace frameless::bench
