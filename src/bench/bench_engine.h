// `frameless bench engine`: frameless vs conventional samples/s, display CPU, camera-change
// latency. Its flags are in tools/bench_engine_command.cpp.
#pragma once
#include <string>
#include <vector>

#include "bench/bench_options.h"
#include "frameless/engine_config.h"

namespace frameless::bench {

// The defaults are the command's.
struct EngineBenchOptions {
  ShadowOptions shadows;
  std::string scene = "default";
  std::string size = "640x360";
  int threads = 0;
  double seconds = 2.0;
  int repeats = 3;
  // The reprojection budget measured beside the unlimited default, a fraction of one core.
  double budget = kBenchReprojectBudget;
  // Further image sizes (WxH) at which the display thread's CPU is measured during the move with
  // reprojection, beside 1280x720: where the 25 %-of-a-core goal holds on this machine.
  std::vector<std::string> moving_sizes;
  // EngineConfig::render_nice of every run.
  int render_nice = kDefaultRenderNice;
  bool json = false;
};

// Runs the benchmark as the command does (output on stdout and, where it has one, in its
// output directory); returns the exit code (2 after a one-line error on stderr).
int run_engine(const EngineBenchOptions& options);

}  // namespace frameless::bench
