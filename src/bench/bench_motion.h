// `frameless bench motion`: a moving camera, every displayed image's error vs the converged image
// for that instant. Its flags are in tools/bench_motion_command.cpp.
#pragma once
#include <string>
#include <vector>

#include "bench/bench_options.h"
#include "frameless/engine_config.h"

namespace frameless::bench {

// The defaults are the command's.
struct MotionOptions {
  ShadowOptions shadows;
  std::string scene = "default";
  std::string size = "320x240";
  std::string out;
  std::string cache;
  int threads = 0;
  double move_seconds = 3;    // length of the camera move
  double hold_seconds = 1;    // still camera before the move (warm-up)
  double tail_seconds = 0.5;  // still camera after the move
  double camera_hz = 10;      // camera input rate: poses published per second
  double refresh = 30;
  double orbit = 40;    // degrees orbited over the move
  double dolly = 0.85;  // eye distance factor over the move
  std::vector<double> alphas = {0.25, 0.5, 1.0};
  std::vector<double> percents = {0.1, 1, 10};
  double alpha = 0.5;  // default setting (the headline frameless value)
  double percent = 1;
  int ref_spp = 32;
  int repeats = 2;
  // The headline motion settings (reprojection + temporal weights) again with their samples
  // capped at these fractions of conventional's measured samples/s: the samples frameless needs
  // for the error of double buffering. Empty: skipped.
  std::vector<double> sample_fractions = {0.5, 0.25, 0.125};
  // The budgeted row's reprojection budget, a fraction of one core (BlendConfig::reproject_budget).
  double budget = kBenchReprojectBudget;
  // EngineConfig::render_nice of every run.
  int render_nice = kDefaultRenderNice;
  bool quick = false;
};

// Runs the benchmark as the command does (output on stdout and, where it has one, in its
// output directory); returns the exit code (2 after a one-line error on stderr).
int run_motion(const MotionOptions& options);

}  // namespace frameless::bench
