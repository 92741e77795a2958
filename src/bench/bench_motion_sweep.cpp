#include "bench/bench_motion_sweep.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <map>

#include <nlohmann/json.hpp>

#include "bench/bench_report.h"
#include "bench/common_options.h"

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
  for (const std::string& scene : o.scenes)
    for (const std::string& size : o.sizes) {
      int w = 0, h = 0;
      if (!parse_size(size, w, h, error)) return report_error("--sweep-sizes: " + error);
      MotionOptions m = o.base;
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
  nlohmann::json j = bench_header("motion-sweep", nullptr, "", {{"scenes", o.scenes}, {"sizes", o.sizes},
                                                                {"camera_hz", o.base.camera_hz},
                                                                {"threads", o.base.threads}});
  j["regime"] = "conventional frame time / camera input interval";
  j["points"] = rows;
  j["mean_ratio_to_conventional"] = mean_ratio;
  if (!write_json(o.base.out + "/sweep.json", j, error) ||
      !write_text_atomic(o.base.out + "/sweep.csv", csv.text(), error))
    return report_error(error);

  // One line per setting: ratio to double buffering against the regime, one point style per scene.
  std::string dat;
  std::vector<std::string> names;
  for (const auto& [name, r] : mean_ratio) names.push_back(name);
  for (const std::string& name : names) {
    dat += "# " + name + "\n";
    for (const SweepPoint& p : points)
      if (p.rmse.count(name))
        dat += csv_number(p.regime) + " " + csv_number(p.rmse.at(name) / p.conventional_rmse) + " \"" +
               p.scene + " " + p.size + "\"\n";
    dat += "\n\n";
  }
  if (!write_text_atomic(o.base.out + "/sweep.dat", dat, error)) return report_error(error);
  std::string body =
      "set title 'Moving camera: time-averaged RMSE against double buffering, by regime'\n"
      "set xlabel 'regime: conventional frame time / camera input interval (log)'\n"
      "set ylabel 'RMSE / double buffering RMSE'\nset logscale x\nset grid\n"
      "set key outside right font ',8'\nset yrange [0:*]\n"
      "set arrow from graph 0, first 1 to graph 1, first 1 nohead dt 2 lc rgb 'gray40'\nplot ";
  for (size_t k = 0; k < names.size(); ++k)
    body += (k ? ", " : "") + std::string("'") + o.base.out + "/sweep.dat' index " + std::to_string(k) +
            " using 1:2 with linespoints lw 2 title '" + names[k] + "'";
  body += "\n";
  bool png = false;
  if (!plot_png(o.base.out, "sweep", 1000, 460, body, error, &png)) return report_error(error);
  std::printf("bench motion sweep: camera %.3g Hz, %zu points\n", o.base.camera_hz, points.size());
  for (const SweepPoint& p : points) {
    std::printf("  %-8s %-8s regime %5.2f  conventional RMSE %.4f", p.scene.c_str(), p.size.c_str(), p.regime,
                p.conventional_rmse);
    for (const auto& [name, rmse] : p.rmse) std::printf("  %s %.2fx", name.c_str(), rmse / p.conventional_rmse);
    std::printf("\n");
  }
  std::printf("  mean ratio over the sweep:");
  for (const auto& [name, r] : mean_ratio) std::printf("  %s %.2fx", name.c_str(), r);
  std::printf("\n  wrote %s/sweep.json%s\n", o.base.out.c_str(), png ? " and sweep.png" : "");
  return 0;
}

}  // namespace frameless::bench
