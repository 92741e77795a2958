// `frameless bench scaling`: samples/s of the frameless engine and primary-ray Mrays/s of the BVH
// for 1, 2, ... threads up to the hardware threads and oversubscribed (2x, 4x); speed-up and
// efficiency against linear scaling (capped at the core count); and the conventional mode's frame
// barrier per frame (release mean and worst, completion, load-imbalance wait) at each count.
#include "bench/bench_scaling.h"

#include <atomic>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <memory>
#include <thread>

#include "bench/bench_options.h"
#include "bench/bench_report.h"
#include "frameless/engine.h"
#include "frameless/tile_render.h"

namespace frameless::bench {
namespace {

struct Throughput {
  double samples_per_s = 0, cpu_fraction = 0;
};

// Engine samples/s after a warm-up (render threads only, no display), and process CPU use.
Throughput engine_rate(const Scene& scene, EngineConfig c, double seconds) {
  Engine e(scene, c, scene.camera);
  e.start();
  sleep_s(0.3);
  const EngineStats a = e.stats();
  const double cpu0 = process_cpu_seconds();
  const auto w0 = std::chrono::steady_clock::now();
  sleep_s(seconds);
  const EngineStats b = e.stats();
  const double cpu1 = process_cpu_seconds();
  const double wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - w0).count();
  e.stop();
  if (e.error()) throw std::runtime_error(*e.error());
  return {double(b.samples - a.samples) / (b.seconds - a.seconds), (cpu1 - cpu0) / wall};
}

// Conventional mode's frame barrier (Parker et al. section 2.1: RTRT's took 61 us on 64 CPUs):
// frames of 64 x 64 pixels, many barriers a second, for `seconds`.
EngineStats barrier_run(const Scene& scene, int threads, double seconds) {
  EngineConfig c;
  c.width = c.height = 64;
  c.threads = threads;
  c.mode = RenderMode::conventional;
  Engine e(scene, c, scene.camera);
  e.start();
  sleep_s(seconds);
  const EngineStats s = e.stats();
  e.stop();
  if (e.error()) throw std::runtime_error(*e.error());
  return s;
}

// Primary rays through every pixel (pixel centres plus jitter-free repeats) traced with
// Accel::intersect by `threads` threads for about `seconds`; rays per second.
double ray_rate(const Scene& scene, int width, int height, int threads, double seconds) {
  const CameraBasis basis = make_camera_basis(scene.camera, width, height);
  const size_t pixels = size_t(width) * size_t(height);
  std::atomic<size_t> next{0};
  std::atomic<bool> stop{false};
  std::atomic<uint64_t> traced{0}, hit_count{0};
  auto worker = [&] {
    enable_flush_to_zero();
    uint64_t n = 0, hits = 0;
    while (!stop.load(std::memory_order_relaxed)) {
      const size_t b = next.fetch_add(256, std::memory_order_relaxed);
      for (size_t i = b; i < b + 256; ++i) {
        const size_t p = i % pixels;
        Ray r = camera_ray(basis, float(p % size_t(width)) + 0.5f, float(p / size_t(width)) + 0.5f);
        Hit h;
        hits += scene.accel.intersect(r, h) ? 1 : 0;
      }
      n += 256;
    }
    traced.fetch_add(n);
    hit_count.fetch_add(hits);  // keeps the result live
  };
  const auto t0 = std::chrono::steady_clock::now();
  std::vector<std::thread> pool;
  for (int i = 0; i < threads; ++i) pool.emplace_back(worker);
  sleep_s(seconds);
  stop = true;
  for (std::thread& t : pool) t.join();
  const double wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  return double(traced.load()) / wall;
}

}  // namespace

