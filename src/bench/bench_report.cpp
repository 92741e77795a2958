// Shared helpers of the benchmarks: descriptions, atomic JSON/CSV, gnuplot, memory and CPU probes.
#include "bench/bench_report.h"

#include "frameless/cpu_clock.h"
#include "frameless/tile_render.h"

#include <sys/utsname.h>
#include <sys/wait.h>

#include <time.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <thread>

#include "bench/bench_options.h"
#include "display/atomic_file.h"
#include "display/manifest.h"
#include "frameless/reference_cache.h"

#ifndef FRAMELESS_VERSION
#define FRAMELESS_VERSION "unknown"
#endif

namespace frameless::bench {
namespace {

// First line of `cmd`'s output, or "" (used for git; its errors go to /dev/null).
std::string command_line_output(const std::string& cmd) {
  FILE* p = popen(cmd.c_str(), "r");
  if (!p) return "";
  char buf[256] = {0};
  std::string out;
  if (std::fgets(buf, sizeof buf, p)) out = buf;
  pclose(p);
  while (!out.empty() && (out.back() == '\n' || out.back() == '\r')) out.pop_back();
  return out;
}

std::string proc_field(const std::string& file, const std::string& key) {
  std::ifstream in(file);
  std::string line;
  while (std::getline(in, line)) {
    if (line.rfind(key, 0) == 0) {
      const size_t colon = line.find(':');
      if (colon == std::string::npos) continue;
      size_t b = line.find_first_not_of(" \t", colon + 1);
      return b == std::string::npos ? "" : line.substr(b);
    }
  }
  return "";
}

double proc_kb(const std::string& key) {
  const std::string v = proc_field("/proc/self/status", key);
  return v.empty() ? 0.0 : std::atof(v.c_str()) * 1024.0;
}

}  // namespace

nlohmann::json describe_machine() {
  nlohmann::json j;
  j["cpu"] = proc_field("/proc/cpuinfo", "model name");
  j["hardware_threads"] = hardware_threads();
  const std::string mem = proc_field("/proc/meminfo", "MemTotal");
  j["memory_gib"] = mem.empty() ? 0.0 : std::atof(mem.c_str()) / (1024.0 * 1024.0);
  utsname u{};
  if (uname(&u) == 0) j["kernel"] = std::string(u.sysname) + " " + u.release + " " + u.machine;
  double load[3] = {0, 0, 0};
  if (getloadavg(load, 3) == 3) j["load_average_at_start"] = {load[0], load[1], load[2]};
  j["note"] = "load_average_at_start > hardware_threads means other work shared the cores";
  return j;
}

nlohmann::json describe_build() {
  nlohmann::json j;
  j["version"] = FRAMELESS_VERSION;
  // This file's directory is inside the source tree (CMake passes absolute paths).
  const std::string src = std::filesystem::path(__FILE__).parent_path().string();
  const std::string commit =
      command_line_output("git -C '" + src + "' describe --always --dirty --abbrev=10 2>/dev/null");
  j["git"] = commit.empty() ? "unknown" : commit;
#if defined(__clang__)
  j["compiler"] = std::string("clang ") + __VERSION__;
#else
  j["compiler"] = std::string("g++ ") + __VERSION__;
#endif
#ifdef NDEBUG
  j["optimised"] = true;
#else
  j["optimised"] = false;
#endif
#if defined(__AVX512F__)
  j["isa"] = "avx512";
#elif defined(__AVX2__)
  j["isa"] = "avx2";
#else
  j["isa"] = "sse";
#endif
#if defined(__SANITIZE_ADDRESS__) || defined(__SANITIZE_THREAD__)
  j["sanitizer"] = true;
#endif
  return j;
}

nlohmann::json describe_scene(const Scene& scene, const std::string& spec) {
  nlohmann::json j;
  j["spec"] = spec;
  j["name"] = scene.name;
  j["spheres"] = scene.geometry.num_spheres();
  j["triangles"] = scene.geometry.num_triangles();
  j["lights"] = scene.lights.size();
  j["materials"] = scene.materials.size();
  const AccelStats& a = scene.accel.stats();
  j["bvh"] = {{"build_ms", a.build_ms}, {"bytes", a.bytes},   {"geometry_bytes", a.geometry_bytes},
              {"nodes", a.nodes},       {"leaves", a.leaves}, {"depth", a.depth}};
  return j;
}

nlohmann::json bench_header(const std::string& name, const Scene* scene, const std::string& spec,
                            const nlohmann::json& settings) {
  nlohmann::json j;
  j["benchmark"] = name;
  j["machine"] = describe_machine();
  j["build"] = describe_build();
  if (scene) j["scene"] = describe_scene(*scene, spec);
  j["settings"] = settings;
  return j;
}

std::string code_version(const Scene& scene) {
  return std::string(FRAMELESS_VERSION) + "+" + renderer_fingerprint(scene);
}

bool prepare_out_dir(const std::string& dir, std::string& error) {
  if (dir.empty()) {
    error = "--out: an output directory is required";
    return false;
  }
  std::error_code ec;
  std::filesystem::create_directories(dir, ec);
  if (ec) {
    error = "--out: cannot create " + dir + ": " + ec.message();
    return false;
  }
  return directory_writable(dir, error);
}

bool write_text_atomic(const std::string& path, const std::string& text, std::string& error) {
  const Result<bool> r = write_text_file_atomic(path, text);
  if (!r.ok()) error = r.error().message;
  return r.ok();
}

bool write_json(const std::string& path, const nlohmann::json& j, std::string& error) {
  return write_text_atomic(path, j.dump(2) + "\n", error);
}

std::string csv_number(double v) {
  if (std::isnan(v)) return "nan";
  if (std::isinf(v)) return v > 0 ? "inf" : "-inf";
  char buf[40];
  std::snprintf(buf, sizeof buf, "%.6g", v);
  return buf;
}

namespace {
// A cell as RFC 4180 has it: quoted (its quotes doubled) when it holds a comma, quote or line break.
std::string csv_cell(const std::string& cell) {
  if (cell.find_first_of(",\"\r\n") == std::string::npos) return cell;
  std::string q = "\"";
  for (char c : cell) q += c == '"' ? std::string("\"\"") : std::string(1, c);
  return q + "\"";
}
}  // namespace

std::string CsvTable::text() const {
  std::string t;
  for (size_t i = 0; i < header.size(); ++i) t += (i ? "," : "") + csv_cell(header[i]);
  t += "\n";
  for (const auto& row : rows) {
    for (size_t i = 0; i < row.size(); ++i) t += (i ? "," : "") + csv_cell(row[i]);
    t += "\n";
  }
  return t;
}

bool gnuplot_found() {
  const char* path = std::getenv("PATH");
  std::stringstream dirs(path ? path : "/usr/bin:/bin");
  std::string dir;
  while (std::getline(dirs, dir, ':')) {
    std::error_code ec;
    if (!dir.empty() && std::filesystem::exists(std::filesystem::path(dir) / "gnuplot", ec))
      return true;
  }
  return false;
}

namespace {
std::string doubled(const std::string& text, char c) {
  std::string out;
  for (const char x : text) out += x == c ? std::string(2, c) : std::string(1, x);
  return out;
}
}  // namespace

std::string gnuplot_text(const std::string& text) { return doubled(text, '\''); }

std::string gnuplot_tic_text(const std::string& text) { return doubled(text, '%'); }

bool plot_png(const std::string& dir, const std::string& name, int width, int height,
              const std::string& body, std::string& error, bool* png_written) {
  if (png_written) *png_written = false;
  const std::string png = dir + "/" + name + ".png";
  const std::string gp = dir + "/" + name + ".gp";
  const std::string tmp = temporary_path_for(png);
  std::string script = "set terminal pngcairo size " + std::to_string(width) + "," +
                       std::to_string(height) + " font 'sans,9'\n";
  script += "set output '" + tmp + "'\n" + body + "\nset output\n";
  if (!write_text_atomic(gp, script, error)) return false;
  if (!gnuplot_found()) {
    std::fprintf(
        stderr,
        "frameless: gnuplot not found (apt-get install gnuplot); skipped %s, script in %s\n",
        png.c_str(), gp.c_str());
    return true;
  }
  const std::string cmd = "gnuplot '" + gp + "' > '" + dir + "/" + name + ".gp.log' 2>&1";
  if (std::system(cmd.c_str()) != 0) {
    std::remove(tmp.c_str());
    std::fprintf(stderr, "frameless: gnuplot failed on %s (see %s.gp.log); skipped %s\n",
                 gp.c_str(), name.c_str(), png.c_str());
    return true;
  }
  std::remove((dir + "/" + name + ".gp.log").c_str());
  if (!commit_temporary(tmp, png, error)) return false;
  if (png_written) *png_written = true;
  return true;
}

void bench_progress(const std::string& bench, const std::string& what) {
  if (show_progress()) std::fprintf(stderr, "bench %s: %s\n", bench.c_str(), what.c_str());
}

double rss_bytes() { return proc_kb("VmRSS"); }
double peak_rss_bytes() { return proc_kb("VmHWM"); }

double process_cpu_seconds() {
  timespec ts{};
  clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &ts);
  return double(ts.tv_sec) + 1e-9 * double(ts.tv_nsec);
}

