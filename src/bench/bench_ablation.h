// `frameless bench ablation`: each skip of the per-sample path (and variance tracking, adaptive
// sampling) off vs on, time saved and image unchanged. Its flags are in
// tools/bench_ablation_command.cpp.
#pragma once
#include <string>

namespace frameless::bench {

// The defaults are the command's.
struct AblationOptions {
  std::string scene = "default";
  std::string size = "320x180";
  int threads = 0;
  int spp = 8;
  int repeats = 5;
  double seconds = 1.0;
  bool json = false;
  std::string out;
};

// Runs the benchmark as the command does (output on stdout and, where it has one, in its
// output directory); returns the exit code (2 after a one-line error on stderr).
int run_ablation(const AblationOptions& options);

}  // namespace frameless::bench
