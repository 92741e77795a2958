// `frameless bench patches`: spline patches traced directly against the same patches tessellated,
// and Broyden's iteration counts. Its flags are in tools/bench_patches_command.cpp.
#pragma once
#include <string>
#include <vector>

#include "bench/bench_options.h"

namespace frameless::bench {

// The defaults are the command's.
struct PatchesOptions {
  ShadowOptions shadows;
  std::string scene = "teapot";
  std::string size = "320x240";
  int spp = 2;
  int repeats = 3;
  std::vector<int> levels{4, 8, 16, 32, 64};
  bool json = false;
  std::string out;
};

// Runs the benchmark as the command does (output on stdout and, where it has one, in its
// output directory); returns the exit code (2 after a one-line error on stderr).
int run_patches(const PatchesOptions& options);

}  // namespace frameless::bench
