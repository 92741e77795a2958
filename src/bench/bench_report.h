// Shared helpers of the `frameless bench` benchmarks: what ran where (machine, build, scene,
// settings), JSON and CSV outputs written atomically, gnuplot plots to PNG; main thread only.
#pragma once
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "core/scene/scene.h"
#include "frameless/engine_config.h"

namespace frameless::bench {

// CPU model, hardware threads, memory, kernel and the load average when the benchmark started
// (a shared machine's load explains much of the run-to-run spread).
nlohmann::json describe_machine();
// Version, git commit (and whether the tree was dirty), compiler, optimisation, vector ISA.
nlohmann::json describe_build();
// Scene spec and name, primitive counts, lights, materials, BVH statistics.
nlohmann::json describe_scene(const Scene& scene, const std::string& spec);
// The three above plus the benchmark name and its settings, as the head of every NAME.json.
nlohmann::json bench_header(const std::string& name, const Scene* scene, const std::string& spec,
                            const nlohmann::json& settings);

// Version string plus the renderer fingerprint: the code part of reference-cache keys.
std::string code_version(const Scene& scene);

// Creates DIR if needed and checks it is writable; false with a one-line message.
bool prepare_out_dir(const std::string& dir, std::string& error);
// Writes text through a temporary file and a rename.
bool write_text_atomic(const std::string& path, const std::string& text, std::string& error);
bool write_json(const std::string& path, const nlohmann::json& j, std::string& error);

// A CSV table: a header row and rows of cells (numbers formatted with csv_number).
struct CsvTable {
  std::vector<std::string> header;
  std::vector<std::vector<std::string>> rows;
  std::string text() const;
};
std::string csv_number(double v);  // %.6g; "nan"/"inf" spelled out; used for JSON-less tables too

// `text` for a single-quoted gnuplot string (a quote is doubled), e.g. a run's name as a title.
std::string gnuplot_text(const std::string& text);
// A tic label is also a format string: `text` (already gnuplot_text) with each % doubled.
std::string gnuplot_tic_text(const std::string& text);

// Writes DIR/NAME.gp (pngcairo terminal and output lines are added here, `body` holds the rest)
// and runs gnuplot on it, producing DIR/NAME.png. Without gnuplot it prints one message naming
// the script and returns true (the benchmark still succeeds); false only if a file cannot be
// written. *png_written tells whether the PNG exists.
bool plot_png(const std::string& dir, const std::string& name, int width, int height,
              const std::string& body, std::string& error, bool* png_written = nullptr);
bool gnuplot_found();

// Progress line on stderr ("bench NAME: what") only when show_progress().
void bench_progress(const std::string& bench, const std::string& what);

// Resident set size and its peak (VmRSS, VmHWM from /proc/self/status), bytes; 0 if unknown.
double rss_bytes();
double peak_rss_bytes();
// Process CPU seconds (user + system, all threads).
double process_cpu_seconds();
// Runs a shell command (a bench-only peer), its stdout and stderr into `output`; its exit status,
// or -1 when it could not run or ended by a signal.
int run_command(const std::string& command, std::string& output);
// Sleeps the calling thread for `seconds`.
void sleep_s(double seconds);
// One image of `s` rendered on the calling thread alone; cpu_seconds receives that thread's CPU
// time (robust on a shared machine). Returns the RGB floats.
std::vector<float> render_one_thread(const Scene& s, int w, int h, int spp, double& cpu_seconds);

// Median of the non-NaN values (mean of the middle two for an even count); NaN when none.
double median(std::vector<double> values);

// Least-squares line y = a + b x; returns b and sets *intercept and *r2 when given.
double fit_slope(const std::vector<double>& x, const std::vector<double>& y,
                 double* intercept = nullptr, double* r2 = nullptr);

}  // namespace frameless::bench
