// `frameless bench scale`: spheres:N up to 3.5e7 (build time, memory, samples/s, sub-linear ray
// cost). Its flags are in tools/bench_scale_command.cpp.
#pragma once
#include <string>
#include <vector>

#include "core/scenes/builtin_scenes.h"

namespace frameless::bench {

// The defaults are the command's.
struct ScaleOptions {
  std::string out;
  std::string size = "160x120";
  int threads = 0;
  double max_n = double(kMaxRandomSpheres);
  std::vector<double> ns;  // empty: decades from 1e3 plus 3.5e7, capped by --max-n
  int spp = 4;
  bool quick = false;
};

// Runs the benchmark as the command does (output on stdout and, where it has one, in its
// output directory); returns the exit code (2 after a one-line error on stderr).
int run_scale(const ScaleOptions& options);

}  // namespace frameless::bench
