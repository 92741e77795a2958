// `frameless bench dynamic`: samples/s against the number of moving objects (tested per ray,
// outside the BVH). Its flags are in tools/bench_dynamic_command.cpp.
#pragma once
#include <string>
#include <vector>

namespace frameless::bench {

// The defaults are the command's.
struct DynamicOptions {
  std::string scene = "default";
  std::vector<int> counts{0, 1, 2, 4, 8, 16, 32, 64, 128};
  std::string size = "256x144";
  int spp = 2;
  int repeats = 3;
  bool json = false;
  std::string out;
};

// Runs the benchmark as the command does (output on stdout and, where it has one, in its
// output directory); returns the exit code (2 after a one-line error on stderr).
int run_dynamic(const DynamicOptions& options);

}  // namespace frameless::bench
