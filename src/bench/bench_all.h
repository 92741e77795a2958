// `frameless bench all`: error, motion, latency, scaling and scale into one directory, as child
// processes of this executable. Its flags are in tools/bench_all_command.cpp.
#pragma once
#include <string>

namespace frameless::bench {

// The defaults are the command's.
struct AllOptions {
  std::string out;
  std::string scene = "default";
  bool quick = false;
  double max_n = 1e6;
  std::string cache;
};

// Runs the benchmark as the command does (output on stdout and, where it has one, in its
// output directory); returns the exit code (2 after a one-line error on stderr).
int run_all(const AllOptions& options);

}  // namespace frameless::bench
