// `frameless bench error`: static convergence, the displayed image's error vs time and samples. Its
// flags are in tools/bench_error_command.cpp.
#pragma once
#include <string>

#include "bench/bench_options.h"

namespace frameless::bench {

// The defaults are the command's.
struct ErrorOptions {
  ShadowOptions shadows;
  std::string scene = "default";
  std::string size = "320x240";
  std::string out;
  std::string cache;
  int threads = 0;
  double seconds = 10;
  double refresh = 30;
  double alpha = 0.5;
  int ref_spp = 512;
  bool quick = false;
};

// Runs the benchmark as the command does (output on stdout and, where it has one, in its
// output directory); returns the exit code (2 after a one-line error on stderr).
int run_error(const ErrorOptions& options);

}  // namespace frameless::bench
