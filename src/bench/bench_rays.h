// `frameless bench rays`: primary- and shadow-ray throughput of the BVH (and of Embree when built
// with it). Its flags are in tools/bench_rays_command.cpp.
#pragma once
#include <string>

#include "bench/bench_options.h"

namespace frameless::bench {

// The defaults are the command's.
struct RaysOptions {
  ShadowOptions shadows;
  std::string scene = "bunny";
  std::string size = "512x512";
  int threads = 0;
  int reps = 5;
  bool json = false;
  bool no_embree = false;
  bool opaque = false;
  CameraOptions camera;
};

// Runs the benchmark as the command does (output on stdout and, where it has one, in its
// output directory); returns the exit code (2 after a one-line error on stderr).
int run_rays(const RaysOptions& options);

}  // namespace frameless::bench
