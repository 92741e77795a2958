// `frameless bench build`: BVH build time, serial and parallel, against Embree's with 1 and N
// threads. Its flags are in tools/bench_build_command.cpp.
#pragma once
#include <string>
#include <vector>

namespace frameless::bench {

// The defaults are the command's.
struct BuildOptions {
  std::vector<std::string> scenes{"bunny", "spheres:1000000", "room", "default"};
  int threads = 0;
  int reps = 5;
  bool json = false;
  bool no_embree = false;
  bool shuffle = false;
};

// Runs the benchmark as the command does (output on stdout and, where it has one, in its
// output directory); returns the exit code (2 after a one-line error on stderr).
int run_build(const BuildOptions& options);

}  // namespace frameless::bench
