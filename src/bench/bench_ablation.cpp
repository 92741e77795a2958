// `frameless bench ablation`: switches each skip of the per-sample path (and variance tracking,
// and adaptive sampling) off and on; reports the time each saves and proves the image unchanged:
// bit-identical where the skip is exact, within a stated tolerance otherwise. Text table + JSON.
#include "bench/bench_ablation.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <functional>
#include <stdexcept>
#include <memory>
#include <thread>
#include <vector>

#include <nlohmann/json.hpp>

#include "bench/bench_options.h"
#include "bench/bench_report.h"
#include "core/scene/scene_analysis.h"
#include "core/scene/scene_finalize.h"
#include "core/shading/parker_shaders.h"
#include "core/scenes/scene_variants.h"
#include "frameless/cpu_clock.h"
#include "frameless/engine.h"
#include "frameless/image_error.h"
#include "frameless/tile_render.h"

namespace frameless::bench {
namespace {

struct Row {
  std::string skip, scene, path_on, path_off, code_on, code_off, timing, check;
  double on = 0, off = 0;  // seconds (or seconds per sample) with the skip on / off
  double saved = 0;        // 1 - on / off
  bool exact = false;      // bit-identical images expected
  bool identical = false;  // images bit-identical
  double rmse = 0, tolerance = 0;
  bool pass = false;
};

void note(const std::string& what) {
  if (show_progress()) std::fprintf(stderr, "bench ablation: %s...\n", what.c_str());
}

// Compact form of a shading path for the table: L(ights) R(efraction) A(bsorption) H(ighlights).
std::string path_code(uint32_t path) {
  std::string s = "----";
  const char* letters = "LRAH";
  for (int b = 0; b < 4; ++b)
    if (path & (1u << b)) s[size_t(b)] = letters[b];
  return s;
}

// "model name" of the first CPU in /proc/cpuinfo (empty when unknown).
std::string cpu_model() {
  std::ifstream in("/proc/cpuinfo");
  for (std::string line; std::getline(in, line);)
    if (line.rfind("model name", 0) == 0) {
      const size_t colon = line.find(':');
      return colon == std::string::npos ? "" : line.substr(std::min(line.size(), colon + 2));
    }
  return "";
}

bool bit_identical(const std::vector<float>& a, const std::vector<float>& b) {
  return a.size() == b.size() && std::memcmp(a.data(), b.data(), a.size() * sizeof(float)) == 0;
}

// Renders `on` and `off` alternately, and which goes first alternates too (no order bias); the
// row gets each one's median CPU time, the images the last of each.
void alternate(int repeats, Row& r, std::vector<float>& img_on, std::vector<float>& img_off,
               const std::function<std::vector<float>(bool on, double& seconds)>& render) {
  std::vector<double> t_on, t_off;
  double t = 0;
  for (int k = 0; k < std::max(1, repeats); ++k)
    for (int j = 0; j < 2; ++j) {
      const bool on = (j == 0) == (k % 2 == 0);
      (on ? img_on : img_off) = render(on, t);
      (on ? t_on : t_off).push_back(t);
    }
  r.on = median(t_on);
  r.off = median(t_off);
}

// A per-sample skip: renders with `on` and `off` settings alternately, median CPU time of each.
Row per_sample_row(Scene& s, const std::string& skip, const std::function<void(SkipConfig&)>& off,
                   const AblationOptions& a, int w, int h, double tolerance) {
  note(skip);
  Row r;
  r.skip = skip;
  r.scene = s.name;
  r.timing = "1-thread CPU s per image";
  const SkipConfig on_cfg = s.settings.skips;
  SkipConfig off_cfg = on_cfg;
  off(off_cfg);
  r.path_on = describe_shade_path(shade_path(s.features, on_cfg));
  r.path_off = describe_shade_path(shade_path(s.features, off_cfg));
  r.code_on = path_code(shade_path(s.features, on_cfg));
  r.code_off = path_code(shade_path(s.features, off_cfg));
  std::vector<float> img_on, img_off;
  alternate(a.repeats, r, img_on, img_off, [&](bool on, double& t) {
    s.settings.skips = on ? on_cfg : off_cfg;
    return render_one_thread(s, w, h, a.spp, t);
  });
  s.settings.skips = on_cfg;
  r.exact = tolerance == 0;
  r.identical = bit_identical(img_on, img_off);
  r.rmse = image_error(img_on, img_off).rmse;
  r.tolerance = tolerance;
  r.pass = r.exact ? r.identical : r.rmse <= tolerance;
  r.check = r.exact ? "bit-identical" : "RMSE <= " + std::to_string(tolerance);
  return r;
}

// Parker's classes compiled (the kernel's switch) against the same classes through the plug-in
// interface (core/shading/parker_shaders.h): what the compiled dispatch saves, images within 1e-4.
Row interface_row(const AblationOptions& a, int w, int h) {
  note("parker classes compiled vs through the interface");
  auto compiled = load_scene_or_report(a.scene), routed = load_scene_or_report(a.scene);
  if (!compiled || !routed) throw std::runtime_error(a.scene + ": cannot load");
  Row r;
  r.skip = "interface";
  r.scene = compiled->name;
  r.timing = "1-thread CPU s per image";
  r.path_on = r.code_on = "compiled";
  r.path_off = r.code_off = "shader.h (" + std::to_string(route_through_interface(*routed)) + ")";
  finalize_scene(*routed);
  std::vector<float> img_on, img_off;
  alternate(a.repeats, r, img_on, img_off,
            [&](bool on, double& t) { return render_one_thread(on ? *compiled : *routed, w, h, a.spp, t); });
  r.identical = bit_identical(img_on, img_off);
  r.rmse = image_error(img_on, img_off).rmse;
  r.tolerance = 1e-4;
  r.pass = r.rmse <= r.tolerance;
  r.check = "RMSE <= 1e-4";
  return r;
}

// Mean image of a deterministic engine after `ticks` ticks (pixels never sampled are 0).
std::vector<float> engine_mean(Engine& e) {
  std::vector<float> out(size_t(3) * e.width() * e.height(), 0.0f);
  for (int y = 0; y < e.height(); ++y)
    for (int x = 0; x < e.width(); ++x) {
      PixelSnapshot p;
      if (e.read_pixel(x, y, p) && p.epoch != 0)
        for (int c = 0; c < 3; ++c) out[size_t(3 * (y * e.width() + x) + c)] = p.mean[c];
    }
  return out;
}

// Variance tracking: samples/s of the wall-clock engine with and without the Welford M2, and the
// deterministic engine's means bit-identical either way.
Row variance_row(const Scene& s, const EngineConfig& base, const AblationOptions& a) {
  note("variance tracking");
  Row r;
  r.skip = "variance";
  r.scene = s.name;
  r.timing = "engine s per M samples";
  r.path_on = r.code_on = "no M2";
  r.path_off = r.code_off = "M2";
  std::vector<double> t_on, t_off;
  for (int k = 0; k < std::max(1, a.repeats / 2); ++k)
    for (bool track : {false, true}) {
      EngineConfig c = base;
      c.track_variance = track;
      Engine e(s, c, s.camera);
      e.start();
      std::this_thread::sleep_for(std::chrono::duration<double>(0.2));
      const EngineStats s0 = e.stats();
      std::this_thread::sleep_for(std::chrono::duration<double>(a.seconds));
      const EngineStats s1 = e.stats();
      e.stop();
      const double per_msample = (s1.seconds - s0.seconds) / (1e-6 * double(s1.samples - s0.samples));
      (track ? t_off : t_on).push_back(per_msample);
    }
  r.on = median(t_on);
  r.off = median(t_off);
  std::vector<float> img[2];
  for (bool track : {false, true}) {
    EngineConfig c = base;
    c.deterministic = true;
    c.track_variance = track;
    Engine e(s, c, s.camera);
    for (int k = 0; k < 8; ++k) e.advance(0.01);
    img[track] = engine_mean(e);
  }
  r.exact = true;
  r.identical = bit_identical(img[0], img[1]);
  r.rmse = image_error(img[0], img[1]).rmse;
  r.pass = r.identical;
  r.check = "bit-identical";
  return r;
}

struct AdaptiveFigures {
  double target_rmse = 0;
  double plain_samples = 0, adaptive_samples = 0;  // samples to reach the target
  double plain_seconds = 0, adaptive_seconds = 0;  // wall seconds to reach it
  double plain_final = 0, adaptive_final = 0;      // RMSE after the same sample budget
  uint64_t budget = 0;
};

// Adaptive vs plain at equal sample budgets (deterministic engine, `ticks` ticks of a quarter
// sweep each) against a converged reference: RMSE after each tick, and samples and wall seconds
// to reach the plain run's final RMSE.
AdaptiveFigures adaptive_figures(const Scene& s, const EngineConfig& base, int ticks,
                                 const std::vector<float>& reference) {
  AdaptiveFigures f;
  std::vector<double> curve[2], samples[2], seconds[2];
  for (int adaptive = 0; adaptive < 2; ++adaptive) {
    EngineConfig c = base;
    c.deterministic = true;
    c.adaptive.enabled = adaptive;
    c.samples_per_tick = uint64_t(c.width) * c.height * 2 / 4;
    Engine e(s, c, s.camera);
    double wall = 0;
    for (int k = 0; k < ticks; ++k) {
      const auto t0 = std::chrono::steady_clock::now();
      e.advance(0.01);
      wall += std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
      curve[adaptive].push_back(image_error(engine_mean(e), reference).rmse);
      samples[adaptive].push_back(double(e.stats().samples));
      seconds[adaptive].push_back(wall);
    }
  }
  f.budget = uint64_t(samples[0].back());
  f.plain_final = curve[0].back();
  f.adaptive_final = curve[1].back();
  f.target_rmse = f.plain_final;
  for (int adaptive = 0; adaptive < 2; ++adaptive)
    for (size_t k = 0; k < curve[adaptive].size(); ++k)
      if (curve[adaptive][k] <= f.target_rmse) {
        (adaptive ? f.adaptive_samples : f.plain_samples) = samples[adaptive][k];
        (adaptive ? f.adaptive_seconds : f.plain_seconds) = seconds[adaptive][k];
        break;
      }
  return f;
}

// A loop whose values decay into the subnormal range, timed with and without FTZ/DAZ.
double denormal_loop_seconds(bool ftz) {
  double seconds = 0;
  std::thread t([&] {
    if (ftz) enable_flush_to_zero();
    volatile float sink = 0;
    volatile float tiny_in = 1e-40f;  // subnormal; volatile so the loop is not folded
    const float tiny = tiny_in;
    const double t0 = thread_cpu_seconds();
    for (int rep = 0; rep < 20000; ++rep) {
      float x[64];
      for (int i = 0; i < 64; ++i) x[i] = 1e-38f * float(i + 1);
      // Converges to 2e-40 and stays subnormal; with DAZ `tiny` reads as 0 and x flushes to 0.
      for (int step = 0; step < 200; ++step)
        for (int i = 0; i < 64; ++i) x[i] = x[i] * 0.5f + tiny;
      float sum = 0;
      for (int i = 0; i < 64; ++i) sum += x[i];
      sink = sink + sum;
    }
    seconds = thread_cpu_seconds() - t0;
  });
  t.join();
  return seconds;
}

void print_table(FILE* out, const nlohmann::json& j, const std::vector<Row>& rows,
                 const AdaptiveFigures& af) {
  std::fprintf(out, "ablation: scene %s, %s, %d spp per timed image, %d threads for the engine\n",
               j["scene"].get<std::string>().c_str(), j["size"].get<std::string>().c_str(),
               j["spp"].get<int>(), j["threads"].get<int>());
  std::fprintf(out, "%-11s %-22s %-14s %9s %9s %7s  %s\n", "skip", "scene", "path on->off",
               "on", "off", "saved", "image check");
  for (const Row& r : rows)
    std::fprintf(out, "%-11s %-22s %-14s %9.4f %9.4f %6.1f%%  %s: %s (RMSE %.2e)\n",
                 r.skip.c_str(), r.scene.c_str(), (r.code_on + "->" + r.code_off).c_str(), r.on,
                 r.off, 100.0 * r.saved, r.check.c_str(), r.pass ? "pass" : "FAIL", r.rmse);
  std::fprintf(out, "paths: L lights, R refraction, A absorption, H highlights compiled in, E the black "
                    "environment sampled (path tracing); timings: "
                    "per-sample rows in 1-thread CPU seconds per image (median), variance in engine "
                    "seconds per million samples, adaptive in deterministic-engine seconds to reach plain's "
                    "final RMSE\n");
  std::fprintf(out,
               "adaptive vs plain (deterministic, equal budget of %llu samples): RMSE %.5f vs %.5f; "
               "to reach RMSE %.5f: %.0f vs %.0f samples, %.3f vs %.3f s\n",
               (unsigned long long)af.budget, af.adaptive_final, af.plain_final, af.target_rmse,
               af.adaptive_samples, af.plain_samples, af.adaptive_seconds, af.plain_seconds);
  std::fprintf(out, "denormal loop: %.4f s without FTZ/DAZ, %.4f s with (x%.1f)\n",
               j["denormal_loop"]["seconds_without_ftz"].get<double>(),
               j["denormal_loop"]["seconds_with_ftz"].get<double>(),
               j["denormal_loop"]["slowdown_without_ftz"].get<double>());
}

}  // namespace

int run_ablation(const AblationOptions& a) {
  std::string error;
  int w = 0, h = 0;
  if (!parse_size(a.size, w, h, error)) return report_error(error);
  if (!valid_threads(a.threads, error)) return report_error(error);
  if (a.spp < 1 || a.spp > 4096) return report_error("--spp: must be 1..4096");
  if (a.repeats < 1 || a.repeats > 100) return report_error("--repeats: must be 1..100");
  if (!(a.seconds > 0 && a.seconds <= 600)) return report_error("--seconds: must be in (0, 600]");
  if (!a.out.empty()) {
    std::error_code ec;
    std::filesystem::create_directories(a.out, ec);
    if (ec) return report_error("--out: cannot create '" + a.out + "': " + ec.message());
  }
  auto base = load_scene_or_report(a.scene);
  auto no_lights = load_scene_or_report(a.scene);
  auto no_dielectric = load_scene_or_report(a.scene);
  auto no_highlights = load_scene_or_report(a.scene);
  // Path tracing with no emitter and a black background: nothing to sample but Parker's lights.
  auto dark_path = load_scene_or_report(a.scene);
  if (!base || !no_lights || !no_dielectric || !no_highlights || !dark_path) return 2;
  dark_path->settings.integrator = Integrator::kPath;
  dark_path->settings.background = Vec3(0.0f);
  const bool dark = dark_path->emitters.empty() && !dark_path->environment;
  apply_scene_variant(*no_lights, "no-lights");
  apply_scene_variant(*no_dielectric, "no-dielectric");
  apply_scene_variant(*no_highlights, "no-highlights");
  EngineConfig ec;
  ec.width = w;
  ec.height = h;
  ec.threads = a.threads > 0 ? a.threads : hardware_threads();

  std::vector<Row> rows;
  AdaptiveFigures af;
  nlohmann::json j;
  try {
    // Pruning is bounded, not exact: RMSE 2e-3 (tests/core/skip_test.cpp states the bound).
    rows.push_back(per_sample_row(*no_lights, "shadows", [](SkipConfig& k) { k.shadows = false; }, a, w, h, 0));
    rows.push_back(per_sample_row(*no_dielectric, "refraction", [](SkipConfig& k) { k.refraction = false; }, a, w, h, 0));
    rows.push_back(per_sample_row(*no_highlights, "highlights", [](SkipConfig& k) { k.highlights = false; }, a, w, h, 0));
    rows.push_back(per_sample_row(*base, "any-hit", [](SkipConfig& k) { k.any_hit = false; }, a, w, h, 0));
    rows.push_back(per_sample_row(*base, "prune", [](SkipConfig& k) { k.prune = false; }, a, w, h, 2e-3));
    rows.push_back(per_sample_row(*no_lights, "all", [](SkipConfig& k) { k = {false, false, false, false, false, false}; }, a, w, h, 2e-3));
    if (dark) {
      Row r = per_sample_row(*dark_path, "emitters", [](SkipConfig& k) { k.emitters = false; }, a, w, h, 0);
      r.scene += "/path-dark";  // path tracing, black background, no emitters
      r.path_on = "no emitter or environment sampling";
      r.path_off = "the black environment sampled (shadow rays)";
      r.code_on = "----";
      r.code_off = "E";
      rows.push_back(r);
    }
    rows.push_back(variance_row(*base, ec, a));
    rows.push_back(interface_row(a, w, h));
    for (Row& r : rows) r.saved = r.off > 0 ? 1.0 - r.on / r.off : 0.0;

    note("adaptive vs plain (reference at 64 spp)");
    TileRenderOptions ro;
    ro.spp = 64;
    ro.threads = ec.threads;
    ro.first_sample = 1u << 20;  // independent of the engine's samples
    const std::vector<float> reference = render_tiles(*base, make_camera_basis(base->camera, w, h), ro).rgb;
    af = adaptive_figures(*base, ec, 64, reference);
    {
      // Adaptive changes which samples are taken, so the image differs by noise: it passes when,
      // at an equal sample budget, it is no farther from the converged reference than plain.
      Row r;
      r.skip = "adaptive";
      r.scene = base->name;
      r.timing = "engine s to plain's final RMSE";
      r.path_on = r.code_on = "adaptive";
      r.path_off = r.code_off = "plain";
      r.on = af.adaptive_seconds;
      r.off = af.plain_seconds;
      r.saved = r.off > 0 ? 1.0 - r.on / r.off : 0.0;
      r.rmse = af.adaptive_final;
      r.tolerance = af.plain_final;
      r.pass = af.adaptive_final <= af.plain_final;
      r.check = "RMSE vs reference <= plain's";
      rows.push_back(r);
    }
    note("denormal loop");
    const double dn_off = denormal_loop_seconds(false), dn_on = denormal_loop_seconds(true);

    j["scene"] = a.scene;
    j["size"] = a.size;
    j["spp"] = a.spp;
    j["repeats"] = a.repeats;
    j["threads"] = ec.threads;
    j["hardware_threads"] = hardware_threads();
    j["build"] = "Release -O3 -march=native";
    j["cpu"] = cpu_model();
    for (const Row& r : rows)
      j["skips"].push_back({{"skip", r.skip}, {"scene", r.scene}, {"path_on", r.path_on},
                            {"path_off", r.path_off}, {"timing", r.timing}, {"on", r.on},
                            {"off", r.off}, {"saved_fraction", r.saved}, {"check", r.check},
                            {"bit_identical", r.identical}, {"rmse", r.rmse},
                            {"tolerance", r.tolerance}, {"pass", r.pass}});
    j["adaptive"] = {{"budget_samples", af.budget},
                     {"rmse_plain", af.plain_final},
                     {"rmse_adaptive", af.adaptive_final},
                     {"target_rmse", af.target_rmse},
                     {"samples_to_target_plain", af.plain_samples},
                     {"samples_to_target_adaptive", af.adaptive_samples},
                     {"seconds_to_target_plain", af.plain_seconds},
                     {"seconds_to_target_adaptive", af.adaptive_seconds},
                     {"reference_spp", 64},
                     {"settings", {{"min_samples", ec.adaptive.min_samples},
                                   {"rel_error", ec.adaptive.rel_error},
                                   {"abs_error", ec.adaptive.abs_error},
                                   {"max_skips", ec.adaptive.max_skips}}}};
    j["denormal_loop"] = {{"seconds_without_ftz", dn_off},
                          {"seconds_with_ftz", dn_on},
                          {"slowdown_without_ftz", dn_on > 0 ? dn_off / dn_on : 0.0}};
  } catch (const std::exception& ex) {
    return report_error(ex.what());
  }
  if (a.json)
    std::printf("%s\n", j.dump(2).c_str());
  else
    print_table(stdout, j, rows, af);
  if (!a.out.empty()) {
    std::ofstream(a.out + "/ablation.json") << j.dump(2) << "\n";
    FILE* f = std::fopen((a.out + "/ablation.txt").c_str(), "w");
    if (!f) return report_error("--out: cannot write " + a.out + "/ablation.txt");
    print_table(f, j, rows, af);
    std::fclose(f);
  }
  for (const Row& r : rows)
    if (!r.pass) return 1;
  return 0;
}

}  // namespace frameless::bench
