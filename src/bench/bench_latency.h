// `frameless bench latency`: from a camera change to 50/95/100 % of the pixels showing it, against
// the ideal. Its flags are in tools/bench_latency_command.cpp.
#pragma once
#include <string>
#include <vector>

#include "bench/bench_options.h"

namespace frameless::bench {

// The defaults are the command's.
struct LatencyOptions {
  ShadowOptions shadows;
  std::string scene = "default";
  std::string size = "320x240";
  std::string out;
  int threads = 0;
  std::vector<double> percents = {0.1, 1, 10, 50};
  int repeats = 3;
  double refresh = 240;
  bool quick = false;
};

// Runs the benchmark as the command does (output on stdout and, where it has one, in its
// output directory); returns the exit code (2 after a one-line error on stderr).
int run_latency(const LatencyOptions& options);

}  // namespace frameless::bench
