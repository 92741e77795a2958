// `frameless bench all`: runs error, motion, latency, scaling and scale with modest defaults into
// one directory (each as a child process of this executable, so memory and failures stay apart)
// and writes DIR/summary.json with the headline figures.
#include "bench/bench_all.h"

#include <sys/wait.h>
#include <unistd.h>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <memory>

#include "bench/bench_options.h"
#include "bench/bench_report.h"

namespace frameless::bench {
namespace {

// Runs this executable with `args`; returns its exit status (or -1).
int run_self(const std::vector<std::string>& args) {
  std::vector<char*> argv;
  static char exe[] = "/proc/self/exe";
  argv.push_back(exe);
  for (const std::string& a : args) argv.push_back(const_cast<char*>(a.c_str()));
  argv.push_back(nullptr);
  std::fflush(stdout);
  std::fflush(stderr);
  const pid_t pid = fork();
  if (pid < 0) return -1;
  if (pid == 0) {
    execv("/proc/self/exe", argv.data());
    _exit(127);
  }
  int status = 0;
  if (waitpid(pid, &status, 0) < 0) return -1;
  return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

nlohmann::json read_json(const std::string& path) {
  std::ifstream in(path);
  if (!in) return nullptr;
  try {
    return nlohmann::json::parse(in);
  } catch (...) {
    return nullptr;
  }
}

}  // namespace

int run_all(const AllOptions& a) {
  std::string error;
  if (!(a.max_n >= 1 && a.max_n <= 35e6)) return report_error("--max-n: must be in [1, 35000000]");
  if (!prepare_out_dir(a.out, error)) return report_error(error);
  std::vector<std::string> common = {"--out", a.out};
  if (a.quick) common.push_back("--quick");
  auto with = [&](std::vector<std::string> v, bool scene, bool cache) {
    if (scene) v.insert(v.begin() + 2, a.scene);
    v.insert(v.end(), common.begin(), common.end());
    if (cache && !a.cache.empty()) v.insert(v.end(), {"--cache", a.cache});
    return v;
  };
  char max_n[32];
  std::snprintf(max_n, sizeof max_n, "%.0f", a.max_n);
  const std::vector<std::pair<std::string, std::vector<std::string>>> runs = {
      {"error", with({"bench", "error"}, true, true)},
      {"motion", with({"bench", "motion"}, true, true)},
      {"latency", with({"bench", "latency"}, true, false)},
      {"scaling", with({"bench", "scaling"}, true, false)},
      {"scale", with({"bench", "scale", "--max-n", max_n}, false, false)},
      {"gi", with({"bench", "gi"}, false, true)},  // its own scene: the Cornell box
  };
  nlohmann::json summary =
      bench_header("all", nullptr, a.scene, {{"quick", a.quick}, {"max_n", a.max_n}});
  int failures = 0;
  for (const auto& [name, args] : runs) {
    bench_progress("all", name);
    const int rc = run_self(args);
    summary["status"][name] = rc;
    if (rc != 0) {
      ++failures;
      std::fprintf(stderr, "frameless: bench %s failed (exit %d); going on\n", name.c_str(), rc);
    }
  }
  // Headline figures from each report.
  const nlohmann::json m = read_json(a.out + "/motion.json");
  if (m.is_object()) {
    summary["motion_time_avg_rmse"] = m.value("time_avg_rmse", nlohmann::json());
    summary["motion_frameless_setting"] = m.value("frameless_setting", "");
  }
  const nlohmann::json e = read_json(a.out + "/error.json");
  if (e.is_object() && e.contains("modes")) {
    for (const auto& [mode, v] : e["modes"].items())
      if (v.contains("final")) summary["error_final_rmse"][mode] = v["final"]["rmse"];
    if (e.contains("adaptive_time_to_error_speedup"))
      summary["adaptive_time_to_error_speedup"] = e["adaptive_time_to_error_speedup"];
  }
  const nlohmann::json g = read_json(a.out + "/gi.json");
  if (g.is_object() && g.contains("frameless"))
    for (const auto& [name, v] : g["frameless"].items())
      summary["gi_rmse_vs_cycles"][name] = v.value("at_cycles_times", nlohmann::json());
  const nlohmann::json l = read_json(a.out + "/latency.json");
  if (l.is_object()) summary["latency"] = l.value("results", nlohmann::json());
  const nlohmann::json s = read_json(a.out + "/scaling.json");
  if (s.is_object() && s.contains("points")) {
    for (const auto& p : s["points"]) {
      summary["scaling_efficiency"][std::to_string(p["threads"].get<int>())] = p["efficiency"];
      summary["scaling_cpu_efficiency"][std::to_string(p["threads"].get<int>())] =
          p["cpu_efficiency"];
    }
  }
  const nlohmann::json sc = read_json(a.out + "/scale.json");
  if (sc.is_object()) summary["scale_fit"] = sc.value("fit", nlohmann::json());
  if (!write_json(a.out + "/summary.json", summary, error)) return report_error(error);
  std::printf("bench all: wrote %s/summary.json (%d of %zu benchmarks failed)\n", a.out.c_str(),
              failures, runs.size());
  return failures ? 1 : 0;
}

}  // namespace frameless::bench
