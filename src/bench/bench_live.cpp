// Live Engine + DisplayThread runs scored against reference images at every display tick.
#include "bench/bench_live.h"

#include <chrono>
#include <cmath>
#include <map>
#include <mutex>
#include <stdexcept>
#include <thread>

#include "frameless/engine.h"
#include "frameless/image_error.h"

namespace frameless::bench {

LiveResult run_live(const Scene& scene, const LiveMode& mode, const LiveSchedule& s) {
  if (s.poses.empty() || s.references.size() != s.poses.size())
    throw std::runtime_error("bench: one reference per camera pose is needed");
  using Clock = std::chrono::steady_clock;
  Engine engine(scene, mode.engine, s.poses[0]);
  DisplayThread display(engine, mode.display);
  LiveResult result;
  std::mutex m;
  std::map<uint32_t, int> pose_of_epoch;  // written by this thread, read at each tick
  pose_of_epoch[engine.camera_epoch()] = 0;
  Clock::time_point t0;
  uint64_t samples = 0;
  const size_t pixels = size_t(mode.engine.width) * size_t(mode.engine.height);
  display.set_on_tick([&](const DisplayImage& img) {
    TickRecord r;
    r.t = std::chrono::duration<double>(Clock::now() - t0).count();
    samples += img.info.samples;
    r.samples = samples;
    r.coverage = img.info.coverage;
    {
      std::lock_guard<std::mutex> lock(m);
      auto it = pose_of_epoch.upper_bound(img.info.newest_epoch);
      r.pose = it == pose_of_epoch.begin() ? 0 : std::prev(it)->second;
    }
    if (img.pixels() != pixels) return;
    const ImageError e = image_error(img.rgb.data(), s.references[size_t(r.pose)]->data(), pixels);
    r.mse = e.mse;
    r.rmse = e.rmse;
    r.rel_mse = e.rel_mse;
    r.rmse_debiased =
        std::sqrt(debiased_mse(e.mse, s.noise_mse.empty() ? 0.0 : s.noise_mse[size_t(r.pose)]));
    std::lock_guard<std::mutex> lock(m);
    result.ticks.push_back(r);
  });
  t0 = Clock::now();
  engine.start();
  display.start();
  const EngineStats s0 = engine.stats();
  for (size_t k = 1; k < s.poses.size(); ++k) {
    const double at = s.hold_seconds + double(k - 1) * s.pose_interval;
    if (at >= s.duration) break;
    std::this_thread::sleep_until(
        t0 + std::chrono::duration_cast<Clock::duration>(std::chrono::duration<double>(at)));
    std::lock_guard<std::mutex> lock(m);
    pose_of_epoch[engine.publish_camera(s.poses[k])] = int(k);
  }
  std::this_thread::sleep_until(
      t0 + std::chrono::duration_cast<Clock::duration>(std::chrono::duration<double>(s.duration)));
  display.stop();
  const EngineStats s1 = engine.stats();
  result.reproject = display.stats().reproject;
  result.display_cpu_seconds = display.stats().cpu_seconds;
  engine.stop();
  if (engine.error()) throw std::runtime_error(*engine.error());
  if (display.error()) throw std::runtime_error(*display.error());
  result.seconds = std::chrono::duration<double>(Clock::now() - t0).count();
  result.samples_per_s = double(s1.samples - s0.samples) / std::max(1e-9, s1.seconds - s0.seconds);
  result.dropped = s1.dropped;
  return result;
}

double time_average(const std::vector<TickRecord>& ticks, double t0, double t1,
                    double TickRecord::*field) {
  double sum = 0, weight = 0;
  for (size_t i = 0; i < ticks.size(); ++i) {
    if (ticks[i].t < t0 || ticks[i].t > t1) continue;
    const double next = i + 1 < ticks.size() ? std::min(ticks[i + 1].t, t1) : t1;
    const double w = std::max(0.0, next - ticks[i].t);
    sum += w * ticks[i].*field;
    weight += w;
  }
  return weight > 0 ? sum / weight : std::nan("");
}

}  // namespace frameless::bench
