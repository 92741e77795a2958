// `frameless bench rays` over one scene or several: each measured by rays_of_scene (bench_rays.cpp),
// then, for several, one table of the ratios to Embree; with --out, the runs as DIR/rays.json and
// DIR/rays.csv and the ratios as a bar chart, DIR/rays.png (our Mrays/s without Embree).
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <iterator>
#include <string>
#include <vector>

#include "bench/bench_options.h"
#include "bench/bench_rays.h"
#include "bench/bench_report.h"
#include "core/scenes/scene_load.h"

namespace frameless::bench {
namespace {

// A kind of ray as the runs report it: how many were traced, our Mrays/s key and the ratio to
// Embree's call.
struct RayKind {
  const char* name;     // CSV and table
  const char* label;    // plot legend
  const char* count;    // the number of rays traced
  const char* mrays;    // our key, "_1t" appended for one thread
  const char* ratio;    // the key in "embree", "_1t" appended for one thread
};
constexpr RayKind kKinds[] = {
    {"primary", "primary / rtcIntersect1", "primary_rays", "primary_mrays_per_s", "ratio_primary_vs_intersect1"},
    {"packets", "packets of 8 / rtcIntersect8", "primary_rays", "primary_packet_mrays_per_s",
     "ratio_primary_packet_vs_packet8"},
    {"shadow", "shadow / rtcOccluded1", "shadow_rays", "shadow_mrays_per_s", "ratio_shadow_vs_occluded1"},
    {"bounce", "bounce / rtcIntersect1", "bounce_rays", "bounce_mrays_per_s", "ratio_bounce_vs_intersect1"},
    {"bounce_shadow", "bounce shadow / rtcOccluded1", "bounce_shadow_rays", "bounce_shadow_mrays_per_s",
     "ratio_bounce_shadow_vs_occluded1"},
};

bool has_rays(const nlohmann::ordered_json& run, const RayKind& k) {
  return run.contains(k.count) && run[k.count].get<double>() > 0.0;
}

// A run's figure, NaN when it has none: no rays of that kind (a rate over no rays measures only
// the loop), no Embree, or a time too short to give a finite rate.
double figure(const nlohmann::ordered_json& run, const RayKind& k, bool ratio, bool one_thread) {
  if (!has_rays(run, k)) return NAN;
  const std::string suffix = one_thread ? "_1t" : "";
  const nlohmann::ordered_json* at = &run;
  std::string key = std::string(k.mrays) + suffix;
  if (ratio) {
    if (!run.contains("embree")) return NAN;
    at = &run["embree"];
    key = std::string(k.ratio) + suffix;
  }
  const double v = at->contains(key) && (*at)[key].is_number() ? (*at)[key].get<double>() : NAN;
  return std::isfinite(v) ? v : NAN;
}

// Each scene's name for tables and plots: a model's file name without its folder and extension,
// the whole spec where two would share one; tabs and line breaks (the plot data's separators)
// become spaces.
std::vector<std::string> scene_names(const std::vector<nlohmann::ordered_json>& runs) {
  std::vector<std::string> specs, names;
  for (const nlohmann::ordered_json& run : runs) {
    specs.push_back(run["scene"].get<std::string>());
    const std::filesystem::path p(specs.back());
    names.push_back(p.has_extension() ? p.stem().string() : specs.back());
  }
  for (size_t i = 0; i < names.size(); ++i) {
    const bool shared = std::count(names.begin(), names.end(), names[i]) > 1;
    std::string name = shared ? specs[i] : names[i];
    for (char& c : name)
      if (c == '\t' || c == '\n' || c == '\r') c = ' ';
    names[i] = name;
  }
  return names;
}

// What the summary and the plot add to Embree's name: which of its modes and build qualities was
// measured (nothing for its defaults).
std::string embree_mode(const RaysOptions& a) {
  std::string mode = a.embree_robust ? "robust mode" : "";
  if (a.embree_quality != "medium") mode += (mode.empty() ? "" : ", ") + a.embree_quality + " build quality";
  return mode.empty() ? "" : " (" + mode + ")";
}

// The bar chart of every run's figures by kind of ray, one panel per thread count.
std::string plot_body(const std::string& dat, bool ratios, int threads, const std::string& mode) {
  // Scene names as written (a model's underscores are no subscripts).
  std::string body = "set termoption noenhanced\nset style data histograms\nset style histogram clustered gap 1\n";
  body += "set style fill solid 0.85 border -1\nset datafile missing '?'\nset datafile separator tab\n";
  // The ratios' range always holds 1, so the line at 1 stays inside each panel.
  body += std::string("set grid ytics\nset key outside right top vertical\nset xtics nomirror\n") +
          (ratios ? "set yrange [0:1.2<*]\n" : "set yrange [0:*]\n");
  body += ratios ? "set ylabel 'ours / Embree (above 1: ours faster)'\n" : "set ylabel 'Mrays/s'\n";
  if (ratios) body += "set arrow 1 from graph 0, first 1 to graph 1, first 1 nohead lw 2 dt 2 lc rgb 'black'\n";
  const int panels = threads > 1 ? 2 : 1;
  if (panels > 1) body += "set multiplot layout 2,1\n";
  for (int p = 0; p < panels; ++p) {
    const int column0 = 2 + p * int(std::size(kKinds));
    body += "set title '" + std::string(p == 0 ? "1 thread" : std::to_string(threads) + " threads") +
            (ratios ? ": ratio to Embree 3" + mode + " on the same rays" : std::string(": Mrays/s (no Embree comparison)")) + "'\n";
    body += "plot";
    for (size_t k = 0; k < std::size(kKinds); ++k)
      body += std::string(k ? "," : "") + " '" + dat + "' using " + std::to_string(column0 + int(k)) +
              (k == 0 ? ":xtic(1)" : "") + " title '" + (ratios ? kKinds[k].label : kKinds[k].name) + "'";
    body += "\n";
  }
  if (panels > 1) body += "unset multiplot\n";
  return body;
}

// DIR/rays.csv, rays.dat and rays.png, then rays.json last: the last run's report is replaced
// whole, never mixed with this one's (its plot and report go first).
int write_outputs(const RaysOptions& a, const std::vector<nlohmann::ordered_json>& runs, bool ratios, int threads,
                  bool& png) {
  std::string error;
  std::error_code ignored;
  for (const char* old : {"rays.json", "rays.png"}) std::filesystem::remove(a.out + "/" + old, ignored);
  const std::vector<std::string> names = scene_names(runs);
  CsvTable csv;
  csv.header = {"scene", "kind", "rays", "mrays_per_s_1t", "mrays_per_s", "ratio_to_embree_1t", "ratio_to_embree"};
  std::string dat = "# scene, then by kind of ray (primary packets shadow bounce bounce_shadow): 1 thread, then " +
                    std::to_string(threads) + " threads; " + (ratios ? "ratios to Embree" : "Mrays/s") + "\n";
  for (size_t r = 0; r < runs.size(); ++r) {
    const nlohmann::ordered_json& run = runs[r];
    for (const RayKind& k : kKinds)
      csv.rows.push_back({names[r], k.name, csv_number(run.value(k.count, 0.0)), csv_number(figure(run, k, false, true)),
                          csv_number(figure(run, k, false, false)), csv_number(figure(run, k, true, true)),
                          csv_number(figure(run, k, true, false))});
    dat += gnuplot_tic_text(names[r]);  // a tic label is a format too; tab-separated columns
    for (const bool one : {true, false})
      for (const RayKind& k : kKinds) {
        const double v = figure(run, k, ratios, one);
        dat += "\t" + (std::isfinite(v) ? csv_number(v) : std::string("?"));
      }
    dat += "\n";
  }
  nlohmann::json settings = {{"scenes", a.scenes}, {"size", a.size}, {"threads", threads},
                                   {"reps", a.reps}, {"opaque", a.opaque}, {"embree", ratios},
                                   {"embree_robust", a.embree_robust && ratios}};
  if (ratios) settings["embree_quality"] = a.embree_quality;
  nlohmann::ordered_json j = bench_header("rays", nullptr, "", settings);
  j["runs"] = runs;  // each as --json prints it for one scene
  if (!write_text_atomic(a.out + "/rays.csv", csv.text(), error) ||
      !write_text_atomic(a.out + "/rays.dat", dat, error))
    return report_error(error);
  png = false;
  if (!plot_png(a.out, "rays", 1100, threads > 1 ? 700 : 380, plot_body(a.out + "/rays.dat", ratios, threads, embree_mode(a)), error, &png))
    return report_error(error);
  j["outputs"] = {{"plot", png ? "rays.png" : ""}, {"data", "rays.dat"}, {"table", "rays.csv"}};
  if (!write_json(a.out + "/rays.json", j, error)) return report_error(error);
  return 0;
}

// Several scenes: the ratios side by side, one row per scene.
void print_summary(const std::vector<nlohmann::ordered_json>& runs, bool ratios, int threads, const std::string& mode) {
  const std::string columns = threads > 1 ? "1 thread / " + std::to_string(threads) + " threads" : "1 thread";
  std::printf("\n%s, %s:\n%-22s", ratios ? ("ours / Embree" + mode).c_str() : "Mrays/s", columns.c_str(), "scene");
  for (const RayKind& k : kKinds) std::printf(" %15s", k.name);
  std::printf("\n");
  const std::vector<std::string> names = scene_names(runs);
  for (size_t r = 0; r < runs.size(); ++r) {
    std::printf("%-22s", names[r].c_str());
    for (const RayKind& k : kKinds) {
      const double one = figure(runs[r], k, ratios, true), many = figure(runs[r], k, ratios, false);
      if (!has_rays(runs[r], k))
        std::printf(" %15s", "no rays");
      else if (threads > 1)
        std::printf(" %7.2f /%6.2f", one, many);
      else
        std::printf(" %15.2f", one);
    }
    std::printf("\n");
  }
}

}  // namespace

int run_rays(const RaysOptions& a) {
  std::string error;
  int width = 0, height = 0;
  // The arguments, the model files named and the output folder are checked before the first
  // scene's run (a built-in name's typo is found at its turn).
  if (a.scenes.empty()) return report_error("bench rays: no scene given");
  if (!parse_size(a.size, width, height, error)) return report_error(error);
  if (!valid_threads(a.threads, error)) return report_error(error);
  if (a.reps < 1 || a.reps > 1000) return report_error("--reps: must be between 1 and 1000");
  if (a.embree_quality != "low" && a.embree_quality != "medium" && a.embree_quality != "high")
    return report_error("--embree-quality: '" + a.embree_quality + "' is not low, medium or high");
  for (const std::string& spec : a.scenes)
    if (is_scene_file(spec) && !std::filesystem::is_regular_file(spec)) return report_error(spec + ": no such file");
  if (!a.out.empty() && !prepare_out_dir(a.out, error)) return report_error(error);
  const int threads = a.threads > 0 ? a.threads : hardware_threads();
  std::vector<nlohmann::ordered_json> runs;
  for (size_t i = 0; i < a.scenes.size(); ++i) {
    if (i > 0 && !a.json) std::printf("\n");
    nlohmann::ordered_json run;
    if (const int rc = rays_of_scene(a, a.scenes[i], run); rc != 0) return rc;
    runs.push_back(std::move(run));
  }
  bool ratios = true;
  for (const nlohmann::ordered_json& run : runs) ratios = ratios && run.contains("embree");
  bool png = false;
  if (!a.out.empty())
    if (const int rc = write_outputs(a, runs, ratios, threads, png); rc != 0) return rc;
  if (a.json) {
    nlohmann::ordered_json all;
    all["runs"] = runs;
    std::printf("%s\n", (runs.size() == 1 ? runs[0] : all).dump().c_str());
    return 0;
  }
  if (runs.size() > 1) print_summary(runs, ratios, threads, embree_mode(a));
  if (!a.out.empty())
    std::printf("wrote %s/rays.json, rays.csv, rays.dat%s\n", a.out.c_str(), png ? " and rays.png" : "");
  return 0;
}

}  // namespace frameless::bench
