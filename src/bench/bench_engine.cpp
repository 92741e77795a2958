// `frameless bench engine`: samples/s in frameless and conventional mode, display-thread CPU cost
// at 60 Hz for 1280x720, and camera-change latency against the ideal; prints text or JSON.
#include "bench/bench_engine.h"

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <memory>
#include <string>
#include <thread>
#include <utility>
#include <vector>

#include <nlohmann/json.hpp>

#include "bench/bench_options.h"
#include "bench/bench_report.h"
#include "bench/latency_trial.h"
#include "display/camera_path.h"
#include "display/display_thread.h"
#include "frameless/cpu_clock.h"
#include "frameless/engine.h"

namespace frameless::bench {
namespace {

void note(const char* what) {
  if (show_progress()) std::fprintf(stderr, "bench engine: %s...\n", what);
}

struct Throughput {
  double per_s = 0;      // samples per wall second
  double per_cpu_s = 0;  // samples per CPU second of the whole process (render + display threads)
};

// Samples/s after a short warm-up, with a display thread at 60 Hz in both modes (the same load
// the viewer adds). Conventional mode is measured over whole frames: samples cost differs across
// the image, and a window ending mid-frame would count a biased part of it.
Throughput throughput(const Scene& scene, EngineConfig c, const Camera& camera, double seconds) {
  Engine e(scene, c, camera);
  DisplayConfig dc;
  dc.refresh_hz = 60;
  DisplayThread d(e, dc);
  e.start();
  d.start();
  sleep_s(0.3);
  // Waits `at_least` seconds, then in conventional mode until the next frame completes.
  auto wait = [&](double at_least) {
    sleep_s(at_least);
    if (c.mode != RenderMode::conventional) return;
    const uint64_t f0 = e.stats().frames_completed;
    const auto give_up = std::chrono::steady_clock::now() + std::chrono::seconds(30);
    while (e.stats().frames_completed == f0 && std::chrono::steady_clock::now() < give_up)
      sleep_s(0.0005);
  };
  wait(0.0);
  const EngineStats a = e.stats();
  const double c0 = process_cpu_seconds();
  wait(seconds);
  const EngineStats b = e.stats();
  const double c1 = process_cpu_seconds();
  d.stop();
  e.stop();
  if (e.error()) throw std::runtime_error(*e.error());
  if (d.error()) throw std::runtime_error(*d.error());
  return {double(b.samples - a.samples) / (b.seconds - a.seconds),
          double(b.samples - a.samples) / std::max(1e-9, c1 - c0)};
}

struct DisplayCost {
  double cpu_fraction = 0;       // display-thread CPU time / wall time
  double updates_per_s = 0;      // pixel updates it blended per second
  double ns_per_update = 0;      // its CPU time per blended update
  double consumer_fraction = 0;  // CPU of a consumer taking an image per tick (acquire_latest)
  double reprojections_per_s = 0;
  double reproject_fraction = 0;  // the part of cpu_fraction spent reprojecting
  ReprojectTimes phases;          // mean wall ms of each phase of a reprojection
};

// Display-thread CPU time as a fraction of one core while the engine renders; then, separately
// (so it does not take CPU from the render threads during the first measurement), the CPU of a
// consumer that takes every new image as the viewer's presentation thread does.
// `moving`: a camera orbiting 15 degrees a second, published at 30 Hz, during the measurement;
// `reproject`: the display moves its image at every camera change (the render cache);
// `viewer`: the consumer runs during the measurement instead (the viewer's case: the display
// hands over every image, so each tick brings another buffer up to date).
DisplayCost display_cpu(const Scene& scene, EngineConfig c, const Camera& camera, double seconds,
                        bool moving = false, bool reproject = false, float budget = 0.0f,
                        int width = 1280, int height = 720, bool viewer = false) {
  c.width = width;
  c.height = height;
  Engine e(scene, c, camera);
  DisplayConfig dc;
  dc.refresh_hz = 60;
  dc.blend.reproject = reproject;
  dc.blend.reproject_budget = budget;
  DisplayThread d(e, dc);
  e.start();
  d.start();
  std::atomic<bool> stop{false};
  std::thread mover;
  if (moving)
    mover = std::thread([&] {
      const CameraPath path = make_shorthand_path(camera, {15.0 * (seconds + 1.0), 1.0}, seconds + 1.0);
      const auto t0 = std::chrono::steady_clock::now();
      for (int k = 1; !stop.load(); ++k) {
        std::this_thread::sleep_until(t0 + std::chrono::microseconds(k * 33333));
        e.publish_camera(evaluate_camera_path(path, k / 30.0, camera));
      }
    });
  // Takes every image (polling at twice the display rate) until `done`, adding its CPU time while
  // `counting`: the viewer's consumer starts with the display but counts from the window's start.
  std::atomic<bool> done{false}, counting{false};
  double consumer_cpu = 0;
  const auto consume = [&] {
    while (!done.load()) {
      const double c0 = thread_cpu_seconds();
      d.acquire_latest();
      if (counting.load()) consumer_cpu += thread_cpu_seconds() - c0;
      sleep_s(1.0 / 120.0);
    }
  };
  std::thread presenter;
  if (viewer) presenter = std::thread(consume);
  sleep_s(0.5);  // skip the first full-image ticks (initial resync and buffer fills)
  const DisplayStats s0 = d.stats();
  counting = viewer;
  auto t0 = std::chrono::steady_clock::now();
  sleep_s(seconds);
  const DisplayStats s1 = d.stats();
  stop = true;
  if (mover.joinable()) mover.join();
  if (!viewer) {  // after the display's window, so it took no CPU from the render threads there
    t0 = std::chrono::steady_clock::now();
    counting = true;
    presenter = std::thread(consume);
    sleep_s(std::max(0.5, seconds / 2));
  }
  done = true;
  presenter.join();
  const double consumer_wall =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  d.stop();
  e.stop();
  // Between tick ends, so the window holds exactly the ticks whose CPU time it counts (a window
  // between stats() calls could count a tick that began before it: a fraction above one).
  const double wall = std::max(1e-9, s1.tick_end_seconds - s0.tick_end_seconds);
  const double updates = double(s1.pixels_updated - s0.pixels_updated);
  DisplayCost r;
  r.cpu_fraction = (s1.cpu_seconds - s0.cpu_seconds) / wall;
  r.reprojections_per_s = double(s1.reproject.reprojections - s0.reproject.reprojections) / wall;
  r.reproject_fraction = (s1.reproject.cpu_seconds - s0.reproject.cpu_seconds) / wall;
  const double moves = double(s1.reproject.reprojections - s0.reproject.reprojections);
  for (int i = 0; i < ReprojectTimes::kPhases; ++i) {
    r.phases.ms[i] = moves > 0 ? (s1.reproject.phase_ms.ms[i] - s0.reproject.phase_ms.ms[i]) / moves : 0.0;
    r.phases.cpu_ms[i] = moves > 0 ? (s1.reproject.phase_ms.cpu_ms[i] - s0.reproject.phase_ms.cpu_ms[i]) / moves : 0.0;
  }
  r.updates_per_s = updates / wall;
  r.ns_per_update = updates > 0 ? 1e9 * (s1.cpu_seconds - s0.cpu_seconds) / updates : 0.0;
  r.consumer_fraction = consumer_cpu / std::max(1e-9, consumer_wall);
  return r;
}

}  // namespace

int run_engine(const EngineBenchOptions& a) {
  std::string error;
  int width = 0, height = 0;
  if (!parse_size(a.size, width, height, error)) return report_error(error);
  if (!valid_threads(a.threads, error)) return report_error(error);
  if (!(a.seconds > 0 && a.seconds <= 600)) return report_error("--seconds: must be in (0, 600]");
  if (!(a.budget > 0 && a.budget <= 1)) return report_error("--budget: must be in (0, 1]");
  if (a.render_nice < 0 || a.render_nice > kMaxRenderNice) return report_error("--render-nice: must be 0..19");
  std::vector<std::pair<int, int>> moving_sizes;
  for (const std::string& size : a.moving_sizes) {
    int w = 0, h = 0;
    if (!parse_size(size, w, h, error, "--moving-sizes")) return report_error(error);
    moving_sizes.emplace_back(w, h);
  }
  std::unique_ptr<Scene> scene = load_scene_or_report(a.scene, &a.shadows);
  if (!scene) return 2;
  EngineConfig c;
  c.width = width;
  c.height = height;
  c.threads = a.threads > 0 ? a.threads : hardware_threads();
  c.track_variance = false;
  c.render_nice = a.render_nice;
  const Camera camera = scene->camera;

  try {
    // Interleaved runs (frameless, conventional, frameless, ...): a load change on a shared
    // machine then hits both modes alike; each figure is the median of its runs, and the
    // overhead is the median of the per-pair ratios.
    EngineConfig cc = c;
    cc.mode = RenderMode::conventional;
    // The same runs with camera rays traced one by one: the gain of ray packets (same images).
    EngineConfig c1 = c, cc1 = cc;
    c1.packets = cc1.packets = false;
    std::vector<double> fl_s, conv_s, fl_cpu, conv_cpu, ratio, ratio_cpu, cpus, ups, nspu, cons;
    std::vector<double> cpu_moving, cpu_reproject, cpu_reproject_part, reproj_rate, cpu_still_reproject;
    std::vector<double> cpu_budget, reproj_rate_budget;
    std::vector<double> fl1_s, conv1_s, gain_fl, gain_conv;
    for (int k = 0; k < std::max(1, a.repeats); ++k) {
      note("frameless throughput");
      const Throughput f = throughput(*scene, c, camera, a.seconds);
      note("conventional throughput");
      const Throughput v = throughput(*scene, cc, camera, a.seconds);
      note("frameless throughput, single rays");
      const Throughput f1 = throughput(*scene, c1, camera, a.seconds);
      note("conventional throughput, single rays");
      const Throughput v1 = throughput(*scene, cc1, camera, a.seconds);
      fl1_s.push_back(f1.per_s);
      conv1_s.push_back(v1.per_s);
      gain_fl.push_back(f.per_cpu_s / f1.per_cpu_s);
      gain_conv.push_back(v.per_cpu_s / v1.per_cpu_s);
      fl_s.push_back(f.per_s);
      conv_s.push_back(v.per_s);
      fl_cpu.push_back(f.per_cpu_s);
      conv_cpu.push_back(v.per_cpu_s);
      ratio.push_back(f.per_s / v.per_s);
      ratio_cpu.push_back(f.per_cpu_s / v.per_cpu_s);
      note("display CPU at 60 Hz, 1280x720");
      const DisplayCost dcost = display_cpu(*scene, c, camera, a.seconds);
      cpus.push_back(dcost.cpu_fraction);
      ups.push_back(dcost.updates_per_s);
      nspu.push_back(dcost.ns_per_update);
      cons.push_back(dcost.consumer_fraction);
      note("display CPU at 60 Hz, 1280x720, camera moving at 30 Hz, with and without reprojection");
      const DisplayCost moving = display_cpu(*scene, c, camera, a.seconds, true, false);
      const DisplayCost cache = display_cpu(*scene, c, camera, a.seconds, true, true);
      const DisplayCost still_cache = display_cpu(*scene, c, camera, a.seconds, false, true);
      cpu_still_reproject.push_back(still_cache.cpu_fraction);
      cpu_moving.push_back(moving.cpu_fraction);
      cpu_reproject.push_back(cache.cpu_fraction);
      const DisplayCost budget = display_cpu(*scene, c, camera, a.seconds, true, true, float(a.budget));
      cpu_budget.push_back(budget.cpu_fraction);
      reproj_rate_budget.push_back(budget.reprojections_per_s);
      cpu_reproject_part.push_back(cache.reproject_fraction);
      reproj_rate.push_back(cache.reprojections_per_s);
    }
    // The moving display with reprojection at further sizes (its cost grows with the pixels).
    nlohmann::json by_size = nlohmann::json::array();
    for (const auto& [w, h] : moving_sizes) {
      std::vector<double> size_cpu, size_rate, size_part, size_phase[ReprojectTimes::kPhases],
          size_phase_cpu[ReprojectTimes::kPhases];
      std::vector<double> viewer_cpu, viewer_consumer, viewer_rate;
      for (int k = 0; k < std::max(1, a.repeats); ++k) {
        note(("display CPU at 60 Hz, " + std::to_string(w) + "x" + std::to_string(h) +
              ", camera moving at 30 Hz, with reprojection").c_str());
        const DisplayCost m = display_cpu(*scene, c, camera, a.seconds, true, true, 0.0f, w, h);
        note(("display CPU at 60 Hz, " + std::to_string(w) + "x" + std::to_string(h) +
              ", camera moving at 30 Hz, with reprojection and a consumer taking every image").c_str());
        const DisplayCost v = display_cpu(*scene, c, camera, a.seconds, true, true, 0.0f, w, h, true);
        viewer_cpu.push_back(v.cpu_fraction);
        viewer_consumer.push_back(v.consumer_fraction);
        viewer_rate.push_back(v.reprojections_per_s);
        size_cpu.push_back(m.cpu_fraction);
        size_rate.push_back(m.reprojections_per_s);
        size_part.push_back(m.reproject_fraction);
        for (int i = 0; i < ReprojectTimes::kPhases; ++i) {
          size_phase[i].push_back(m.phases.ms[i]);
          size_phase_cpu[i].push_back(m.phases.cpu_ms[i]);
        }
      }
      const double rate = median(size_rate), part = median(size_part);
      // Each phase's CPU time, and its wall time (the display thread may wait for a core inside it).
      nlohmann::json phases, phases_cpu;
      for (int i = 0; i < ReprojectTimes::kPhases; ++i) {
        phases[ReprojectTimes::kNames[i]] = median(size_phase[i]);
        phases_cpu[ReprojectTimes::kNames[i]] = median(size_phase_cpu[i]);
      }
      by_size.push_back({{"width", w},
                         {"height", h},
                         {"display_cpu_fraction", median(size_cpu)},
                         {"reproject_cpu_fraction", part},
                         {"reprojections_per_s", rate},
                         {"ms_per_reprojection", rate > 0 ? 1e3 * part / rate : 0.0},
                         {"phases_wall_ms", phases},
                         {"phases_cpu_ms", phases_cpu},
                         {"viewer", {{"display_cpu_fraction", median(viewer_cpu)},
                                     {"consumer_cpu_fraction", median(viewer_consumer)},
                                     {"reprojections_per_s", median(viewer_rate)}}}});
    }
    const double fl = median(fl_s), conv = median(conv_s), cpu = median(cpus);
    const double overhead = 1.0 - median(ratio), overhead_cpu = 1.0 - median(ratio_cpu);
    std::vector<double> p50, p95, p100, ideal;
    for (int k = 0; k < std::max(1, a.repeats); ++k) {
      note("camera-change latency");
      // Display at 240 Hz so coverage is sampled finely; a trial that never reaches a level
      // (render thread starved) reports -1.
      const LatencyTrial l = measure_latency(*scene, c, camera, 240.0, 10.0);
      auto ms = [](double v) { return std::isnan(v) ? -1.0 : v; };
      p50.push_back(ms(l.p50));
      p95.push_back(ms(l.p95));
      p100.push_back(ms(l.p100));
      ideal.push_back(l.ideal);
    }
    nlohmann::json j;
    j["scene"] = a.scene;
    j["width"] = width;
    j["height"] = height;
    j["threads"] = c.threads;
    j["hardware_threads"] = hardware_threads();
    j["seconds_per_measurement"] = a.seconds;
    j["frameless_samples_per_s"] = fl;
    j["conventional_samples_per_s"] = conv;
    j["frameless_overhead"] = overhead;
    j["frameless_samples_per_cpu_s"] = median(fl_cpu);
    j["conventional_samples_per_cpu_s"] = median(conv_cpu);
    j["frameless_overhead_per_cpu_s"] = overhead_cpu;
    j["frameless_single_ray_samples_per_s"] = median(fl1_s);
    j["conventional_single_ray_samples_per_s"] = median(conv1_s);
    j["packet_gain_frameless_per_cpu_s"] = median(gain_fl);
    j["packet_gain_conventional_per_cpu_s"] = median(gain_conv);
    j["throughput_repeats"] = fl_s.size();
    j["throughput_with_display_hz"] = 60;
    j["display_cpu_fraction"] = cpu;
    j["display_size"] = "1280x720";
    j["display_hz"] = 60;
    j["display_updates_per_s"] = median(ups);
    j["display_ns_per_update"] = median(nspu);
    j["consumer_cpu_fraction"] = median(cons);
    j["display_cpu_fraction_moving"] = median(cpu_moving);
    j["display_cpu_fraction_moving_reproject"] = median(cpu_reproject);
    j["display_cpu_fraction_moving_reproject_budget"] = median(cpu_budget);
    j["reproject_budget"] = a.budget;
    j["display_reprojections_per_s_budget"] = median(reproj_rate_budget);
    j["display_reproject_cpu_fraction"] = median(cpu_reproject_part);
    j["display_reprojections_per_s"] = median(reproj_rate);
    j["display_cpu_fraction_still_reproject"] = median(cpu_still_reproject);
    j["display_moving_reproject_by_size"] = by_size;
    j["reproject_vector_paths"] = Reprojector::vector_paths();
    j["latency_ms"] = {{"p50", median(p50)}, {"p95", median(p95)}, {"p100", median(p100)}};
    j["latency_ideal_ms"] = median(ideal);
    j["latency_repeats"] = p50.size();
    j["update_percent"] = c.update_percent;
    if (a.json) {
      std::printf("%s\n", j.dump(2).c_str());
    } else {
      std::printf("scene %s %dx%d, %d threads\n", a.scene.c_str(), width, height, c.threads);
      std::printf("frameless    %.3f M samples/s\nconventional %.3f M samples/s (frameless overhead %.1f%%)\n",
                  fl * 1e-6, conv * 1e-6, 100.0 * overhead);
      std::printf("per CPU second: frameless %.3f M, conventional %.3f M (overhead %.1f%%)\n",
                  median(fl_cpu) * 1e-6, median(conv_cpu) * 1e-6, 100.0 * overhead_cpu);
      std::printf("single rays: frameless %.3f M samples/s, conventional %.3f M; packets gain "
                  "x%.2f frameless, x%.2f conventional (per CPU second)\n",
                  median(fl1_s) * 1e-6, median(conv1_s) * 1e-6, median(gain_fl), median(gain_conv));
      std::printf("display thread at 60 Hz, 1280x720: %.2f%% of one core (%.2f M updates/s, %.1f ns each)\n",
                  100.0 * cpu, median(ups) * 1e-6, median(nspu));
      std::printf("consumer taking each image (acquire_latest): %.2f%% of one core\n", 100.0 * median(cons));
      std::printf("display thread, camera moving at 30 Hz: %.2f%% of one core; with reprojection %.2f%% "
                  "(%.2f%% reprojecting, %.1f reprojections/s); still camera with reprojection on %.2f%%\n",
                  100.0 * median(cpu_moving), 100.0 * median(cpu_reproject),
                  100.0 * median(cpu_reproject_part), median(reproj_rate), 100.0 * median(cpu_still_reproject));
      std::printf("  with a reprojection budget of %g%% of a core (--reproject-budget %g): %.2f%% of one "
                  "core, %.1f reprojections/s\n",
                  100.0 * a.budget, a.budget, 100.0 * median(cpu_budget), median(reproj_rate_budget));
      for (const nlohmann::json& m : by_size) {
        std::printf("  moving with reprojection at %dx%d: %.2f%% of one core (%.2f%% reprojecting, %.1f "
                    "reprojections/s, %.1f ms each)\n    its phases (CPU ms a reprojection, wall in brackets):",
                    m["width"].get<int>(), m["height"].get<int>(), 100.0 * m["display_cpu_fraction"].get<double>(),
                    100.0 * m["reproject_cpu_fraction"].get<double>(), m["reprojections_per_s"].get<double>(),
                    m["ms_per_reprojection"].get<double>());
        for (const char* name : ReprojectTimes::kNames)
          std::printf(" %s %.2f (%.2f)", name, m["phases_cpu_ms"][name].get<double>(),
                      m["phases_wall_ms"][name].get<double>());
        std::printf(" (%s paths)\n", Reprojector::vector_paths());
        const nlohmann::json& v = m["viewer"];
        std::printf("    with a consumer taking every image (the viewer): display %.2f%% of one core, consumer "
                    "%.2f%%, %.1f reprojections/s\n",
                    100.0 * v["display_cpu_fraction"].get<double>(), 100.0 * v["consumer_cpu_fraction"].get<double>(),
                    v["reprojections_per_s"].get<double>());
      }
      std::printf("camera change -> 50%% %.1f ms, 95%% %.1f ms, 100%% %.1f ms (ideal %.1f ms)\n",
                  median(p50), median(p95), median(p100), median(ideal));
    }
  } catch (const std::exception& ex) {
    return report_error(ex.what());
  }
  return 0;
}

}  // namespace frameless::bench
