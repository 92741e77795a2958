#include "bench/bench_motion_sweep.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <map>
#include <set>

#include <nlohmann/json.hpp>

#include "bench/bench_options.h"
#include "bench/bench_report.h"

namespace frameless::bench {
namespace {

// One (scene, size) of the sweep: its regime and each setting's time-averaged RMSE.
struct SweepPoint {
  std::string scene, size;
  double regime = 0;              // conventional frame time / camera input interval
  double conventional_frame_s = 0;
  std::map<std::string, double> rmse;  // by run name
  double conventional_rmse = 0;
};

}  // namespace

int run_motion_sweep(const MotionSweepOptions& o) {
  std::string error;
  if (o.scenes.empty() || o.sizes.empty()) return report_error("--sweep: needs at least one scene and one size");
  if (!prepare_out_dir(o.base.out, error)) return report_error(error);
  std::vector<SweepPoint> points;
  std::set<std::string> fewer_threads;  // runs on fewer render threads: not equal compute
  for (const std::string& scene : o.scenes)
    for (const std::string& size : o.sizes) {
      int w = 0, h = 0;
      if (!parse_size(size, w, h, error, "--sweep-sizes")) return report_error(error);
      MotionOptions m = o.base;
      m.sample_fractions.clear();  // equal compute only: the capped runs belong to single runs
      m.scene = scene;
      m.size = size;
      std::string dir = scene + "_" + size;
      std::replace_if(dir.begin(), dir.end(), [](char c) { return c == '/' || c == ':' || c == '.'; }, '_');
      m.out = o.base.out + "/" + dir;
      bench_progress("motion sweep", scene + " " + size);
      if (int code = run_motion(m); code != 0) return code;
      std::ifstream in(m.out + "/motion.json");
      nlohmann::json j;
      try {
        in >> j;
      } catch (const std::exception& ex) {
        return report_error(m.out + "/motion.json: " + ex.what());
      }
      SweepPoint p;
      p.scene = scene;
      p.size = size;
      for (const auto& r : j["runs"]) {
        const std::string name = r["run"], kind = r["kind"];
        if (kind == "conventional") {
          // A conventional frame takes every pixel's update: pixels x samples per update / rate.
          const double rate = r["samples_per_s"];
          p.conventional_frame_s = rate > 0 ? double(w) * double(h) * 2.0 / rate : 0.0;
          p.conventional_rmse = r["time_avg_rmse"];
        } else {
          p.rmse[name] = r["time_avg_rmse"];
          if (r["kind"].get<std::string>().find("half-threads") != std::string::npos) fewer_threads.insert(name);
        }
      }
      p.regime = p.conventional_frame_s * o.base.camera_hz;
      points.push_back(p);
    }
  std::sort(points.begin(), points.end(), [](const SweepPoint& a, const SweepPoint& b) { return a.regime < b.regime; });

  // Each mode's best setting over the sweep is the one with the lowest mean ratio; the default
  // settings are reported too (the first frameless row is the default, see run_motion).
  std::map<std::string, double> mean_ratio;
  for (const SweepPoint& p : points)
    for (const auto& [name, rmse] : p.rmse)
      mean_ratio[name] += rmse / p.conventional_rmse / double(points.size());
  CsvTable csv;
  csv.header = {"scene", "size", "regime", "conventional_frame_s", "conventional_rmse", "run", "rmse", "ratio"};
  nlohmann::json rows = nlohmann::json::array();
  for (const SweepPoint& p : points) {
    nlohmann::json runs = nlohmann::json::object();
    for (const auto& [name, rmse] : p.rmse) {
      csv.rows.push_back({p.scene, p.size, csv_number(p.regime), csv_number(p.conventional_frame_s),
                          csv_number(p.conventional_rmse), name, csv_number(rmse),
                          csv_number(rmse / p.conventional_rmse)});
      runs[name] = {{"time_avg_rmse", rmse}, {"ratio_to_conventional", rmse / p.conventional_rmse}};
    }
    rows.push_back({{"scene", p.scene}, {"size", p.size}, {"regime", p.regime},
                    {"conventional_frame_s", p.conventional_frame_s},
                    {"conventional_time_avg_rmse", p.conventional_rmse}, {"runs", runs}});
  }
  // The best setting picked from the sweep: the lowest mean ratio over the points where frameless
  // is meant to work (regime 1 and above; below it double buffering keeps up, and single runs of
  // a few milliseconds' error there are noise), at equal compute (rows on fewer threads excluded).
  std::map<std::string, double> heavy_ratio;
  size_t heavy = 0;
  for (const SweepPoint& p : points) heavy += p.regime >= 1.0;
  for (const SweepPoint& p : points)
    if (p.regime >= 1.0)
      for (const auto& [name, rmse] : p.rmse) heavy_ratio[name] += rmse / p.conventional_rmse / double(heavy);
  std::string best_name;
  for (const auto& [name, r] : heavy_ratio)
    if (!fewer_threads.count(name) && (best_name.empty() || r < heavy_ratio[best_name]))
      best_name = name;
  nlohmann::json j = bench_header("motion-sweep", nullptr, "", {{"scenes", o.scenes}, {"sizes", o.sizes},
                                                                {"camera_hz", o.base.camera_hz},
                                                                {"threads", o.base.threads}});
  j["regime"] = "conventional frame time / camera input interval";
  j["points"] = rows;
  j["mean_ratio_to_conventional"] = mean_ratio;
  j["mean_ratio_to_conventional_regime_1_and_above"] = heavy_ratio;
  if (!best_name.empty())
    j["best_setting"] = {{"run", best_name},
                         {"mean_ratio_to_conventional_regime_1_and_above", heavy_ratio[best_name]},
                         {"points", heavy}};
  if (!write_json(o.base.out + "/sweep.json", j, error) ||
      !write_text_atomic(o.base.out + "/sweep.csv", csv.text(), error))
    return report_error(error);

  // One panel per scene, one line per setting: ratio to double buffering against the regime.
  auto short_name = [](std::string n) {
    for (const std::string cut : {"frameless ", " p=1%"})
      if (const size_t at = n.find(cut); at != std::string::npos) n.erase(at, cut.size());
    return n;
  };
  std::string dat;
  std::vector<std::string> names;
  for (const auto& [name, r] : mean_ratio) names.push_back(name);
  int block = 0;
  std::map<std::string, std::vector<int>> blocks;  // scene -> data blocks, in names' order
  for (const std::string& scene : o.scenes)
    for (const std::string& name : names) {
      dat += "# " + scene + ": " + name + "\n";
      for (const SweepPoint& p : points)
        if (p.scene == scene && p.rmse.count(name))
          dat += csv_number(p.regime) + " " + csv_number(p.rmse.at(name) / p.conventional_rmse) + "\n";
      dat += "\n\n";
      blocks[scene].push_back(block++);
    }
  if (!write_text_atomic(o.base.out + "/sweep.dat", dat, error)) return report_error(error);
  std::string body = "set multiplot layout 1," + std::to_string(o.scenes.size()) +
                     " title 'Moving camera: time-averaged RMSE / double buffering RMSE, by regime'\n"
                     "set xlabel 'conventional frame time / camera interval'\nset logscale x\nset grid\n"
                     "set key top right font ',8' opaque\nset yrange [0:1.6]\n"
                     "set arrow from graph 0, first 1 to graph 1, first 1 nohead dt 2 lc rgb 'gray40'\n";
  for (size_t sc = 0; sc < o.scenes.size(); ++sc) {
    body += "set title '" + o.scenes[sc] + "'\nset ylabel '" + (sc == 0 ? "RMSE ratio" : "") + "'\nplot ";
    const std::vector<int>& bs = blocks[o.scenes[sc]];
    for (size_t k = 0; k < bs.size(); ++k)
      body += (k ? ", " : "") + std::string("'") + o.base.out + "/sweep.dat' index " + std::to_string(bs[k]) +
              " using 1:2 with linespoints lw 2 lt " + std::to_string(k + 1) + " title '" +
              gnuplot_text(short_name(names[k])) + "'";
    body += "\n";
  }
  body += "unset multiplot\n";
  bool png = false;
  if (!plot_png(o.base.out, "sweep", 1200, 480, body, error, &png)) return report_error(error);
  std::printf("bench motion sweep: camera %.3g Hz, %zu points\n", o.base.camera_hz, points.size());
  for (const SweepPoint& p : points) {
    std::printf("  %-8s %-8s regime %5.2f  conventional RMSE %.4f", p.scene.c_str(), p.size.c_str(), p.regime,
                p.conventional_rmse);
    for (const auto& [name, rmse] : p.rmse) std::printf("  %s %.2fx", name.c_str(), rmse / p.conventional_rmse);
    std::printf("\n");
  }
  std::printf("  mean ratio over the sweep:");
  for (const auto& [name, r] : mean_ratio) std::printf("  %s %.2fx", name.c_str(), r);
  if (!best_name.empty())
    std::printf("\n  best setting where the regime is 1 or more: %s (mean %.2fx conventional over %zu points)",
                best_name.c_str(), heavy_ratio[best_name], heavy);
  std::printf("\n  wrote %s/sweep.json%s\n", o.base.out.c_str(), png ? " and sweep.png" : "");
  return 0;
}

}  // namespace frameless::bench
