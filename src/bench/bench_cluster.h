// `frameless bench cluster`: frameless across Open MPI ranks against one process (starts mpirun
// jobs of this executable). Its flags are in tools/bench_cluster_command.cpp.
#pragma once
#include <string>

#include "bench/bench_options.h"
#include "bench/cluster_join.h"

namespace frameless::bench {

// The defaults are the command's.
struct ClusterBenchOptions {
  ClusterJoinOptions cluster;
  ShadowOptions shadows;
  std::string scene = "default";
  std::string size = "640x360";
  int threads = 1;
  int clients = 2;
  double seconds = 2.0;
  std::string mode = "frameless";
  bool json = false;
  bool one = false;
};

// Runs the benchmark as the command does (output on stdout and, where it has one, in its
// output directory); returns the exit code (2 after a one-line error on stderr).
int run_cluster(const ClusterBenchOptions& options);

}  // namespace frameless::bench
