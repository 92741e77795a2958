// `frameless bench accel`: the BVH against the hybrid grid per scene (build time, memory, Mrays/s)
// and what auto chooses. Its flags are in tools/bench_accel_command.cpp.
#pragma once
#include <string>
#include <vector>

namespace frameless::bench {

// The defaults are the command's.
struct AccelOptions {
  std::vector<std::string> scenes{"default", "bunny", "teapot", "spheres:100000", "room"};
  std::string size = "320x240";
  int repeats = 3;
  bool json = false;
  std::string out;
};

// Runs the benchmark as the command does (output on stdout and, where it has one, in its
// output directory); returns the exit code (2 after a one-line error on stderr).
int run_accel(const AccelOptions& options);

}  // namespace frameless::bench
