// `frameless bench latency`: camera change -> 50 %, 95 %, 100 % of the displayed pixels showing
// the new camera (display at 240 Hz, wall clock), for several update percentages, against the
// ideal: every pixel updated once at the measured rate, pixels / (pixel updates per second).
#include "bench/bench_latency.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <memory>

#include "bench/bench_options.h"
#include "bench/bench_report.h"
#include "bench/latency_trial.h"
#include "frameless/engine.h"

namespace frameless::bench {
namespace {

nlohmann::json num(double v) { return std::isnan(v) ? nlohmann::json() : nlohmann::json(v); }

}  // namespace

int run_latency(const LatencyOptions& options) {
  LatencyOptions a = options;
  std::string error;
  if (a.quick) {
    a.size = "160x120";
    a.percents = {1, 10};
    a.repeats = 1;
  }
  int width = 0, height = 0;
  if (!parse_size(a.size, width, height, error)) return report_error(error);
  if (!valid_threads(a.threads, error)) return report_error(error);
  if (a.repeats < 1 || a.repeats > 100) return report_error("--repeats: must be in [1, 100]");
  if (!(a.refresh >= 1 && a.refresh <= 240)) return report_error("--refresh: must be in [1, 240]");
  if (a.percents.empty()) return report_error("--update-percents: at least one value");
  for (double p : a.percents)
    if (!(p >= 0.01 && p <= 100))
      return report_error("--update-percents: each must be in [0.01, 100]");
  if (!prepare_out_dir(a.out, error)) return report_error(error);
  std::unique_ptr<Scene> scene = load_scene_or_report(a.scene, &a.shadows);
  if (!scene) return 2;
  const int threads = a.threads > 0 ? a.threads : hardware_threads();
  try {
    nlohmann::json settings = {
        {"size", a.size},
        {"threads", threads},
        {"refresh_hz", a.refresh},
        {"update_percents", a.percents},
        {"repeats", a.repeats},
        {"quick", a.quick},
        {"camera_change", "eye moved 5% towards the look-at point after 0.4 s"},
        {"ideal",
         "pixels / measured pixel updates per second (one update = "
         "2 jittered samples): every pixel updated exactly once"}};
    nlohmann::json j = bench_header("latency", scene.get(), a.scene, settings);
    CsvTable csv;
    csv.header = {"update_percent", "repeat", "p50_ms", "p95_ms", "p100_ms", "ideal_ms"};
    std::string dat, summary;
    j["results"] = nlohmann::json::array();
    for (size_t i = 0; i < a.percents.size(); ++i) {
      const double p = a.percents[i];
      EngineConfig c;
      c.width = width;
      c.height = height;
      c.threads = threads;
      c.update_percent = p;
      c.track_variance = false;
      std::vector<double> p50, p95, p100, ideal;
      LatencyTrial first;
      for (int r = 0; r < a.repeats; ++r) {
        bench_progress("latency", "update " + csv_number(p) + "%, repeat " + std::to_string(r + 1));
        LatencyTrial t = measure_latency(*scene, c, scene->camera, a.refresh);
        p50.push_back(t.p50), p95.push_back(t.p95), p100.push_back(t.p100),
            ideal.push_back(t.ideal);
        csv.rows.push_back({csv_number(p), std::to_string(r), csv_number(t.p50), csv_number(t.p95),
                            csv_number(t.p100), csv_number(t.ideal)});
        if (r == 0) first = std::move(t);
      }
      const double id = median(ideal);
      j["results"].push_back({{"update_percent", p},
                              {"p50_ms", num(median(p50))},
                              {"p95_ms", num(median(p95))},
                              {"p100_ms", num(median(p100))},
                              {"ideal_ms", num(id)},
                              {"p100_over_ideal", num(median(p100) / id)},
                              {"bound_ms", num(id * (1.0 + p / 100.0))}});
      dat += "# update " + csv_number(p) + "%\n0 0\n";
      for (const auto& [ms, cov] : first.curve)
        dat += csv_number(ms / id) + " " + csv_number(cov) + "\n";
      dat += "\n\n";
      summary += csv_number(p) + " " + csv_number(median(p50) / id) + " " +
                 csv_number(median(p95) / id) + " " + csv_number(median(p100) / id) + "\n";
    }
    if (!write_text_atomic(a.out + "/latency.csv", csv.text(), error) ||
        !write_text_atomic(a.out + "/latency.dat", dat, error) ||
        !write_text_atomic(a.out + "/latency_summary.dat", summary, error))
      return report_error(error);
    std::string body = "set multiplot layout 1,2\nset grid\n";
    body += "set title 'Camera change: fraction of pixels showing it (first repeat)'\n";
    body +=
        "set xlabel 'time since the change / ideal (pixels / update rate)'\nset ylabel 'fraction "
        "of pixels'\n";
    body += "set yrange [0:1.02]\nset xrange [0:*]\nset key bottom right\n";
    body += "set arrow from 1, graph 0 to 1, graph 1 nohead dt 2 lc rgb 'gray40'\nplot ";
    for (size_t i = 0; i < a.percents.size(); ++i)
      body += (i ? ", " : "") + std::string("'") + a.out + "/latency.dat' index " +
              std::to_string(i) + " using 1:2 with lines lw 2 title 'update " +
              csv_number(a.percents[i]) + "%'";
    body +=
        "\nunset arrow\nset title 'Median latency / ideal'\nset logscale x\nset xlabel 'update "
        "percentage'\n";
    body += "set ylabel 'latency / ideal'\nset yrange [0:*]\nset xrange [*:*]\nset key top left\n";
    body += "plot '" + a.out +
            "/latency_summary.dat' using 1:2 with linespoints lw 2 title '50%', '' using 1:3 "
            "with linespoints lw 2 title '95%', '' using 1:4 with linespoints lw 2 title '100%', 1 "
            "dt 2 lc rgb 'gray40' title 'ideal'";
    body += "\nunset multiplot";
    bool png = false;
    if (!plot_png(a.out, "latency", 1000, 400, body, error, &png)) return report_error(error);
    j["outputs"] = {{"csv", "latency.csv"}, {"plot", png ? "latency.png" : ""}};
    if (!write_json(a.out + "/latency.json", j, error)) return report_error(error);
    std::printf("bench latency: %s %dx%d, %d threads, display %.0f Hz (medians of %d)\n",
                a.scene.c_str(), width, height, threads, a.refresh, a.repeats);
    for (const auto& r : j["results"]) {
      auto f = [](const nlohmann::json& v) { return v.is_number() ? v.get<double>() : NAN; };
      std::printf(
          "  update %5.3g%%: 50%% %6.1f ms, 95%% %6.1f ms, 100%% %6.1f ms, ideal %6.1f ms\n",
          r["update_percent"].get<double>(), f(r["p50_ms"]), f(r["p95_ms"]), f(r["p100_ms"]),
          f(r["ideal_ms"]));
    }
    std::printf("  wrote %s/latency.json\n", a.out.c_str());
  } catch (const std::exception& ex) {
    return report_error(ex.what());
  }
  return 0;
}

}  // namespace frameless::bench
