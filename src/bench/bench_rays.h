// `frameless bench rays`: primary- and shadow-ray throughput of the BVH (and of Embree when built
// with it), for one scene or several side by side. Its flags are in tools/bench_rays_command.cpp.
#pragma once
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "bench/bench_options.h"

namespace frameless::bench {

// The defaults are the command's.
struct RaysOptions {
  ShadowOptions shadows;
  std::vector<std::string> scenes = {"bunny"};
  std::string out;  // also write DIR/rays.json, rays.csv and the plot rays.png
  std::string size = "512x512";
  int threads = 0;
  int reps = 5;
  bool json = false;
  bool no_embree = false;
  bool embree_robust = false;  // Embree's scenes with RTC_SCENE_FLAG_ROBUST
  std::string embree_quality = "medium";  // Embree's build quality: low, medium (its default) or high
  bool opaque = false;
  CameraOptions camera;
};

// Runs the benchmark as the command does (output on stdout and, where it has one, in its
// output directory); returns the exit code (2 after a one-line error on stderr).
int run_rays(const RaysOptions& options);

// One scene's measurement (bench_rays.cpp): its JSON object in `result`, and its table on stdout
// unless options.json; the exit code, as run_rays.
int rays_of_scene(const RaysOptions& options, const std::string& spec, nlohmann::ordered_json& result);

}  // namespace frameless::bench
