// `frameless bench instances`: the cost of moving instances (copy, refit or rebuild of the top
// level) and the rays' speed after. Its flags are in tools/bench_instances_command.cpp.
#pragma once
#include <string>

namespace frameless::bench {

// The defaults are the command's.
struct InstancesOptions {
  std::string scene = "sunflowers";
  int reps = 5;
  int size = 256;
  bool json = false;
};

// Runs the benchmark as the command does (output on stdout and, where it has one, in its
// output directory); returns the exit code (2 after a one-line error on stderr).
int run_instances(const InstancesOptions& options);

}  // namespace frameless::bench
