// `frameless bench scaling`: samples/s and Mrays/s vs threads, oversubscribed too, and the
// efficiency vs linear. Its flags are in tools/bench_scaling_command.cpp.
#pragma once
#include <string>
#include <vector>

#include "bench/bench_options.h"

namespace frameless::bench {

// The defaults are the command's.
struct ScalingOptions {
  ShadowOptions shadows;
  std::string scene = "default";
  std::string size = "320x240";
  std::string out;
  std::vector<int> threads;  // empty: 1..cores, 2x and 4x cores
  double seconds = 2;
  bool quick = false;
};

// Runs the benchmark as the command does (output on stdout and, where it has one, in its
// output directory); returns the exit code (2 after a one-line error on stderr).
int run_scaling(const ScalingOptions& options);

}  // namespace frameless::bench
