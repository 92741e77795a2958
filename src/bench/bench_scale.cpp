// `frameless bench scale`: spheres:N for N = 10^3 ... 3.5e7: build time, memory per sphere (BVH +
// geometry bytes and process RSS), samples/s and the cost of a primary ray; fits the slope of
// log(time per ray) against log N to show that ray-tracing cost grows sub-linearly (seed section
// 4).
#include "bench/bench_scale.h"

#include <malloc.h>
#include <atomic>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <memory>
#include <thread>

#include "bench/bench_options.h"
#include "bench/bench_report.h"
#include "core/scenes/builtin_scenes.h"
#include "frameless/cpu_clock.h"
#include "frameless/tile_render.h"

namespace frameless::bench {
namespace {

struct Point {
  uint64_t n = 0;
  double load_s = 0, build_ms = 0, bvh_bytes = 0, geometry_bytes = 0, rss_delta = 0, peak_rss = 0;
  double samples_per_s = 0, ns_per_sample = 0, ns_per_ray = 0, hit_fraction = 0;
};

// Primary rays through the pixel centres, closest hit, on `threads` threads: ns per ray (wall).
double ns_per_primary_ray(const Scene& scene, int width, int height, int threads,
                          double* hit_fraction) {
  const CameraBasis basis = make_camera_basis(scene.camera, width, height);
  const size_t pixels = size_t(width) * size_t(height);
  const size_t rays = std::max<size_t>(pixels, 200000);
  std::atomic<size_t> next{0};
  std::atomic<uint64_t> hits{0}, cpu_ns{0};
  auto worker = [&] {
    enable_flush_to_zero();
    const double c0 = thread_cpu_seconds();
    uint64_t h = 0;
    for (;;) {
      const size_t b = next.fetch_add(1024);
      if (b >= rays) break;
      for (size_t i = b; i < std::min(rays, b + 1024); ++i) {
        const size_t p = i % pixels;
        Hit hit;
        h += scene.accel.intersect(
            camera_ray(basis, float(p % size_t(width)) + 0.5f, float(p / size_t(width)) + 0.5f),
            hit);
      }
    }
    hits.fetch_add(h);
    cpu_ns.fetch_add(uint64_t((thread_cpu_seconds() - c0) * 1e9));
  };
  std::vector<std::thread> pool;
  for (int i = 0; i < threads; ++i) pool.emplace_back(worker);
  for (std::thread& t : pool) t.join();
  if (hit_fraction) *hit_fraction = double(hits.load()) / double(rays);
  // Thread CPU time, which other processes on a shared machine do not inflate.
  return double(cpu_ns.load()) / double(rays);
}

}  // namespace

int run_scale(const ScaleOptions& options) {
  ScaleOptions a = options;
  std::string error;
  if (a.quick) {
    a.max_n = std::min(a.max_n, 1e5);
    a.size = "96x72";
    a.spp = 2;
  }
  int width = 0, height = 0;
  if (!parse_size(a.size, width, height, error)) return report_error(error);
  if (!valid_threads(a.threads, error)) return report_error(error);
  if (a.spp < 1 || a.spp > 4096) return report_error("--spp: must be in [1, 4096]");
  if (!(a.max_n >= 1 && a.max_n <= double(kMaxRandomSpheres)))
    return report_error("--max-n: must be in [1, " + std::to_string(kMaxRandomSpheres) + "]");
  if (a.ns.empty()) {
    for (double n = 1e3; n <= 1e7; n *= 10) a.ns.push_back(n);
    a.ns.push_back(double(kMaxRandomSpheres));
  }
  std::vector<uint64_t> ns;
  for (double n : a.ns) {
    if (!(n >= 1 && n <= double(kMaxRandomSpheres)))
      return report_error("--n: each must be in [1, 35000000]");
    if (n <= a.max_n) ns.push_back(uint64_t(std::llround(n)));
  }
  if (ns.empty()) return report_error("--max-n: leaves no N to run");
  if (!prepare_out_dir(a.out, error)) return report_error(error);
  const int threads = a.threads > 0 ? a.threads : hardware_threads();
  // The loads build on --threads threads too: the build time is one of the figures.
  const ScopedBuildExecutor build_threads(thread_parallel_for(threads));
  try {
    nlohmann::json settings = {
        {"ns", ns},
        {"max_n", a.max_n},
        {"size", a.size},
        {"spp", a.spp},
        {"threads", threads},
        {"quick", a.quick},
        {"scene", "spheres:N (random spheres in a cube of side cbrt(N): same density and picture)"},
        {"ray_cost",
         "primary rays through pixel centres, closest hit, thread CPU ns per ray; ns_per_sample = "
         "process CPU ns per shaded sample (render_tiles)"}};
    nlohmann::json j = bench_header("scale", nullptr, "spheres:N", settings);
    std::vector<Point> points;
    for (uint64_t n : ns) {
      bench_progress("scale", "spheres:" + std::to_string(n));
      malloc_trim(0);
      const double rss0 = rss_bytes();
      Point p;
      p.n = n;
      const auto t0 = std::chrono::steady_clock::now();
      std::unique_ptr<Scene> scene = load_scene_or_report("spheres:" + std::to_string(n));
      if (!scene) return 2;
      p.load_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
      const AccelStats& st = scene->accel.stats();
      p.build_ms = st.build_ms;
      p.bvh_bytes = double(st.bytes);
      p.geometry_bytes = double(st.geometry_bytes);
      p.rss_delta = rss_bytes() - rss0;
      p.peak_rss = peak_rss_bytes();
      TileRenderOptions o;
      o.spp = a.spp;
      o.threads = threads;
      const double cpu0 = process_cpu_seconds();
      const RenderedImage img =
          render_tiles(*scene, make_camera_basis(scene->camera, width, height), o);
      const double samples = double(width) * height * a.spp;
      p.samples_per_s = samples / std::max(1e-9, img.seconds);
      p.ns_per_sample = (process_cpu_seconds() - cpu0) * 1e9 / samples;  // CPU ns, all threads
      p.ns_per_ray = ns_per_primary_ray(*scene, width, height, threads, &p.hit_fraction);
      points.push_back(p);
      if (show_progress())
        std::fprintf(stderr, "  build %.1f s, %.1f bytes/sphere, %.3g samples/s, %.0f ns/ray\n",
                     p.build_ms * 1e-3, (p.bvh_bytes + p.geometry_bytes) / double(n),
                     p.samples_per_s, p.ns_per_ray);
    }
    std::vector<double> lx, ly_ray, ly_sample, ly_build;
    CsvTable csv;
    csv.header = {"n",
                  "load_s",
                  "build_ms",
                  "bvh_bytes",
                  "geometry_bytes",
                  "bytes_per_sphere",
                  "rss_delta_bytes",
                  "rss_bytes_per_sphere",
                  "samples_per_s",
                  "ns_per_sample",
                  "ns_per_ray",
                  "hit_fraction"};
    std::string dat;
    j["points"] = nlohmann::json::array();
    for (const Point& p : points) {
      const double per = (p.bvh_bytes + p.geometry_bytes) / double(p.n);
      j["points"].push_back({{"n", p.n},
                             {"load_s", p.load_s},
                             {"build_ms", p.build_ms},
                             {"bvh_bytes", p.bvh_bytes},
                             {"geometry_bytes", p.geometry_bytes},
                             {"bytes_per_sphere", per},
                             {"rss_delta_bytes", p.rss_delta},
                             {"rss_bytes_per_sphere", p.rss_delta / double(p.n)},
                             {"peak_rss_bytes", p.peak_rss},
                             {"samples_per_s", p.samples_per_s},
                             {"ns_per_sample", p.ns_per_sample},
                             {"ns_per_ray", p.ns_per_ray},
                             {"hit_fraction", p.hit_fraction}});
      csv.rows.push_back({std::to_string(p.n), csv_number(p.load_s), csv_number(p.build_ms),
                          csv_number(p.bvh_bytes), csv_number(p.geometry_bytes), csv_number(per),
                          csv_number(p.rss_delta), csv_number(p.rss_delta / double(p.n)),
                          csv_number(p.samples_per_s), csv_number(p.ns_per_sample),
                          csv_number(p.ns_per_ray), csv_number(p.hit_fraction)});
      dat += std::to_string(p.n) + " " + csv_number(p.ns_per_ray) + " " +
             csv_number(p.ns_per_sample) + " " + csv_number(p.build_ms) + " " + csv_number(per) +
             " " + csv_number(p.rss_delta / double(p.n)) + "\n";
      lx.push_back(std::log(double(p.n)));
      ly_ray.push_back(std::log(p.ns_per_ray));
      ly_sample.push_back(std::log(p.ns_per_sample));
      ly_build.push_back(std::log(std::max(1e-3, p.build_ms)));
    }
    double a_ray = 0, r2_ray = 0, a_sample = 0, r2_sample = 0;
    const double b_ray = fit_slope(lx, ly_ray, &a_ray, &r2_ray);
    const double b_sample = fit_slope(lx, ly_sample, &a_sample, &r2_sample);
    const double b_build = fit_slope(lx, ly_build);
    auto num = [](double v) { return std::isnan(v) ? nlohmann::json() : nlohmann::json(v); };
    j["fit"] = {{"ray_time_slope", num(b_ray)},
                {"ray_time_r2", num(r2_ray)},
                {"sample_time_slope", num(b_sample)},
                {"sample_time_r2", num(r2_sample)},
                {"build_time_slope", num(b_build)},
                {"sublinear", !std::isnan(b_ray) && b_ray < 1.0},
                {"note",
                 "least-squares slope of log(time) against log(N): 1 = linear (brute force), "
                 "about 0 to 0.3 = logarithmic (a BVH); build time is expected near 1 (N log N)"}};
    if (!write_text_atomic(a.out + "/scale.csv", csv.text(), error) ||
        !write_text_atomic(a.out + "/scale.dat", dat, error))
      return report_error(error);
    std::string body =
        "set multiplot layout 1,2\nset grid\nset logscale xy\nset format x '10^{%T}'\nset format y "
        "'%g'\n";
    body += "set title sprintf('Cost per ray and per sample vs spheres (slope %.3f / %.3f)', " +
            csv_number(b_ray) + ", " + csv_number(b_sample) + ")\n";
    body += "set xlabel 'spheres N'\nset ylabel 'CPU nanoseconds'\nset key top left\n";
    body += "plot '" + a.out +
            "/scale.dat' using 1:2 with linespoints lw 2 title 'primary ray (closest hit)', '' "
            "using 1:3 "
            "with linespoints lw 2 title 'shaded sample', exp(" +
            csv_number(a_ray) + ")*x**" + csv_number(b_ray) +
            " dt 2 lc rgb 'gray40' title 'fit', " +
            csv_number(points[0].ns_per_ray / double(points[0].n)) +
            "*x dt 3 lc rgb 'gray60' title 'linear in N'\n";
    body += "set title 'Build time and memory per sphere'\nset ylabel 'ms  /  bytes per sphere'\n";
    body += "plot '" + a.out +
            "/scale.dat' using 1:4 with linespoints lw 2 title 'build ms', '' using 1:5 with "
            "linespoints lw 2 title 'BVH + geometry bytes/sphere', '' using 1:6 with linespoints "
            "lw 2 title 'RSS bytes/sphere'\n";
    body += "unset multiplot";
    bool png = false;
    if (!plot_png(a.out, "scale", 1000, 400, body, error, &png)) return report_error(error);
    j["outputs"] = {{"csv", "scale.csv"}, {"plot", png ? "scale.png" : ""}};
    if (!write_json(a.out + "/scale.json", j, error)) return report_error(error);
    std::printf("bench scale: spheres:N, %d threads (rendering and builds), %dx%d at %d spp\n", threads, width, height,
                a.spp);
    for (const Point& p : points)
      std::printf(
          "  N %9llu: build %8.1f ms, %5.1f B/sphere (RSS %5.1f), %7.3f M samples/s, %6.0f "
          "ns/ray\n",
          (unsigned long long)p.n, p.build_ms, (p.bvh_bytes + p.geometry_bytes) / double(p.n),
          p.rss_delta / double(p.n), p.samples_per_s * 1e-6, p.ns_per_ray);
    std::printf("  slope of log(ray time) vs log N: %.3f (r2 %.2f); per sample %.3f\n", b_ray,
                r2_ray, b_sample);
    std::printf("  wrote %s/scale.json\n", a.out.c_str());
  } catch (const std::exception& ex) {
    return report_error(ex.what());
  }
  return 0;
}

}  // namespace frameless::bench
