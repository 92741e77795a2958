// `frameless bench gi`: light that bounces, measured. The frameless path tracer against a
// converged reference over wall time, next to Blender's Cycles (bench-only peer, skipped with a
// message when absent) on the same scene, size and threads: agreement of the converged images
// and error at Cycles' own render times for 16, 64 and 256 samples per pixel. Its flags are in
// tools/bench_gi_command.cpp.
#pragma once
#include <string>
#include <vector>

#include "bench/bench_options.h"

namespace frameless::bench {

// The defaults are the command's.
struct GiOptions {
  ShadowOptions shadows;
  std::string scene = "cornell";
  std::string size = "128x128";
  std::string out;
  std::string cache;
  int threads = 0;
  int ref_spp = 4096;
  std::vector<int> spp = {16, 64, 256};  // Cycles' sample counts: the time points compared
  double seconds = 0;                    // frameless run without Cycles (0: 10 s)
  bool no_cycles = false;
  bool quick = false;
};

// Runs the benchmark as the command does (output on stdout and in its output directory);
// returns the exit code (2 after a one-line error on stderr).
int run_gi(const GiOptions& options);

}  // namespace frameless::bench
