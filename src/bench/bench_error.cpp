// `frameless bench error`: static convergence. The real Engine + DisplayThread run on the wall
// clock with a still camera; every displayed image is scored (RMSE, relative MSE) against a
// converged, cached reference, for frameless, conventional and adaptive modes on the same threads.
#include "bench/bench_error.h"

#include <cmath>
#include <cstdio>
#include <memory>

#include "bench/bench_live.h"
#include "bench/bench_options.h"
#include "bench/bench_report.h"
#include "core/scenes/scene_load.h"
#include "frameless/reference_cache.h"

namespace frameless::bench {
namespace {

// Seconds until the RMSE first falls to `level` (and stays below it for the next tick); NaN if
// never.
double time_to(const std::vector<TickRecord>& ticks, double level, bool samples_axis,
               size_t pixels) {
  for (size_t i = 0; i + 1 < ticks.size(); ++i)
    if (ticks[i].rmse <= level && ticks[i + 1].rmse <= level)
      return samples_axis ? double(ticks[i].samples) / double(pixels) : ticks[i].t;
  return std::nan("");
}

}  // namespace

int run_error(const ErrorOptions& options) {
  ErrorOptions a = options;
  std::string error;
  if (a.quick) {
    a.size = "160x120";
    a.seconds = 3;
    a.ref_spp = 64;
  }
  int width = 0, height = 0;
  if (!parse_size(a.size, width, height, error)) return report_error(error);
  if (!valid_threads(a.threads, error)) return report_error(error);
  if (!(a.seconds > 0 && a.seconds <= 3600)) return report_error("--seconds: must be in (0, 3600]");
  if (!(a.refresh >= 1 && a.refresh <= 240)) return report_error("--refresh: must be in [1, 240]");
  if (!(a.alpha > 0 && a.alpha <= 1)) return report_error("--alpha: must be in (0, 1]");
  if (a.ref_spp < 2 || a.ref_spp > 1 << 20)
    return report_error("--ref-spp: must be in [2, 1048576]");
  if (!prepare_out_dir(a.out, error)) return report_error(error);
  std::unique_ptr<Scene> scene = load_scene_or_report(a.scene, &a.shadows);
  if (!scene) return 2;
  const int threads = a.threads > 0 ? a.threads : hardware_threads();
  const std::string cache = a.cache.empty() ? default_reference_cache_dir(a.out) : a.cache;
  const size_t pixels = size_t(width) * size_t(height);

  try {
    bench_progress("error",
                   "reference (" + std::to_string(a.ref_spp) + " spp, cached in " + cache + ")");
    ReferenceSpec rs;
    rs.scene_id = scene_identity(a.scene);
    rs.code_version = code_version(*scene);
    rs.camera = scene->camera;
    rs.width = width;
    rs.height = height;
    rs.spp = a.ref_spp;
    auto ref = load_or_render_reference(*scene, rs, cache, threads);
    if (!ref.ok()) return report_error(ref.error().message);

    LiveSchedule sched;
    sched.poses = {scene->camera};
    sched.references = {&ref->rgb};
    sched.noise_mse = {ref->noise_mse};
    sched.duration = a.seconds;

    std::vector<LiveMode> modes;
    LiveMode base;
    base.engine.width = width;
    base.engine.height = height;
    base.engine.threads = threads;
    base.display.refresh_hz = a.refresh;
    base.display.blend.alpha = float(a.alpha);
    LiveMode fl = base;
    fl.name = fl.kind = "frameless";
    modes.push_back(fl);
    // The motion settings (reprojection, temporal weights, closed loop): a still camera must
    // converge no slower with them.
    LiveMode fm = base;
    fm.name = fm.kind = "frameless_motion";
    fm.display.blend.reproject = fm.display.blend.temporal = true;
    fm.engine.closed_loop = true;
    modes.push_back(fm);
    LiveMode cv = base;
    cv.name = cv.kind = "conventional";
    cv.engine.mode = RenderMode::conventional;
    modes.push_back(cv);
    LiveMode ad = base;
    ad.name = ad.kind = "adaptive";
    ad.engine.adaptive.enabled = true;
    modes.push_back(ad);

    nlohmann::json settings = {{"size", a.size},
                               {"threads", threads},
                               {"seconds", a.seconds},
                               {"refresh_hz", a.refresh},
                               {"alpha", a.alpha},
                               {"update_percent", base.engine.update_percent},
                               {"reference_spp", a.ref_spp},
                               {"quick", a.quick},
                               {"clock", "wall (real Engine + DisplayThread)"}};
    nlohmann::json j = bench_header("error", scene.get(), a.scene, settings);
    j["reference"] = {{"spp", a.ref_spp},
                      {"noise_rmse", std::sqrt(ref->noise_mse)},
                      {"from_cache", ref->from_cache},
                      {"seconds", ref->seconds},
                      {"file", ref->path},
                      {"key", reference_key_hash(rs)}};
    const std::vector<double> levels = {0.05, 0.02, 0.01, 0.005, 0.003, 0.002, 0.0015, 0.001};
    CsvTable csv;
    csv.header = {"mode", "t_s", "samples_per_pixel", "rmse", "rel_mse", "rmse_debiased"};
    std::string dat;
    double guide_rmse_at_1spp = 0;
    for (const LiveMode& mode : modes) {
      bench_progress("error", mode.name + " for " + csv_number(a.seconds) + " s");
      const LiveResult r = run_live(*scene, mode, sched);
      nlohmann::json mj;
      mj["samples_per_s"] = r.samples_per_s;
      mj["ticks"] = r.ticks.size();
      mj["dropped_samples"] = r.dropped;
      if (!r.ticks.empty()) {
        const TickRecord& last = r.ticks.back();
        mj["final"] = {{"t_s", last.t},
                       {"samples_per_pixel", double(last.samples) / double(pixels)},
                       {"rmse", last.rmse},
                       {"rel_mse", last.rel_mse},
                       {"rmse_debiased", last.rmse_debiased}};
      }
      nlohmann::json tt = nlohmann::json::object(), ts = nlohmann::json::object();
      for (double l : levels) {
        const double t = time_to(r.ticks, l, false, pixels), n = time_to(r.ticks, l, true, pixels);
        tt[csv_number(l)] = std::isnan(t) ? nlohmann::json() : nlohmann::json(t);
        ts[csv_number(l)] = std::isnan(n) ? nlohmann::json() : nlohmann::json(n);
      }
      mj["time_to_rmse_s"] = tt;
      mj["spp_to_rmse"] = ts;
      j["modes"][mode.kind] = mj;
      dat += "# " + mode.name + "\n";
      for (const TickRecord& t : r.ticks) {
        const double spp = double(t.samples) / double(pixels);
        if (guide_rmse_at_1spp == 0 && spp >= 16) guide_rmse_at_1spp = t.rmse * std::sqrt(spp);
        csv.rows.push_back({mode.name, csv_number(t.t), csv_number(spp), csv_number(t.rmse),
                            csv_number(t.rel_mse), csv_number(t.rmse_debiased)});
        if (t.samples > 0)
          dat += csv_number(t.t) + " " + csv_number(spp) + " " + csv_number(t.rmse) + " " +
                 csv_number(t.rel_mse) + "\n";
      }
      dat += "\n\n";
    }
    j["modes_run"] = nlohmann::json::array();
    for (const LiveMode& m : modes) j["modes_run"].push_back(m.kind);
    // Adaptive vs plain frameless: ratio of their times to each RMSE level both reached.
    nlohmann::json sp = nlohmann::json::object();
    for (double l : levels) {
      const auto& tf = j["modes"]["frameless"]["time_to_rmse_s"][csv_number(l)];
      const auto& ta = j["modes"]["adaptive"]["time_to_rmse_s"][csv_number(l)];
      if (tf.is_number() && ta.is_number() && ta.get<double>() > 0)
        sp[csv_number(l)] = tf.get<double>() / ta.get<double>();
    }
    j["adaptive_time_to_error_speedup"] = sp;
    if (!write_text_atomic(a.out + "/error.csv", csv.text(), error) ||
        !write_text_atomic(a.out + "/error.dat", dat, error))
      return report_error(error);
    std::string body = "set multiplot layout 1,2\nset logscale xy\nset grid\nset key top right\n";
    body += "set format y '%g'\nset format x '%g'\n";
    body += "set title 'Still camera: RMSE of the displayed image vs wall time'\n";
    body += "set xlabel 'seconds since start'\nset ylabel 'RMSE vs reference'\n";
    body += "set label 1 'reference noise floor' at graph 0.02, first " +
            csv_number(std::sqrt(ref->noise_mse) * 1.15) + "\n";
    body += "plot " + csv_number(std::sqrt(ref->noise_mse)) + " dt 3 lc rgb 'gray50' notitle";
    for (size_t k = 0; k < modes.size(); ++k)
      body += ", '" + a.out + "/error.dat' index " + std::to_string(k) +
              " using 1:3 with lines lw 2 lt " + std::to_string(k + 1) + " title '" +
              modes[k].name + "'";
    body +=
        "\nset title 'RMSE vs samples per pixel (dashed: 1/sqrt(n))'\nset xlabel 'samples per "
        "pixel'\n";
    body += "plot " + csv_number(std::sqrt(ref->noise_mse)) + " dt 3 lc rgb 'gray50' notitle";
    // Guide through the first mode's RMSE at 16 samples per pixel: RMSE falls as 1/sqrt(samples).
    const double r1 = guide_rmse_at_1spp > 0 ? guide_rmse_at_1spp : 0.1;
    body += ", " + csv_number(r1) + "/sqrt(x) dt 2 lc rgb 'gray30' title '1/sqrt(n)'";
    for (size_t k = 0; k < modes.size(); ++k)
      body += ", '" + a.out + "/error.dat' index " + std::to_string(k) +
              " using 2:3 with lines lw 2 lt " + std::to_string(k + 1) + " title '" +
              modes[k].name + "'";
    body += "\nunset multiplot";
    bool png = false;
    if (!plot_png(a.out, "error", 1000, 400, body, error, &png)) return report_error(error);
    j["outputs"] = {{"csv", "error.csv"}, {"plot", png ? "error.png" : ""}};
    if (!write_json(a.out + "/error.json", j, error)) return report_error(error);
    std::printf("bench error: %s %dx%d, %d threads, %.3g s per mode\n", a.scene.c_str(), width,
                height, threads, a.seconds);
    for (const LiveMode& m : modes) {
      const auto& f = j["modes"][m.kind]["final"];
      std::printf("  %-13s final RMSE %.4f  relMSE %.4g  at %.1f spp\n", m.kind.c_str(),
                  f.value("rmse", 0.0), f.value("rel_mse", 0.0), f.value("samples_per_pixel", 0.0));
    }
    std::printf("  wrote %s/error.json\n", a.out.c_str());
  } catch (const std::exception& ex) {
    return report_error(ex.what());
  }
  return 0;
}

}  // namespace frameless::bench