void sleep_s(double seconds) {
  std::this_thread::sleep_for(std::chrono::duration<double>(seconds));
}

double median(std::vector<double> v) {
  v.erase(std::remove_if(v.begin(), v.end(), [](double x) { return std::isnan(x); }), v.end());
  if (v.empty()) return NAN;
  std::sort(v.begin(), v.end());
  const size_t m = v.size() / 2;
  return v.size() % 2 ? v[m] : 0.5 * (v[m - 1] + v[m]);
}

double fit_slope(const std::vector<double>& x, const std::vector<double>& y, double* intercept,
                 double* r2) {
  const size_t n = std::min(x.size(), y.size());
  if (n < 2) return std::nan("");
  double mx = 0, my = 0;
  for (size_t i = 0; i < n; ++i) mx += x[i], my += y[i];
  mx /= double(n), my /= double(n);
  double sxx = 0, sxy = 0, syy = 0;
  for (size_t i = 0; i < n; ++i) {
    sxx += (x[i] - mx) * (x[i] - mx);
    sxy += (x[i] - mx) * (y[i] - my);
    syy += (y[i] - my) * (y[i] - my);
  }
  const double b = sxx > 0 ? sxy / sxx : std::nan("");
  if (intercept) *intercept = my - b * mx;
  if (r2) *r2 = (sxx > 0 && syy > 0) ? (sxy * sxy) / (sxx * syy) : 1.0;
  return b;
}

std::vector<float> render_one_thread(const Scene& s, int w, int h, int spp, double& cpu_seconds) {
  TileRenderOptions o;
  o.spp = spp;
  o.threads = 1;
  const double t0 = thread_cpu_seconds();
  RenderedImage img = render_tiles(s, make_camera_basis(s.camera, w, h), o);
  cpu_seconds = thread_cpu_seconds() - t0;
  return std::move(img.rgb);
}

int run_command(const std::string& command, std::string& output) {
  output.clear();
  std::FILE* p = popen((command + " 2>&1").c_str(), "r");
  if (!p) return -1;
  char buf[4096];
  size_t n;
  while ((n = std::fread(buf, 1, sizeof buf, p)) > 0) output.append(buf, n);
  const int status = pclose(p);
  return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

}  // namespace frameless::bench
