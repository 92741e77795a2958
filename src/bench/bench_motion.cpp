// `frameless bench motion`: a camera moves along a path (camera_path.h) in steps at a fixed input
// rate; at every display refresh the displayed image is scored against the converged image for the
// camera in effect at that instant (references rendered up front, cached). Frameless at several
// alpha and update percentages, conventional double buffering on the same threads, and adaptive.
#include "bench/bench_motion.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <memory>

#include "bench/bench_live.h"
#include "bench/bench_options.h"
#include "bench/bench_report.h"
#include "display/camera_path.h"
#include "frameless/reference_cache.h"

namespace frameless::bench {
namespace {

struct RunRow {
  LiveMode mode;
  double alpha = 0, percent = 0;
  double sample_fraction = 1;  // render threads capped at this fraction of conventional's samples/s
  LiveResult result;
  double avg_rmse = 0, avg_rmse_debiased = 0, avg_rel_mse = 0, tail_rmse = 0;
  std::vector<double> per_repeat;  // time-averaged RMSE of each repeat
};

}  // namespace

int run_motion(const MotionOptions& options) {
  MotionOptions a = options;
  std::string error;
  if (a.quick) {
    a.size = "160x120";
    a.move_seconds = 1.5;
    a.hold_seconds = 0.5;
    a.tail_seconds = 0.3;
    a.ref_spp = 8;
    a.alphas = {0.5, 1.0};
    a.percents = {1, 10};
    a.repeats = 1;
    a.sample_fractions = {0.25};
  }
  a.sample_fractions.erase(std::remove(a.sample_fractions.begin(), a.sample_fractions.end(), 0.0),
                           a.sample_fractions.end());
  for (double f : a.sample_fractions)
    if (!(f > 0 && f <= 1)) return report_error("--sample-fractions: each must be in (0, 1] (0: none)");
  int width = 0, height = 0;
  if (!parse_size(a.size, width, height, error)) return report_error(error);
  if (!valid_threads(a.threads, error)) return report_error(error);
  if (!(a.move_seconds > 0 && a.move_seconds <= 600))
    return report_error("--move-seconds: must be in (0, 600]");
  if (!(a.hold_seconds >= 0 && a.hold_seconds <= 600))
    return report_error("--hold-seconds: must be in [0, 600]");
  if (!(a.tail_seconds >= 0 && a.tail_seconds <= 600))
    return report_error("--tail-seconds: must be in [0, 600]");
  if (!(a.camera_hz >= 1 && a.camera_hz <= 240))
    return report_error("--camera-hz: must be in [1, 240]");
  if (!(a.refresh >= 1 && a.refresh <= 240)) return report_error("--refresh: must be in [1, 240]");
  if (!(a.budget > 0 && a.budget <= 1)) return report_error("--budget: must be in (0, 1]");
  if (a.render_nice < 0 || a.render_nice > kMaxRenderNice) return report_error("--render-nice: must be 0..19");
  if (!(a.dolly > 0 && std::isfinite(a.orbit))) return report_error("--dolly: must be > 0");
  if (!(a.alpha > 0 && a.alpha <= 1)) return report_error("--alpha: must be in (0, 1]");
  if (!(a.percent >= 0.01 && a.percent <= 100))
    return report_error("--update-percent: must be in [0.01, 100]");
  for (double al : a.alphas)
    if (!(al > 0 && al <= 1)) return report_error("--alphas: each must be in (0, 1]");
  for (double p : a.percents)
    if (!(p >= 0.01 && p <= 100))
      return report_error("--update-percents: each must be in [0.01, 100]");
  if (a.ref_spp < 2 || a.ref_spp > 1 << 20)
    return report_error("--ref-spp: must be in [2, 1048576]");
  if (a.repeats < 1 || a.repeats > 100) return report_error("--repeats: must be in [1, 100]");
  if (!prepare_out_dir(a.out, error)) return report_error(error);
  std::unique_ptr<Scene> scene = load_scene_or_report(a.scene, &a.shadows);
  if (!scene) return 2;
  const int threads = a.threads > 0 ? a.threads : hardware_threads();
  const std::string cache = a.cache.empty() ? default_reference_cache_dir(a.out) : a.cache;

  try {
    // The path and its poses at the camera input rate.
    PathShorthand sh;
    sh.orbit_deg = a.orbit;
    sh.dolly_factor = a.dolly;
    const CameraPath path = make_shorthand_path(scene->camera, sh, a.move_seconds);
    const int steps = std::max(1, int(std::lround(a.move_seconds * a.camera_hz)));
    std::vector<Camera> poses;
    for (int k = 0; k <= steps; ++k)
      poses.push_back(
          evaluate_camera_path(path, a.move_seconds * double(k) / steps, scene->camera));

    ReferenceSpec rs;
    rs.scene_id = scene_identity(a.scene);
    rs.code_version = code_version(*scene);
    rs.width = width;
    rs.height = height;
    rs.spp = a.ref_spp;
    std::vector<Reference> refs;
    int cached = 0;
    double ref_seconds = 0, noise_sum = 0;
    for (size_t k = 0; k < poses.size(); ++k) {
      rs.camera = poses[k];
      if (show_progress())
        std::fprintf(stderr, "\rbench motion: reference %zu/%zu", k + 1, poses.size());
      auto ref = load_or_render_reference(*scene, rs, cache, threads);
      if (!ref.ok()) return report_error(ref.error().message);
      cached += ref->from_cache ? 1 : 0;
      ref_seconds += ref->seconds;
      noise_sum += ref->noise_mse;
      refs.push_back(std::move(*ref));
    }
    if (show_progress()) std::fprintf(stderr, "\n");

    LiveSchedule sched;
    sched.poses = poses;
    for (const Reference& r : refs) {
      sched.references.push_back(&r.rgb);
      sched.noise_mse.push_back(r.noise_mse);
    }
    sched.hold_seconds = a.hold_seconds;
    sched.pose_interval = a.move_seconds / steps;
    sched.duration = a.hold_seconds + a.move_seconds + a.tail_seconds;
    const double t0 = a.hold_seconds, t1 = a.hold_seconds + a.move_seconds;

    LiveMode base;
    base.engine.width = width;
    base.engine.height = height;
    base.engine.threads = threads;
    base.engine.render_nice = a.render_nice;
    base.display.refresh_hz = a.refresh;
    std::vector<RunRow> rows;
    // A frameless row at blend weight `al` and update percent `p`.
    auto frameless_row = [&](const std::string& kind, const std::string& name, double al, double p) {
      RunRow r;
      r.mode = base;
      r.mode.kind = kind;
      r.mode.name = name;
      r.mode.display.blend.alpha = float(al);
      r.mode.engine.update_percent = p;
      r.alpha = al;
      r.percent = p;
      return r;
    };
    auto add_frameless = [&](double al, double p) {
      for (const RunRow& r : rows)
        if (r.mode.kind == "frameless" && r.alpha == al && r.percent == p) return;
      rows.push_back(frameless_row("frameless", "frameless a=" + csv_number(al) + " p=" + csv_number(p) + "%", al, p));
    };
    // The headline motion settings (reprojection + temporal weights) at the default alpha and
    // update percent; the equal-error rows vary threads or the sample cap.
    auto motion_row = [&](const std::string& kind, const std::string& name) {
      RunRow r = frameless_row(kind, name, a.alpha, a.percent);
      r.mode.display.blend.reproject = r.mode.display.blend.temporal = true;
      return r;
    };
    add_frameless(a.alpha, a.percent);  // the default setting first
    for (double al : a.alphas) add_frameless(al, a.percent);
    for (double p : a.percents) add_frameless(a.alpha, p);
    // The render cache and AFR's temporal weights on the default setting.
    // "budget": reprojection kept within --budget of one core (default 0.15: the display thread
    // within 25 % in bench engine's 1280x720 move).
    static const char* const kVariants[] = {"reproject", "reproject+temporal", "temporal",
                                            "closed-loop", "reproject+temporal+closed-loop",
                                            "reproject+temporal+budget", "reproject+temporal+adaptive",
                                            "reproject+temporal+denoise"};
    for (const char* variant : kVariants) {
      const std::string v = variant;
      RunRow r = frameless_row(v, "frameless " + v + " a=" + csv_number(a.alpha) + " p=" + csv_number(a.percent) + "%",
                               a.alpha, a.percent);
      r.mode.display.blend.reproject = v.find("reproject") != std::string::npos;
      r.mode.display.blend.temporal = v.find("temporal") != std::string::npos;
      r.mode.engine.closed_loop = v.find("closed-loop") != std::string::npos;
      if (v.find("budget") != std::string::npos) r.mode.display.blend.reproject_budget = float(a.budget);
      r.mode.engine.adaptive.enabled = v.find("adaptive") != std::string::npos;
      // The display's a-trous filter (display/denoise.h) reads each pixel's variance.
      const bool denoise = v.find("denoise") != std::string::npos;
      r.mode.display.blend.denoise = r.mode.engine.track_variance = denoise;
      rows.push_back(r);
    }
    // Equal error at fewer samples: the headline motion settings on half the render threads,
    // against double buffering on all of them.
    if (threads >= 2) {
      RunRow r = motion_row("reproject+temporal half-threads", "frameless reproject+temporal " +
                                                                   std::to_string(threads / 2) + " of " +
                                                                   std::to_string(threads) + " threads");
      r.mode.engine.threads = threads / 2;
      rows.push_back(r);
    }
    RunRow cv;
    cv.mode = base;
    cv.mode.kind = "conventional";
    cv.mode.name = "conventional (double buffered)";
    cv.mode.engine.mode = RenderMode::conventional;
    rows.push_back(cv);
    RunRow ad;
    ad.mode = base;
    ad.mode.kind = "adaptive";
    ad.mode.name = "adaptive a=" + csv_number(a.alpha) + " p=" + csv_number(a.percent) + "%";
    ad.mode.display.blend.alpha = float(a.alpha);
    ad.mode.engine.update_percent = a.percent;
    ad.alpha = a.alpha;
    ad.percent = a.percent;
    ad.mode.engine.adaptive.enabled = true;
    rows.push_back(ad);

    CsvTable csv;
    csv.header = {"run",  "kind", "alpha",   "update_percent", "t_s",
                  "pose", "rmse", "rel_mse", "rmse_debiased",  "coverage"};
    std::string dat;
    // Repeats interleave the settings, so a change in the machine's load hits all of them alike;
    // time averages are means over repeats, the curves and CSV come from the first repeat.
    auto run_rows = [&](size_t first) {
      for (int rep = 0; rep < a.repeats; ++rep)
        for (size_t k = first; k < rows.size(); ++k) {
          RunRow& r = rows[k];
          bench_progress("motion", r.mode.name + " (repeat " + std::to_string(rep + 1) + ")");
          LiveResult res = run_live(*scene, r.mode, sched);
          const auto& ticks = res.ticks;
          r.avg_rmse += time_average(ticks, t0, t1, &TickRecord::rmse) / a.repeats;
          r.avg_rmse_debiased += time_average(ticks, t0, t1, &TickRecord::rmse_debiased) / a.repeats;
          r.avg_rel_mse += time_average(ticks, t0, t1, &TickRecord::rel_mse) / a.repeats;
          r.tail_rmse += time_average(ticks, t1, sched.duration, &TickRecord::rmse) / a.repeats;
          r.per_repeat.push_back(time_average(ticks, t0, t1, &TickRecord::rmse));
          if (rep == 0) r.result = std::move(res);
        }
    };
    run_rows(0);
    // Equal error at fewer samples: the headline motion settings capped at fractions of
    // conventional's measured samples/s (its first repeat), after the runs that measured it.
    const size_t capped_first = rows.size();
    double conv_rate = 0;
    for (const RunRow& r : rows)
      if (r.mode.kind == "conventional") conv_rate = r.result.samples_per_s;
    if (conv_rate > 0)
      for (double f : a.sample_fractions) {
        RunRow r = motion_row("reproject+temporal capped", "frameless reproject+temporal at " +
                                                               csv_number(f) + "x the samples of conventional");
        r.mode.engine.max_samples_per_s = f * conv_rate;
        r.sample_fraction = f;
        rows.push_back(r);
      }
    run_rows(capped_first);
    for (RunRow& r : rows) {
      dat += "# " + r.mode.name + "\n";
      for (const TickRecord& t : r.result.ticks) {
        csv.rows.push_back({r.mode.name, r.mode.kind, csv_number(r.alpha), csv_number(r.percent),
                            csv_number(t.t), std::to_string(t.pose), csv_number(t.rmse),
                            csv_number(t.rel_mse), csv_number(t.rmse_debiased),
                            csv_number(t.coverage)});
        dat += csv_number(t.t) + " " + csv_number(t.rmse) + "\n";
      }
      dat += "\n\n";
    }

    nlohmann::json settings = {
        {"size", a.size},
        {"threads", threads},
        {"refresh_hz", a.refresh},
        {"camera_hz", a.camera_hz},
        {"hold_seconds", a.hold_seconds},
        {"move_seconds", a.move_seconds},
        {"tail_seconds", a.tail_seconds},
        {"path", {{"orbit_deg", a.orbit}, {"dolly_factor", a.dolly}, {"poses", poses.size()}}},
        {"reference_spp", a.ref_spp},
        {"alphas", a.alphas},
        {"update_percents", a.percents},
        {"default_alpha", a.alpha},
        {"default_update_percent", a.percent},
        {"reproject_budget", a.budget},
        {"quick", a.quick},
        {"repeats", a.repeats},
        {"clock", "wall (real Engine + DisplayThread)"},
        {"averaging",
         "time average over the move [hold, hold + move], each tick weighted by its interval"}};
    nlohmann::json j = bench_header("motion", scene.get(), a.scene, settings);
    j["references"] = {{"count", refs.size()},
                       {"from_cache", cached},
                       {"seconds", ref_seconds},
                       {"spp", a.ref_spp},
                       {"mean_noise_rmse", std::sqrt(noise_sum / double(refs.size()))},
                       {"cache_dir", cache}};
    const RunRow* best = nullptr;
    std::string equal_error_line;
    nlohmann::json table = nlohmann::json::array();
    for (const RunRow& r : rows) {
      table.push_back({{"run", r.mode.name},
                       {"kind", r.mode.kind},
                       {"alpha", r.alpha},
                       {"update_percent", r.percent},
                       {"time_avg_rmse", r.avg_rmse},
                       {"time_avg_rmse_debiased", r.avg_rmse_debiased},
                       {"time_avg_rel_mse", r.avg_rel_mse},
                       {"tail_avg_rmse", r.tail_rmse},
                       {"time_avg_rmse_per_repeat", r.per_repeat},
                       {"samples_per_s", r.result.samples_per_s},
                       {"ticks", r.result.ticks.size()}});
      if (r.mode.kind == "frameless" && (!best || r.avg_rmse < best->avg_rmse)) best = &r;
    }
    const RunRow& fl = rows[0];
    const RunRow* conv = nullptr;
    const RunRow* adap = nullptr;
    for (const RunRow& r : rows) {
      if (r.mode.kind == "conventional") conv = &r;
      if (r.mode.kind == "adaptive") adap = &r;
    }
    auto value = [](const RunRow* r, double RunRow::*f) {
      return r ? nlohmann::json(r->*f) : nlohmann::json();
    };
    j["time_avg_rmse"] = {{"frameless", fl.avg_rmse},
                          {"conventional", value(conv, &RunRow::avg_rmse)},
                          {"adaptive", value(adap, &RunRow::avg_rmse)}};
    for (const RunRow& r : rows)  // the render cache and temporal weights, default setting
      if (r.mode.kind != "frameless" && r.mode.kind != "conventional" && r.mode.kind != "adaptive") {
        j["time_avg_rmse"][r.mode.kind] = r.avg_rmse;
        j["reprojection"][r.mode.kind] = {{"reprojections", r.result.reproject.reprojections},
                                          {"display_cpu_s", r.result.display_cpu_seconds},
                                          {"reproject_cpu_s", r.result.reproject.cpu_seconds}};
      }
    j["time_avg_rmse_debiased"] = {{"frameless", fl.avg_rmse_debiased},
                                   {"conventional", value(conv, &RunRow::avg_rmse_debiased)},
                                   {"adaptive", value(adap, &RunRow::avg_rmse_debiased)}};
    j["time_avg_rel_mse"] = {{"frameless", fl.avg_rel_mse},
                             {"conventional", value(conv, &RunRow::avg_rel_mse)},
                             {"adaptive", value(adap, &RunRow::avg_rel_mse)}};
    j["frameless_setting"] =
        "the default setting: " + fl.mode.name + " (best frameless setting under frameless_best)";
    j["frameless_best"] = {{"run", best->mode.name}, {"time_avg_rmse", best->avg_rmse}};
    j["runs"] = table;
    // Each mode at its best setting (equal compute: all threads, no sample cap), and the
    // defaults: fair settings for the headline.
    const RunRow* best_any = nullptr;
    for (size_t k = 0; k < capped_first; ++k) {
      const RunRow& r = rows[k];
      if (r.mode.kind == "conventional" || r.mode.engine.threads != threads) continue;
      if (!best_any || r.avg_rmse < best_any->avg_rmse) best_any = &r;
    }
    if (conv && best_any) {
      j["best_per_mode"] = {
          {"conventional", {{"run", conv->mode.name}, {"time_avg_rmse", conv->avg_rmse}}},
          {"frameless_plain", {{"run", best->mode.name}, {"time_avg_rmse", best->avg_rmse}}},
          {"frameless_any", {{"run", best_any->mode.name}, {"time_avg_rmse", best_any->avg_rmse}}},
          {"default_frameless_ratio", fl.avg_rmse / conv->avg_rmse},
          {"best_frameless_ratio", best_any->avg_rmse / conv->avg_rmse}};
    }
    // Samples for equal error: the capped runs' RMSE against their fraction, and the fraction
    // where it meets conventional's RMSE (log-log interpolation between the bracketing runs).
    if (conv && rows.size() > capped_first) {
      std::vector<std::pair<double, double>> curve;  // (fraction, rmse), the full rate first
      for (const RunRow& r : rows)
        if (r.mode.kind == "reproject+temporal") curve.push_back({1.0, r.avg_rmse});
      for (size_t k = capped_first; k < rows.size(); ++k)
        curve.push_back({rows[k].sample_fraction, rows[k].avg_rmse});
      std::sort(curve.begin(), curve.end(), [](auto& x, auto& y) { return x.first > y.first; });
      nlohmann::json points = nlohmann::json::array();
      for (const auto& [f, e] : curve) points.push_back({{"fraction", f}, {"time_avg_rmse", e}});
      nlohmann::json at = nullptr;
      std::string note = "frameless's error stays below conventional's down to the smallest fraction run";
      for (size_t k = 0; k + 1 < curve.size(); ++k) {
        const auto [f0, e0] = curve[k];
        const auto [f1, e1] = curve[k + 1];
        if (e0 <= conv->avg_rmse && e1 > conv->avg_rmse) {
          const double u = std::log(conv->avg_rmse / e0) / std::log(e1 / e0);
          at = std::exp(std::log(f0) + u * (std::log(f1) - std::log(f0)));
          note = "interpolated between the runs at " + csv_number(f0) + " and " + csv_number(f1);
          break;
        }
      }
      if (!curve.empty() && curve.front().second > conv->avg_rmse) note = "frameless needs more samples";
      j["equal_error_samples"] = {{"conventional_rmse", conv->avg_rmse},
                                  {"runs", points},
                                  {"fraction_at_equal_error", at},
                                  {"note", note}};
      equal_error_line = at.is_null() ? note + " (" + csv_number(curve.back().first) + "x: RMSE " +
                                            csv_number(curve.back().second) + ")"
                                      : csv_number(at.get<double>()) + "x conventional's samples (" + note + ")";
    }

    if (!write_text_atomic(a.out + "/motion.csv", csv.text(), error) ||
        !write_text_atomic(a.out + "/motion.dat", dat, error))
      return report_error(error);
    std::string bars;
    for (size_t k = 0; k < rows.size(); ++k)
      bars += std::to_string(k) + " " + csv_number(rows[k].avg_rmse) + " \"" + rows[k].mode.name +
              "\"\n";
    if (!write_text_atomic(a.out + "/motion_avg.dat", bars, error)) return report_error(error);
    // Short labels: "frameless " and the default setting's " a=.. p=..%" add nothing on a plot.
    const std::string default_suffix = " a=" + csv_number(a.alpha) + " p=" + csv_number(a.percent) + "%";
    auto label = [&](std::string n) {
      if (n.rfind("frameless ", 0) == 0 && n != rows[0].mode.name) n.erase(0, 10);
      if (const size_t at = n.find(default_suffix); at != std::string::npos && n != rows[0].mode.name)
        n.erase(at, default_suffix.size());
      if (const size_t at = n.find(" the samples of conventional"); at != std::string::npos)
        n.replace(at, std::string::npos, " samples");
      return gnuplot_text(n);
    };
    std::string body = "set multiplot layout 2,1\nset grid\n";
    body +=
        "set title 'Moving camera: RMSE of each displayed image vs the converged image for that "
        "instant'\n";
    body +=
        "set xlabel 'seconds (camera moves between the dashed lines)'\nset ylabel 'RMSE'\nset key "
        "outside right top font ',8'\n";
    body += "set arrow from " + csv_number(t0) + ", graph 0 to " + csv_number(t0) +
            ", graph 1 nohead dt 2 lc rgb 'gray40'\n";
    body += "set arrow from " + csv_number(t1) + ", graph 0 to " + csv_number(t1) +
            ", graph 1 nohead dt 2 lc rgb 'gray40'\n";
    // Scale the curves to the move (the initial fill of an empty screen would dwarf it).
    double ymax = 0;
    for (const RunRow& r : rows)
      for (const TickRecord& t : r.result.ticks)
        if (t.t >= t0) ymax = std::max(ymax, t.rmse);
    body += "set yrange [0:" + csv_number(ymax > 0 ? 1.5 * ymax : 1.0) + "]\nplot ";
    for (size_t k = 0; k < rows.size(); ++k) {
      const bool key = k == 0 || rows[k].mode.kind != "frameless";
      body += (k ? ", " : "") + std::string("'") + a.out + "/motion.dat' index " +
              std::to_string(k) + " using 1:2 with lines lt " + std::to_string(k + 1) + " lw " +
              (key ? "2.5" : "1") + " title '" + label(rows[k].mode.name) + "'";
    }
    body +=
        "\nunset arrow\nset title 'Time-averaged RMSE during the move'\nset xlabel ''\nset ylabel "
        "'time-averaged RMSE'\n";
    body +=
        "set style fill solid 0.6\nset boxwidth 0.7\nset xtics rotate by -30 font ',8'\nset key "
        "off\nset yrange [0:*]\nset bmargin 9\nset rmargin 18\nset xtics (";
    for (size_t k = 0; k < rows.size(); ++k)
      body += (k ? ", '" : "'") + gnuplot_tic_text(label(rows[k].mode.name)) + "' " + std::to_string(k);
    body += ")\n";
    body += "plot '" + a.out + "/motion_avg.dat' using 1:2 with boxes lc rgb '#4477aa'";
    body += "\nunset multiplot";
    bool png = false;
    if (!plot_png(a.out, "motion", 1200, 900, body, error, &png)) return report_error(error);
    j["outputs"] = {{"csv", "motion.csv"}, {"plot", png ? "motion.png" : ""}};
    if (!write_json(a.out + "/motion.json", j, error)) return report_error(error);
    std::printf("bench motion: %s %dx%d, %d threads, camera %.3g Hz over %.3g s\n", a.scene.c_str(),
                width, height, threads, a.camera_hz, a.move_seconds);
    for (const RunRow& r : rows)
      std::printf("  %-44s time-avg RMSE %.4f (debiased %.4f)%s\n", r.mode.name.c_str(), r.avg_rmse,
                  r.avg_rmse_debiased,
                  conv && r.avg_rmse > 0 && &r != conv
                      ? (" " + csv_number(r.avg_rmse / conv->avg_rmse) + "x conventional").c_str()
                      : "");
    if (j.contains("best_per_mode"))
      std::printf("  best setting: %s at %.3fx conventional (plain frameless at the default alpha and "
                  "update %%: %.3fx; view and capture default to reprojection + temporal weights)\n",
                  j["best_per_mode"]["frameless_any"]["run"].get<std::string>().c_str(),
                  j["best_per_mode"]["best_frameless_ratio"].get<double>(),
                  j["best_per_mode"]["default_frameless_ratio"].get<double>());
    if (!equal_error_line.empty())
      std::printf("  samples for conventional's error: %s\n", equal_error_line.c_str());
    std::printf("  wrote %s/motion.json\n", a.out.c_str());
  } catch (const std::exception& ex) {
    return report_error(ex.what());
  }
  return 0;
}

}  // namespace frameless::bench
