// `frameless bench shadows`: cost and accuracy of hard, soft, area-sampled and transparent shadows,
// and of the hemisphere ambient. Its flags are in tools/bench_shadows_command.cpp.
#pragma once
#include <string>
#include <vector>

namespace frameless::bench {

// The defaults are the command's.
struct ShadowBenchOptions {
  std::vector<std::string> scenes{"default", "balls"};
  std::string size = "256x144";
  int spp = 4;
  int repeats = 5;
  int reference_samples = 64;
  float light_radius = 0.5f;
  bool json = false;
  std::string out;
};

// Runs the benchmark as the command does (output on stdout and, where it has one, in its
// output directory); returns the exit code (2 after a one-line error on stderr).
int run_shadows(const ShadowBenchOptions& options);

}  // namespace frameless::bench
