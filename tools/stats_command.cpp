// `frameless stats`: measures how pixel updates spread over the screen and over time for one or
// all pixel orders, and writes DIR/stats.json, mask PNGs and a gnuplot comparison plot.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <memory>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "bench/bench_report.h"
#include "core/scenes/scene_load.h"
#include "display/atomic_file.h"
#include "display/png_io.h"
#include "frameless/stats_closed_loop.h"
#include "frameless/stats_run.h"
#include "tools/command_registry.h"
#include "tools/tool_options.h"

namespace frameless::cli {
namespace {

using bench::write_text_atomic;

constexpr double kAlpha = 0.001;  // significance level of the verdicts

struct StatsArgs {
  ShadowOptions shadows;
  std::string scene = "default";
  std::string size = "320x240";
  int threads = 0;
  int chunk = 64;
  double update_percent = 1.0;
  std::string order = "hilbert-shuffled";
  bool deterministic = false;
  double sweeps = 0;
  double duration = 0;
  bool compare = false;
  std::string out = "captures/stats";
  int ticks_per_sweep = 8;
  double refresh = 30.0;
  double coherence_seconds = 1.0;
  uint64_t seed = 1;
  CameraOptions camera;
};

struct OrderResult {
  PixelOrder order;
  OrderStats stats;
  double samples_per_s = 0;
  uint64_t overflow = 0;
};

// Updated pixels white, the rest black; gaps between panels grey.
bool write_masks_png(const std::string& path, int w, int h, const std::vector<const OrderResult*>& rs,
                     std::string& error) {
  const int gap = rs.size() > 1 ? 8 : 0;
  const int total_w = int(rs.size()) * w + (int(rs.size()) - 1) * gap;
  std::vector<unsigned char> rgb(size_t(total_w) * size_t(h) * 3, 96);
  for (size_t k = 0; k < rs.size(); ++k) {
    const auto& mask = rs[k]->stats.typical_mask;
    if (mask.size() != size_t(w) * size_t(h)) continue;
    const int x0 = int(k) * (w + gap);
    for (int y = 0; y < h; ++y)
      for (int x = 0; x < w; ++x) {
        const unsigned char v = mask[size_t(y) * size_t(w) + size_t(x)] ? 255 : 0;
        for (int c = 0; c < 3; ++c) rgb[(size_t(y) * size_t(total_w) + size_t(x0 + x)) * 3 + size_t(c)] = v;
      }
  }
  if (auto r = write_png_rgb8(path, total_w, h, rgb.data()); !r) {
    error = r.error().message;
    return false;
  }
  return true;
}

bool gnuplot_available() {
  const char* path = std::getenv("PATH");
  std::string dirs = path ? path : "/usr/bin:/bin";
  size_t start = 0;
  while (start <= dirs.size()) {
    const size_t end = dirs.find(':', start);
    const std::string dir = dirs.substr(start, end == std::string::npos ? std::string::npos : end - start);
    std::error_code ec;
    if (!dir.empty() && std::filesystem::exists(std::filesystem::path(dir) / "gnuplot", ec)) return true;
    if (end == std::string::npos) break;
    start = end + 1;
  }
  return false;
}

// Two panels: spectrum / randomised-chunk null against frequency, and staleness curves.
bool write_plot(const std::string& dir, const std::vector<OrderResult>& rs, std::string& error) {
  std::string spectrum, stale, script;
  for (const OrderResult& r : rs) {
    spectrum += std::string("# ") + to_string(r.order) + "\n";
    const auto& st = r.stats.structure;
    for (size_t i = 0; i < st.radial_freq.size(); ++i)
      spectrum += std::to_string(st.radial_freq[i]) + " " + std::to_string(st.radial_ratio[i]) + " " +
                  std::to_string(st.radial_white[i]) + "\n";
    spectrum += "\n\n";
    stale += std::string("# ") + to_string(r.order) + "\n";
    const auto& sl = r.stats.staleness;
    for (size_t i = 0; i < sl.curve_sweeps.size(); ++i)
      stale += std::to_string(sl.curve_sweeps[i]) + " " + std::to_string(sl.curve_fraction[i]) + "\n";
    stale += "\n\n";
  }
  if (!write_text_atomic(dir + "/spectrum.dat", spectrum, error) || !write_text_atomic(dir + "/staleness.dat", stale, error))
    return false;
  const std::string png = dir + "/compare.png";
  const std::string tmp = temporary_path_for(png);
  script += "set terminal pngcairo size 1000,380 font 'sans,9'\n";
  script += "set output '" + tmp + "'\n";
  script += "set multiplot layout 1,2\n";
  script += "set title 'Update-mask power spectrum / random-chunk null (1 = no structure)'\n";
  script += "set xlabel 'spatial frequency (cycles per pixel)'\nset ylabel 'power ratio'\n";
  script += "set logscale xy\nset format x '%g'\nset format y '%g'\nset xrange [0.005:1]\nset grid\nset key top right\n";
  script += "set arrow from 0.0625, graph 0 to 0.0625, graph 1 nohead dt 2 lc rgb 'gray40'\n";
  script += "plot ";
  for (size_t k = 0; k < rs.size(); ++k) {
    char title[160];
    std::snprintf(title, sizeof title, "%s (%.3g M samples/s)", to_string(rs[k].order),
                  rs[k].samples_per_s * 1e-6);
    script += (k ? ", " : "") + std::string("'") + dir + "/spectrum.dat' index " + std::to_string(k) +
              " using 1:2 with linespoints pt 7 ps 0.5 title '" + title + "'";
  }
  script += "\nunset logscale xy\nunset arrow\n";
  script += "set title 'Staleness after a camera change'\n";
  script += "set xlabel 'sweeps since the change'\nset ylabel 'fraction of pixels showing the new camera'\n";
  script += "set format x '%g'\nset xrange [0:*]\nset yrange [0:1.02]\nset key bottom right\n";
  if (!rs.empty())
    script += "set arrow from " + std::to_string(rs[0].stats.staleness.bound_sweeps) +
              ", graph 0 to " + std::to_string(rs[0].stats.staleness.bound_sweeps) +
              ", graph 1 nohead dt 2 lc rgb 'gray40'\nset label 'bound 1 + p/100' at " +
              std::to_string(rs[0].stats.staleness.bound_sweeps) + ", graph 0.5 right offset -0.5,0\n";
  script += "plot ";
  for (size_t k = 0; k < rs.size(); ++k)
    script += (k ? ", " : "") + std::string("'") + dir + "/staleness.dat' index " + std::to_string(k) +
              " using 1:2 with lines lw 2 title '" + to_string(rs[k].order) + "'";
  script += "\nunset multiplot\nset output\n";
  const std::string gp = dir + "/compare.gp";
  if (!write_text_atomic(gp, script, error)) return false;
  if (!gnuplot_available()) {
    std::fprintf(stderr, "frameless: gnuplot not found; skipped %s (script in %s)\n", png.c_str(), gp.c_str());
    return true;
  }
  const std::string cmd = "gnuplot '" + gp + "' > /dev/null 2>&1";
  if (std::system(cmd.c_str()) != 0) {
    std::remove(tmp.c_str());
    std::fprintf(stderr, "frameless: gnuplot failed on %s; skipped %s\n", gp.c_str(), png.c_str());
    return true;
  }
  return commit_temporary(tmp, png, error);
}

nlohmann::json to_json(const OrderResult& r, int chunk) {
  const OrderStats& s = r.stats;
  nlohmann::json j;
  j["uniformity"] = {{"min", s.uniformity.min},           {"max", s.uniformity.max},
                     {"mean", s.uniformity.mean},         {"cv", s.uniformity.cv},
                     {"chi2", s.uniformity.chi2.chi2},    {"dof", s.uniformity.chi2.dof},
                     {"p_value", s.uniformity.chi2.p_value}, {"pass", s.uniformity.chi2.p_value > kAlpha}};
  const StructureStats& st = s.structure;
  j["structure"] = {{"masks", st.masks},
                    {"mean_density", st.mean_density},
                    {"lowfreq_cutoff", StructureOptions{}.lowfreq_cutoff},
                    {"lowfreq_ratio", st.lowfreq_ratio},
                    {"lowfreq_ratio_white", st.lowfreq_ratio_white},
                    {"lowfreq_terms", st.lowfreq_terms},
                    {"lowfreq_p_value", st.lowfreq_p_value},
                    {"pass", st.lowfreq_p_value > kAlpha},
                    {"morans_i", st.morans_i},
                    {"morans_i_expected", st.morans_i_expected},
                    {"morans_i_variance", st.morans_i_variance},
                    {"morans_i_z", st.morans_i_z},
                    {"morans_i_coarse", st.morans_i_coarse},
                    {"coarse_cell", st.coarse_cell},
                    {"radial", {{"freq", st.radial_freq}, {"ratio", st.radial_ratio}, {"white", st.radial_white}}}};
  j["temporal"] = {{"intervals", s.temporal.intervals},       {"mean_seconds", s.temporal.mean_seconds},
                   {"cv", s.temporal.cv},                     {"max_seconds", s.temporal.max_seconds},
                   {"mean_sweeps", s.temporal.mean_sweeps},   {"max_sweeps", s.temporal.max_sweeps}};
  const StalenessStats& sl = s.staleness;
  // Budget rounding: a few visits of the thread with the fewest pixels.
  uint64_t fewest = 0;
  for (uint64_t p : s.balance.pixels) fewest = fewest ? std::min(fewest, p) : p;
  const double slack = fewest ? 3.0 / double(fewest) : 0.0;
  auto finite = [](double v) { return std::isfinite(v) ? nlohmann::json(v) : nlohmann::json(nullptr); };
  j["staleness"] = {{"measured", sl.measured},
                    {"never", sl.never},
                    {"p50_sweeps", finite(sl.t50_sweeps)},
                    {"p95_sweeps", finite(sl.t95_sweeps)},
                    {"p100_sweeps", finite(sl.t100_sweeps)},
                    {"bound_sweeps", sl.bound_sweeps},
                    {"within_bound", sl.measured && sl.never == 0 && sl.t100_sweeps <= sl.bound_sweeps + slack},
                    {"max_age_sweeps", sl.max_age_sweeps},
                    {"curve", {{"sweeps", sl.curve_sweeps}, {"fraction", sl.curve_fraction}}}};
  nlohmann::json threads = nlohmann::json::array();
  for (size_t t = 0; t < s.balance.pixels.size(); ++t)
    threads.push_back({{"pixels", s.balance.pixels[t]},
                       {"updates", t < s.balance.updates.size() ? s.balance.updates[t] : 0},
                       {"samples_per_s", t < s.balance.samples_per_s.size() ? s.balance.samples_per_s[t] : 0.0},
                       {"busy_s", t < s.balance.busy_s.size() ? s.balance.busy_s[t] : 0.0}});
  j["balance"] = {{"threads", threads},
                  {"pixel_spread", s.balance.pixel_spread},
                  {"chunk_size", chunk},
                  {"within_one_chunk", s.balance.within_one_chunk}};
  j["samples_per_s"] = r.samples_per_s;
  j["log_overflow"] = r.overflow;
  return j;
}

int run_stats(const StatsArgs& a) {
  std::string error;
  if (a.sweeps > 0 && a.duration > 0) return report_error("--sweeps and --duration: give one of them");
  const bool deterministic = a.deterministic || a.sweeps > 0;
  if (deterministic && a.duration > 0)
    return report_error("--duration: wall-clock runs only (use --sweeps with --deterministic)");
  if (a.sweeps < 0 || a.sweeps > 1000) return report_error("--sweeps: must be between 0 and 1000");
  if (a.duration < 0 || a.duration > 3600) return report_error("--duration: must be between 0 and 3600 seconds");
  if (!valid_threads(a.threads, error)) return report_error(error);
  if (a.chunk < 1 || a.chunk > 1 << 20) return report_error("--chunk: must be between 1 and 1048576");
  if (!(a.update_percent >= 0.01 && a.update_percent <= 100))
    return report_error("--update-percent: must be between 0.01 and 100");
  if (a.ticks_per_sweep < 2 || a.ticks_per_sweep > 1024)
    return report_error("--ticks-per-sweep: must be between 2 and 1024");
  if (!(a.refresh >= 1 && a.refresh <= 240)) return report_error("--refresh: must be between 1 and 240");
  if (!(a.coherence_seconds > 0 && a.coherence_seconds <= 600))
    return report_error("--coherence-seconds: must be between 0 and 600");
  const auto order = parse_pixel_order(a.order);
  if (!order) return report_error("--order: unknown order '" + a.order + "' (hilbert-shuffled|hilbert|scanline|random)");
  {
    std::error_code ec;
    std::filesystem::create_directories(a.out, ec);
  }
  if (!directory_writable(a.out, error)) return report_error(error);

  std::unique_ptr<Scene> scene = load_scene_or_report(a.scene, &a.shadows);
  if (!scene) return 2;
  int width = 0, height = 0;
  if (!parse_size(a.size, width, height, error)) return report_error(error);
  if (int64_t(width) * height > 4096 * 4096) return report_error("--size: at most 16777216 pixels for stats");
  Camera camera = scene->camera;
  if (!a.camera.apply(camera, error)) return report_error(error);

  StatsRunConfig rc;
  rc.width = width;
  rc.height = height;
  rc.threads = a.threads > 0 ? a.threads : hardware_threads();
  rc.chunk_size = a.chunk;
  rc.update_percent = a.update_percent;
  rc.seed = a.seed;
  rc.deterministic = deterministic;
  rc.sweeps = a.sweeps > 0 ? a.sweeps : 4.0;
  rc.duration = a.duration > 0 ? a.duration : 2.0;
  rc.ticks_per_sweep = a.ticks_per_sweep;
  rc.refresh_hz = a.refresh;
  // Deterministic: where updates land does not depend on the shading, so a flat shader records it.
  if (deterministic) rc.shader = flat_shader();

  std::vector<PixelOrder> orders = {*order};
  if (a.compare)
    orders = {PixelOrder::hilbert_shuffled, PixelOrder::hilbert, PixelOrder::scanline, PixelOrder::random};
  std::vector<OrderResult> results;
  try {
    for (PixelOrder o : orders) {
      rc.order = o;
      if (show_progress()) std::fprintf(stderr, "%s: recording\n", to_string(o));
      const UpdateTrace trace = run_for_stats(*scene, camera, rc);
      if (show_progress()) std::fprintf(stderr, "%s: analysing\n", to_string(o));
      OrderResult r{o, analyze_trace(trace), trace.samples_per_s, trace.overflow};
      if (deterministic) {
        // Coherence needs the real ray tracer on the real clock.
        if (show_progress()) std::fprintf(stderr, "%s: measuring samples/s\n", to_string(o));
        StatsRunConfig wall = rc;
        wall.shader = SampleShader{};
        r.samples_per_s = measure_samples_per_s(*scene, camera, wall, a.coherence_seconds);
      }
      results.push_back(std::move(r));
    }
  } catch (const std::exception& e) {
    return report_error(e.what());
  }
  // The closed-loop order (render threads serving a display's asks): its starvation bound.
  ClosedLoopStats closed;
  try {
    if (show_progress()) std::fprintf(stderr, "closed loop: recording\n");
    StatsRunConfig cl = rc;
    cl.order = *order;
    closed = closed_loop_stats(*scene, camera, cl);
  } catch (const std::exception& e) {
    return report_error(e.what());
  }

  nlohmann::json j;
  j["config"] = {{"scene", a.scene},         {"width", width},
                 {"height", height},         {"threads", rc.threads},
                 {"chunk", a.chunk},         {"update_percent", a.update_percent},
                 {"deterministic", deterministic},
                 {"sweeps", deterministic ? nlohmann::json(rc.sweeps) : nlohmann::json(nullptr)},
                 {"duration", deterministic ? nlohmann::json(nullptr) : nlohmann::json(rc.duration)},
                 {"ticks_per_sweep", a.ticks_per_sweep}, {"refresh_hz", a.refresh},
                 {"coherence_seconds", deterministic ? nlohmann::json(a.coherence_seconds) : nlohmann::json(nullptr)},
                 {"seed", a.seed},           {"alpha", kAlpha},
                 {"clock", deterministic ? "virtual (per-thread samples_per_s are virtual; samples_per_s is "
                                           "wall clock with the ray tracer)" : "wall"}};
  for (const OrderResult& r : results) j["orders"][to_string(r.order)] = to_json(r, a.chunk);
  nlohmann::json cl_threads = nlohmann::json::array();
  for (const ClosedLoopStats::Thread& t : closed.threads)
    cl_threads.push_back({{"pixels", t.pixels}, {"updates", t.updates}, {"worst_gap_updates", t.worst_gap},
                          {"bound_updates", t.bound}, {"never_updated", t.never_updated},
                          {"asked_share", t.asked_share}});
  j["closed_loop"] = {{"asked_fraction", closed.asked_fraction}, {"sweeps", closed.sweeps},
                      {"bound", "every pixel within 2 n + 2 runs of its thread's updates (n: its list)"},
                      {"bound_holds", closed.bound_holds}, {"threads", cl_threads}};
  if (!write_text_atomic(a.out + "/stats.json", j.dump(2) + "\n", error)) return report_error(error);

  std::vector<const OrderResult*> all;
  for (const OrderResult& r : results) {
    all.push_back(&r);
    if (!write_masks_png(a.out + "/mask_" + to_string(r.order) + ".png", width, height, {&r}, error))
      return report_error(error);
  }
  if (results.size() > 1 && !write_masks_png(a.out + "/masks.png", width, height, all, error))
    return report_error(error);
  if (!write_plot(a.out, results, error)) return report_error(error);

  std::printf("%-17s %10s %10s %9s %10s %8s %8s %8s %8s %9s %11s\n", "order", "chi2 p", "lowfreq", "lf p",
              "moran I", "I coarse", "t50", "t95", "t100", "max age", "Msamples/s");
  for (const OrderResult& r : results) {
    const OrderStats& s = r.stats;
    std::printf("%-17s %10.3g %10.3f %9.2g %10.3f %8.3f %8.3f %8.3f %8.3f %9.3f %11.3f\n", to_string(r.order),
                s.uniformity.chi2.p_value, s.structure.lowfreq_ratio, s.structure.lowfreq_p_value,
                s.structure.morans_i, s.structure.morans_i_coarse, s.staleness.t50_sweeps,
                s.staleness.t95_sweeps, s.staleness.t100_sweeps, s.staleness.max_age_sweeps,
                r.samples_per_s * 1e-6);
    if (r.overflow > 0)
      std::fprintf(stderr, "frameless: %s: %llu updates did not fit the log (analysed the first ones)\n",
                   to_string(r.order), (unsigned long long)r.overflow);
  }
  size_t worst = 0, bound = 0;
  double share = 0;
  for (const ClosedLoopStats::Thread& t : closed.threads) {
    if (t.bound && double(t.worst_gap) / double(t.bound) >= (bound ? double(worst) / double(bound) : 0.0)) {
      worst = t.worst_gap;
      bound = t.bound;
    }
    share += t.asked_share / double(closed.threads.size());
  }
  std::printf("closed-loop order (top half asked every tick): %.0f%% of updates on the asked half, worst "
              "revisit %zu updates, bound %zu: %s\n",
              100.0 * share, worst, bound, closed.bound_holds ? "holds" : "VIOLATED");
  std::printf("wrote %s/stats.json and figures (times in sweeps; p-values at alpha %g)\n", a.out.c_str(), kAlpha);
  if (!closed.bound_holds) {
    std::fprintf(stderr, "frameless: closed-loop order: a pixel waited longer than its starvation bound\n");
    return 1;
  }
  return 0;
}

const bool stats_registered = register_command(
    "", "stats", "Measure the pixel-update distribution (uniformity, structure, staleness, balance, coherence)",
    [](CLI::App& app) {
      auto a = std::make_shared<StatsArgs>();
      app.add_option("scene", a->scene, "built-in name, .json scene or .obj/.ply/.gltf/.glb model (default: default)");
      add_shadow_flags(app, a->shadows);
      app.add_option("--size", a->size, "image size WxH")->capture_default_str();
      app.add_option("--threads", a->threads, "render threads (default: all cores)");
      app.add_option("--chunk", a->chunk, "pixels per chunk of the line")->capture_default_str();
      app.add_option("--update-percent", a->update_percent,
                     "a thread re-reads the camera after this % of its pixels")->capture_default_str();
      app.add_option("--order", a->order, "hilbert-shuffled|hilbert|scanline|random")->capture_default_str();
      app.add_flag("--deterministic", a->deterministic,
                   "virtual clock, reproducible (distribution statistics use a flat shader)");
      // --sweeps and --duration exclude each other; run_stats reports it in the usual one line.
      app.add_option("--sweeps", a->sweeps, "deterministic run length in sweeps (default 4)");
      app.add_option("--duration", a->duration, "wall-clock run length in seconds (default 2)");
      app.add_flag("--compare", a->compare, "all four orders side by side");
      app.add_option("--out", a->out, "output directory")->capture_default_str();
      app.add_option("--ticks-per-sweep", a->ticks_per_sweep,
                     "deterministic: display intervals per sweep (mask density = 1/this)")->capture_default_str();
      app.add_option("--refresh", a->refresh, "display ticks per second")->capture_default_str();
      app.add_option("--coherence-seconds", a->coherence_seconds,
                     "deterministic: wall-clock seconds per order for samples/s")->capture_default_str();
      app.add_option("--seed", a->seed, "partition and sample seed")->capture_default_str();
      add_camera_flags(app, a->camera);
      app.footer(std::string("Scenes: ") + builtin_scene_help());
      return [a] { return run_stats(*a); };
    });

}  // namespace
}  // namespace frameless::cli