int run_scaling(const ScalingOptions& options) {
  ScalingOptions a = options;
  std::string error;
  if (a.quick) {
    a.size = "160x120";
    a.seconds = 0.5;
  }
  int width = 0, height = 0;
  if (!parse_size(a.size, width, height, error)) return report_error(error);
  if (!(a.seconds > 0 && a.seconds <= 600)) return report_error("--seconds: must be in (0, 600]");
  const int cores = hardware_threads();
  if (a.threads.empty()) {
    for (int t = 1; t <= cores; t = t < 4 ? t + 1 : t * 2) a.threads.push_back(t);
    if (a.threads.back() != cores) a.threads.push_back(cores);
    a.threads.push_back(2 * cores);
    a.threads.push_back(4 * cores);
  }
  for (int t : a.threads)
    if (t < 1 || t > 1024) return report_error("--threads: each must be between 1 and 1024");
  if (!prepare_out_dir(a.out, error)) return report_error(error);
  std::unique_ptr<Scene> scene = load_scene_or_report(a.scene, &a.shadows);
  if (!scene) return 2;
  try {
    nlohmann::json settings = {
        {"size", a.size},
        {"threads", a.threads},
        {"seconds_per_point", a.seconds},
        {"hardware_threads", cores},
        {"quick", a.quick},
        {"engine", "frameless mode, no display thread, default EngineConfig otherwise"},
        {"rays", "primary rays through pixel centres, Accel::intersect (closest hit), no shading"}};
    nlohmann::json j = bench_header("scaling", scene.get(), a.scene, settings);
    CsvTable csv;
    csv.header = {"threads",     "samples_per_s",  "speedup",        "efficiency",    "mrays_per_s",
                  "ray_speedup", "ray_efficiency", "cpu_cores_used", "cpu_efficiency"};
    std::string dat;
    double base_s = 0, base_r = 0, base_cpu = 0;
    j["points"] = nlohmann::json::array();
    for (int t : a.threads) {
      bench_progress("scaling", std::to_string(t) + " threads");
      EngineConfig c;
      c.width = width;
      c.height = height;
      c.threads = t;
      const Throughput th = engine_rate(*scene, c, a.seconds);
      const double rays = ray_rate(*scene, width, height, t, a.seconds);
      const EngineStats bar = barrier_run(*scene, t, a.seconds);
      if (base_s == 0)
        base_s = th.samples_per_s / a.threads.front();  // per-thread rate of the first point
      if (base_r == 0) base_r = rays / a.threads.front();
      const double ideal = std::min(t, cores);
      const double sp = th.samples_per_s / base_s, rsp = rays / base_r;
      // Per CPU-second: what the threads achieve with the CPU they actually got. On a machine
      // shared with other work this separates the engine's own scaling from missing cores.
      const double per_cpu = th.samples_per_s / std::max(1e-9, th.cpu_fraction);
      if (base_cpu == 0) base_cpu = per_cpu;
      j["points"].push_back({{"threads", t},
                             {"samples_per_s", th.samples_per_s},
                             {"speedup", sp},
                             {"efficiency", sp / ideal},
                             {"mrays_per_s", rays * 1e-6},
                             {"ray_speedup", rsp},
                             {"ray_efficiency", rsp / ideal},
                             {"cpu_cores_used", th.cpu_fraction},
                             {"samples_per_cpu_s", per_cpu},
                             {"cpu_efficiency", per_cpu / base_cpu},
                             {"barrier_frames", bar.barrier_frames},
                             {"barrier_release_mean_us", bar.barrier_release_mean_us},
                             {"barrier_release_max_us", bar.barrier_release_max_us},
                             {"barrier_completion_mean_us", bar.barrier_completion_mean_us},
                             {"barrier_wait_mean_us", bar.barrier_wait_mean_us}});
      csv.rows.push_back({std::to_string(t), csv_number(th.samples_per_s), csv_number(sp),
                          csv_number(sp / ideal), csv_number(rays * 1e-6), csv_number(rsp),
                          csv_number(rsp / ideal), csv_number(th.cpu_fraction),
                          csv_number(per_cpu / base_cpu)});
      dat += std::to_string(t) + " " + csv_number(sp) + " " + csv_number(rsp) + " " +
             csv_number(sp / ideal) + " " + csv_number(rsp / ideal) + " " +
             csv_number(per_cpu / base_cpu) + " " + csv_number(th.cpu_fraction) + "\n";
    }
    j["efficiency_note"] =
        "speedup = rate / (rate of the first point per thread); efficiency = speedup / "
        "min(threads, hardware threads): 1 = linear up to the cores, flat beyond; cpu_efficiency = "
        "samples "
        "per process CPU-second relative to the first point: the engine's own overhead "
        "(contention, sharing) without the cores other processes took";
    if (!write_text_atomic(a.out + "/scaling.csv", csv.text(), error) ||
        !write_text_atomic(a.out + "/scaling.dat", dat, error))
      return report_error(error);
    std::string body = "set multiplot layout 1,2\nset grid\nset logscale x 2\nset key top left\n";
    body += "set title 'Speed-up vs threads (" + std::to_string(cores) + " hardware threads)'\n";
    body += "set xlabel 'threads'\nset ylabel 'speed-up over one thread'\nset yrange [0:*]\n";
    body += "plot x < " + std::to_string(cores) + " ? x : " + std::to_string(cores) +
            " dt 2 lc rgb 'gray40' title 'linear to the cores', '" + a.out +
            "/scaling.dat' using 1:2 with linespoints lw 2 title 'engine samples/s', '' using 1:3 "
            "with linespoints lw 2 title 'primary Mrays/s'\n";
    body +=
        "set title 'Efficiency against linear'\nset ylabel 'efficiency (and CPU cores used)'\nset "
        "yrange [0:*]\nset key bottom left\n";
    body += "plot 1 dt 2 lc rgb 'gray40' notitle, '" + a.out +
            "/scaling.dat' using 1:4 with linespoints lw 2 title 'engine', '' using 1:5 with "
            "linespoints lw 2 title 'rays', '' using 1:6 with linespoints lw 2 dt 4 title 'engine "
            "per CPU-second', '' using 1:7 with points pt 7 title 'CPU cores used (engine)'\n";
    body += "unset multiplot";
    bool png = false;
    if (!plot_png(a.out, "scaling", 1000, 400, body, error, &png)) return report_error(error);
    j["outputs"] = {{"csv", "scaling.csv"}, {"plot", png ? "scaling.png" : ""}};
    if (!write_json(a.out + "/scaling.json", j, error)) return report_error(error);
    std::printf("bench scaling: %s %dx%d, %d hardware threads\n", a.scene.c_str(), width, height,
                cores);
    for (const auto& p : j["points"])
      std::printf("  %3d threads: %7.3f M samples/s (eff %.2f), %7.2f Mrays/s (eff %.2f)\n",
                  p["threads"].get<int>(), p["samples_per_s"].get<double>() * 1e-6,
                  p["efficiency"].get<double>(), p["mrays_per_s"].get<double>(),
                  p["ray_efficiency"].get<double>());
    std::printf("  conventional mode's frame barrier (64x64 frames; Parker's RTRT: 61 us on 64 CPUs):\n");
    for (const auto& p : j["points"])
      std::printf("  %3d threads: %6llu frames, release %.1f us mean, %.1f us worst; completion %.1f us; "
                  "waiting for the slowest thread %.1f us\n",
                  p["threads"].get<int>(), (unsigned long long)p["barrier_frames"].get<uint64_t>(),
                  p["barrier_release_mean_us"].get<double>(), p["barrier_release_max_us"].get<double>(),
                  p["barrier_completion_mean_us"].get<double>(), p["barrier_wait_mean_us"].get<double>());
    std::printf("  (efficiency per CPU-second: ");
    for (const auto& p : j["points"]) std::printf("%.2f ", p["cpu_efficiency"].get<double>());
    std::printf(")\n  wrote %s/scaling.json\n", a.out.c_str());
  } catch (const std::exception& ex) {
    return report_error(ex.what());
  }
  return 0;
}

}  // namespace frameless::bench
