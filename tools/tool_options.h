// Flags of the options shared by several commands (camera, shadows); main thread only. The
// options themselves, the size and thread checks and scene loading live in src/bench.
#pragma once
#include <CLI/CLI.hpp>

#include "bench/bench_options.h"

namespace frameless::cli {

using bench::CameraOptions;
using bench::hardware_threads;
using bench::load_scene_checked;
using bench::load_scene_or_report;
using bench::parse_size;
using bench::quiet_rank;
using bench::report_error;
using bench::ShadowOptions;
using bench::show_progress;
using bench::thread_parallel_for;
using bench::valid_threads;

// Creates the folder an output file goes to when missing and checks it can be written (before
// minutes of rendering); false with a one-line `error` otherwise.
bool output_dir_ok(const std::string& path, std::string& error);

// --eye/--look/--up x,y,z and --fov DEG into `camera`.
void add_camera_flags(CLI::App& app, CameraOptions& camera);

// --shadows, --shadow-samples, --transparent-shadows, --accel and --integrator into `shadows`.
void add_shadow_flags(CLI::App& app, ShadowOptions& shadows);

}  // namespace frameless::cli
