// `frameless bench gi`: the path tracer's error over wall time in the real Engine + DisplayThread
// against its converged reference; Blender's Cycles on the same scene at 16/64/256 spp (its own
// render times); the two converged images compared.
#include "bench/bench_gi.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <memory>

#include "bench/bench_live.h"
#include "bench/bench_report.h"
#include "bench/cycles_peer.h"
#include "core/scene/scene_analysis.h"
#include "core/scene/scene_build.h"
#include "core/scenes/scene_load.h"
#include "core/shading/irradiance_bake.h"
#include "display/png_io.h"
#include "frameless/reference_cache.h"
#include "frameless/tile_render.h"

namespace frameless::bench {
namespace {

double mse(const std::vector<float>& a, const std::vector<float>& b) {
  double s = 0;
  for (size_t i = 0; i < a.size(); ++i) s += double(a[i] - b[i]) * double(a[i] - b[i]);
  return a.empty() ? 0.0 : s / double(a.size());
}

// Per-channel means of an RGB image.
std::vector<double> channel_means(const std::vector<float>& rgb) {
  std::vector<double> m(3, 0.0);
  for (size_t i = 0; i < rgb.size(); ++i) m[i % 3] += rgb[i];
  for (double& v : m) v /= double(rgb.size() / 3);
  return m;
}

// Box-filters an RGB image over k x k blocks (the noise left in converged images averages out).
std::vector<float> box_filter(const std::vector<float>& rgb, int w, int h, int k) {
  const int bw = w / k, bh = h / k;
  std::vector<float> out(size_t(bw) * bh * 3, 0.0f);
  for (int y = 0; y < bh * k; ++y)
    for (int x = 0; x < bw * k; ++x)
      for (int c = 0; c < 3; ++c)
        out[(size_t(y / k) * bw + x / k) * 3 + c] += rgb[(size_t(y) * w + x) * 3 + c] / float(k * k);
  return out;
}

// RMSE of the frameless display at wall time t: the newest tick at or before t.
const TickRecord* tick_at(const std::vector<TickRecord>& ticks, double t) {
  const TickRecord* r = nullptr;
  for (const TickRecord& k : ticks)
    if (k.t <= t && k.samples > 0) r = &k;
  return r;
}

}  // namespace

int run_gi(const GiOptions& options) {
  GiOptions a = options;
  std::string error;
  if (a.quick) {
    a.size = "64x64";
    a.ref_spp = 512;
    a.spp = {4, 16};
  }
  int width = 0, height = 0;
  if (!parse_size(a.size, width, height, error)) return report_error(error);
  if (!valid_threads(a.threads, error)) return report_error(error);
  if (a.ref_spp < 2 || a.ref_spp > 1 << 20) return report_error("--ref-spp: must be in [2, 1048576]");
  for (int n : a.spp)
    if (n < 1 || n > 65536) return report_error("--spp: each must be in [1, 65536]");
  if (a.spp.empty()) return report_error("--spp: give at least one sample count");
  std::sort(a.spp.begin(), a.spp.end());
  if (!(a.seconds >= 0 && a.seconds <= 3600)) return report_error("--seconds: must be in [0, 3600]");
  if (!prepare_out_dir(a.out, error)) return report_error(error);
  if (a.shadows.integrator.empty()) a.shadows.integrator = "path";
  std::unique_ptr<Scene> scene = load_scene_or_report(a.scene, &a.shadows);
  if (!scene) return 2;
  const int threads = a.threads > 0 ? a.threads : hardware_threads();
  const std::string cache = a.cache.empty() ? default_reference_cache_dir(a.out) : a.cache;
  const size_t pixels = size_t(width) * size_t(height);
  scene->settings.width = width;
  scene->settings.height = height;

  try {
    nlohmann::json settings = {{"size", a.size},       {"threads", threads},
                               {"reference_spp", a.ref_spp}, {"cycles_spp", a.spp},
                               {"quick", a.quick},     {"integrator", integrator_name(scene->settings.integrator)},
                               {"clock", "wall (real Engine + DisplayThread); Cycles: its own render time"}};
    nlohmann::json j = bench_header("gi", scene.get(), a.scene, settings);

    bench_progress("gi", "reference (" + std::to_string(a.ref_spp) + " spp, cached in " + cache + ")");
    ReferenceSpec rs;
    rs.scene_id = scene_identity(a.scene) + ";integrator=" + integrator_name(scene->settings.integrator);
    rs.code_version = code_version(*scene);
    rs.camera = scene->camera;
    rs.width = width;
    rs.height = height;
    rs.spp = a.ref_spp;
    auto ref = load_or_render_reference(*scene, rs, cache, threads);
    if (!ref.ok()) return report_error(ref.error().message);
    const double ref_mean = (channel_means(ref->rgb)[0] + channel_means(ref->rgb)[1] + channel_means(ref->rgb)[2]) / 3;
    j["reference"] = {{"spp", a.ref_spp},
                      {"noise_rmse", std::sqrt(ref->noise_mse)},
                      {"from_cache", ref->from_cache},
                      {"seconds", ref->seconds},
                      {"mean", ref_mean}};
    std::string werr;
    if (auto w = write_png(a.out + "/path_reference.png", width, height, ref->rgb.data()); !w)
      return report_error(w.error().message);

    // Cycles: converged image, then the timed sample counts.
    const std::string blender = a.no_cycles ? "" : find_blender();
    const std::string unsupported = cycles_unsupported(*scene);
    std::vector<double> cycles_t, cycles_rmse;
    nlohmann::json cj;
    if (a.no_cycles) {
      cj["skipped"] = "--no-cycles";
    } else if (blender.empty()) {
      cj["skipped"] = "blender not found: apt-get install blender (tools/install-deps.sh --bench)";
    } else if (!unsupported.empty()) {
      cj["skipped"] = unsupported;
    } else {
      bench_progress("gi", "Cycles reference (" + std::to_string(a.ref_spp) + " spp)");
      auto conv = render_with_cycles(blender, *scene, width, height, a.ref_spp, threads, 1, a.out);
      if (!conv) return report_error(conv.error().message);
      if (auto w = write_png(a.out + "/cycles_reference.png", width, height, conv->rgb.data()); !w)
        return report_error(w.error().message);
      const std::vector<double> mf = channel_means(ref->rgb), mc = channel_means(conv->rgb);
      nlohmann::json agree;
      double worst_mean = 0;
      for (int c = 0; c < 3; ++c) worst_mean = std::max(worst_mean, std::abs(mc[c] / mf[c] - 1.0));
      const std::vector<float> bf = box_filter(ref->rgb, width, height, 4), bc = box_filter(conv->rgb, width, height, 4);
      agree["mean_frameless"] = mf;
      agree["mean_cycles"] = mc;
      agree["worst_channel_mean_difference"] = worst_mean;
      agree["box4_rmse_over_mean"] = std::sqrt(mse(bf, bc)) / ref_mean;
      agree["goal"] = "means within 1 % per channel; 4x4-box RMSE under 1 % of the mean";
      cj["version"] = conv->version;
      cj["reference_seconds"] = conv->seconds;
      cj["agreement"] = agree;
      // The Cycles reference's own noise, from its 1/n scaling at the smallest count below.
      nlohmann::json points = nlohmann::json::array();
      double noise_mse_ref = 0;
      for (size_t k = 0; k < a.spp.size(); ++k) {
        const int n = a.spp[k];
        bench_progress("gi", "Cycles at " + std::to_string(n) + " spp");
        auto r = render_with_cycles(blender, *scene, width, height, n, threads, 2 + int(k), a.out);
        if (!r) return report_error(r.error().message);
        const double m = mse(r->rgb, conv->rgb);
        if (k == 0) noise_mse_ref = m * double(n) / double(a.ref_spp);
        const double debiased = std::sqrt(std::max(0.0, m - noise_mse_ref));
        cycles_t.push_back(r->seconds);
        cycles_rmse.push_back(debiased);
        points.push_back({{"spp", n}, {"seconds", r->seconds}, {"rmse", std::sqrt(m)},
                          {"rmse_debiased", debiased},
                          {"rmse_vs_frameless_reference", std::sqrt(mse(r->rgb, ref->rgb))}});
      }
      cj["points"] = points;
      cj["reference_noise_rmse_estimate"] = std::sqrt(noise_mse_ref);
    }
    j["cycles"] = cj;

    // Frameless, path then igi: the live engine and display for as long as Cycles took at its
    // largest count, read at Cycles' times; one-shot renders at Cycles' sample counts.
    const double run_s = !cycles_t.empty() ? std::max(1.0, cycles_t.back() * 1.15)
                                           : (a.seconds > 0 ? a.seconds : 10.0);
    LiveSchedule sched;
    sched.poses = {scene->camera};
    sched.references = {&ref->rgb};
    sched.noise_mse = {ref->noise_mse};
    sched.duration = run_s;
    ShadowOptions igi_options = a.shadows;
    igi_options.integrator = "igi";
    std::unique_ptr<Scene> igi_scene = load_scene_or_report(a.scene, &igi_options);
    if (!igi_scene) return 2;
    igi_scene->settings.width = width;
    igi_scene->settings.height = height;
    struct Run {
      const char* name;
      const Scene* scene;
      bool denoise;
      bool discontinuity;  // igi: OpenRT's discontinuity buffer on the display (the default)
    };
    const Run runs[] = {{"path", scene.get(), false, true},
                        {"path_denoise", scene.get(), true, true},
                        {"igi", igi_scene.get(), false, true},
                        {"igi_no_discontinuity", igi_scene.get(), false, false}};
    std::string dat;
    for (const auto& [name, sc, denoise, discontinuity] : runs) {
      LiveMode fl;
      fl.name = fl.kind = name;
      fl.engine.width = width;
      fl.engine.height = height;
      fl.engine.threads = threads;
      fl.display.blend.denoise = denoise;
      fl.display.blend.discontinuity = discontinuity;
      fl.engine.track_variance = denoise;
      bench_progress("gi", std::string("frameless ") + name + " for " + csv_number(run_s) + " s");
      const LiveResult live = run_live(*sc, fl, sched);
      nlohmann::json fj;
      fj["samples_per_s"] = live.samples_per_s;
      fj["ticks"] = live.ticks.size();
      fj["dropped_samples"] = live.dropped;
      fj["display_cpu_share"] = live.seconds > 0 ? live.display_cpu_seconds / live.seconds : 0.0;
      dat += std::string("# frameless ") + name + ": t rmse_debiased spp\n";
      for (const TickRecord& t : live.ticks)
        if (t.samples > 0)
          dat += csv_number(t.t) + " " + csv_number(t.rmse_debiased) + " " +
                 csv_number(double(t.samples) / double(pixels)) + "\n";
      dat += "\n\n";
      nlohmann::json cmp = nlohmann::json::array();
      for (size_t k = 0; k < cycles_t.size(); ++k) {
        const TickRecord* t = tick_at(live.ticks, cycles_t[k]);
        nlohmann::json c = {{"cycles_spp", a.spp[k]}, {"seconds", cycles_t[k]}, {"cycles_rmse", cycles_rmse[k]}};
        if (t) {
          c["frameless_rmse"] = t->rmse_debiased;
          c["frameless_spp"] = double(t->samples) / double(pixels);
          c["ratio"] = cycles_rmse[k] > 0 ? t->rmse_debiased / cycles_rmse[k] : 0.0;
        }
        cmp.push_back(c);
      }
      fj["at_cycles_times"] = cmp;
      nlohmann::json at = nlohmann::json::object();  // at fixed times, for runs without Cycles
      for (double tt : {0.25, 1.0, 4.0})
        if (const TickRecord* t = tick_at(live.ticks, tt); t && tt <= run_s) at[csv_number(tt)] = t->rmse_debiased;
      fj["rmse_at_seconds"] = at;
      if (!live.ticks.empty()) {
        const TickRecord& last = live.ticks.back();
        fj["final"] = {{"t_s", last.t}, {"rmse_debiased", last.rmse_debiased},
                       {"samples_per_pixel", double(last.samples) / double(pixels)}};
      }
      nlohmann::json shots = nlohmann::json::array();
      // The display's filters act on live runs only: one-shot renders would repeat a row.
      for (int n : denoise || !discontinuity ? std::vector<int>{} : a.spp) {
        TileRenderOptions o;
        o.spp = n;
        o.threads = threads;
        o.first_sample = 2u * uint32_t(a.ref_spp);  // indices the reference never used, net-aligned
        const RenderedImage img = render_tiles(*sc, make_camera_basis(sc->camera, width, height), o);
        const double m = std::max(0.0, mse(img.rgb, ref->rgb) - ref->noise_mse);
        shots.push_back({{"spp", n}, {"seconds", img.seconds}, {"rmse_debiased", std::sqrt(m)}});
      }
      fj["one_shot"] = shots;
      j["frameless"][name] = fj;
    }
    // The display filters' cost at 1280x720 (path plain and --denoise, igi with its discontinuity
    // buffer; 3 s each;
    // both score every image against a black reference, so the difference is the filter's).
    if (!a.quick) {
      const std::vector<float> black(size_t(1280) * 720 * 3, 0.0f);
      LiveSchedule big;
      big.poses = {scene->camera};
      big.references = {&black};
      big.noise_mse = {0.0};
      big.duration = 3.0;
      nlohmann::json cost;
      for (const char* kind : {"plain", "denoise", "igi_discontinuity"}) {
        const bool denoise = std::string(kind) == "denoise", igi = std::string(kind) == "igi_discontinuity";
        LiveMode m;
        m.name = m.kind = kind;
        m.engine.width = 1280;
        m.engine.height = 720;
        m.engine.threads = threads;
        m.display.blend.denoise = denoise;
        m.engine.track_variance = denoise;
        bench_progress("gi", std::string("display cost at 1280x720, ") + m.name);
        const LiveResult r = run_live(igi ? *igi_scene : *scene, m, big);
        cost[m.name] = {{"display_cpu_share", r.seconds > 0 ? r.display_cpu_seconds / r.seconds : 0.0},
                        {"ticks", r.ticks.size()},
                        {"ms_per_tick", r.ticks.empty() ? 0.0 : 1e3 * r.display_cpu_seconds / double(r.ticks.size())}};
      }
      j["denoise_cost_1280x720"] = cost;
    }
    // Parker's ambient against the path-traced reference: the Whitted integrator with the
    // irradiance volume the path tracer bakes, and with the default hemisphere ambient.
    {
      nlohmann::json amb;
      for (const char* kind : {"irradiance_volume", "hemisphere"}) {
        ShadowOptions wo = a.shadows;
        wo.integrator = "whitted";
        std::unique_ptr<Scene> ws = load_scene_or_report(a.scene, &wo);
        if (!ws) return 2;
        double bake = 0.0;
        if (std::string(kind) == "irradiance_volume") {
          ws->ambient = Ambient{};
          ws->ambient.kind = AmbientKind::kIrradianceVolume;
          bench_progress("gi", "baking the irradiance volume");
          bake = bake_irradiance_volume(*ws);
        } else {
          ws->ambient = default_hemisphere_ambient();
        }
        ws->features = analyse_scene(*ws);
        TileRenderOptions o;
        o.spp = 16;
        o.threads = threads;
        const RenderedImage img = render_tiles(*ws, make_camera_basis(ws->camera, width, height), o);
        const double m = std::max(0.0, mse(img.rgb, ref->rgb) - ref->noise_mse);
        amb[kind] = {{"rmse", std::sqrt(m)}, {"bake_seconds", bake}, {"render_seconds_16spp", img.seconds}};
        if (std::string(kind) == "irradiance_volume") {
          const IrradianceVolume& v = *ws->ambient.volume;
          amb[kind]["grid"] = {v.nx, v.ny, v.nz};
          amb[kind]["paths_per_vertex"] = ws->ambient.volume_samples;
          if (auto w = write_png(a.out + "/whitted_irradiance_volume.png", width, height, img.rgb.data()); !w)
            return report_error(w.error().message);
        }
      }
      j["whitted_ambient_vs_path"] = amb;
    }
    dat += "# Cycles: t rmse_debiased spp\n";
    for (size_t k = 0; k < cycles_t.size(); ++k)
      dat += csv_number(cycles_t[k]) + " " + csv_number(cycles_rmse[k]) + " " + std::to_string(a.spp[k]) + "\n";
    if (!write_text_atomic(a.out + "/gi.dat", dat, error)) return report_error(error);
    std::string body = "set logscale xy\nset grid\nset key top right\nset format y '%g'\nset format x '%g'\n";
    body += "set title 'Cornell box: RMSE against the converged reference vs wall time (" +
            std::to_string(threads) + " threads)'\n";
    body += "set xlabel 'seconds'\nset ylabel 'RMSE (reference noise removed)'\n";
    body += "plot '" + a.out + "/gi.dat' index 0 using 1:2 with lines lw 2 title 'frameless path'";
    body += ", '" + a.out + "/gi.dat' index 1 using 1:2 with lines lw 2 title 'frameless path --denoise'";
    body += ", '" + a.out + "/gi.dat' index 2 using 1:2 with lines lw 2 title 'frameless igi'";
    body += ", '" + a.out + "/gi.dat' index 3 using 1:2 with lines lw 1 dt 2 title 'frameless igi --no-discontinuity'";
    if (!cycles_t.empty())
      body += ", '" + a.out + "/gi.dat' index 4 using 1:2 with linespoints lw 2 pt 7 title 'Cycles " +
              gnuplot_text(cj.value("version", "")) + "'";
    bool png = false;
    if (!plot_png(a.out, "gi", 800, 500, body, error, &png)) return report_error(error);
    j["outputs"] = {{"plot", png ? "gi.png" : ""}, {"data", "gi.dat"}};
    if (!write_json(a.out + "/gi.json", j, error)) return report_error(error);

    std::printf("bench gi: %s %dx%d, %d threads\n", a.scene.c_str(), width, height, threads);
    if (cj.contains("skipped")) {
      std::printf("  Cycles: skipped (%s)\n", cj["skipped"].get<std::string>().c_str());
    } else {
      const auto& ag = cj["agreement"];
      std::printf("  Cycles %s agreement: worst channel mean %.2f %%, 4x4-box RMSE %.2f %% of the mean\n",
                  cj["version"].get<std::string>().c_str(),
                  100 * ag["worst_channel_mean_difference"].get<double>(),
                  100 * ag["box4_rmse_over_mean"].get<double>());
    }
    for (const auto& [name, fj] : j["frameless"].items()) {
      std::printf("  frameless %s: %.3g M samples/s\n", name.c_str(), fj["samples_per_s"].get<double>() / 1e6);
      for (const auto& sh : fj["one_shot"])
        std::printf("    render %4d spp: %7.3f s, RMSE %.4f\n", sh["spp"].get<int>(),
                    sh["seconds"].get<double>(), sh["rmse_debiased"].get<double>());
      for (const auto& c : fj["at_cycles_times"])
        std::printf("    at Cycles' %4d spp time %7.3f s: Cycles RMSE %.4f, frameless %.4f (%.2fx)\n",
                    c["cycles_spp"].get<int>(), c["seconds"].get<double>(), c["cycles_rmse"].get<double>(),
                    c.value("frameless_rmse", 0.0), c.value("ratio", 0.0));
      for (const auto& [t, r] : fj["rmse_at_seconds"].items())
        std::printf("    display RMSE at %s s: %.4f\n", t.c_str(), r.get<double>());
      std::printf("    display thread: %.0f %% of a core\n", 100 * fj["display_cpu_share"].get<double>());
    }
    for (const auto& [kind, v] : j["whitted_ambient_vs_path"].items())
      std::printf("  Whitted with %s ambient: RMSE %.4f against the path tracer (bake %.2f s)\n", kind.c_str(),
                  v["rmse"].get<double>(), v["bake_seconds"].get<double>());
    if (j.contains("denoise_cost_1280x720")) {
      const auto& c = j["denoise_cost_1280x720"];
      std::printf("  display at 1280x720: %.1f ms per tick plain, %.1f ms with --denoise, %.1f ms igi with its "
                  "discontinuity buffer\n",
                  c["plain"]["ms_per_tick"].get<double>(), c["denoise"]["ms_per_tick"].get<double>(),
                  c["igi_discontinuity"]["ms_per_tick"].get<double>());
    }
    std::printf("  wrote %s/gi.json\n", a.out.c_str());
  } catch (const std::exception& ex) {
    return report_error(ex.what());
  }
  return 0;
}

}  // namespace frameless::bench
