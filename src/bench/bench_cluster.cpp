// `frameless bench cluster`: frameless across Open MPI ranks against one process. Run plainly, it
// measures one process, then starts `mpirun -np K+1` jobs of itself for K = 1..--clients and
// tabulates them; run under mpirun (`--one`), rank 0 measures the job it leads and prints JSON.
// Frameless mode, or conventional mode with OpenRT's pieces on demand (--mode).
// Per run: pixel updates/s reaching the display, bytes per update on the wire, master CPU, the
// round trip of a small request, camera-change latency (50/95/100 % of pixels) and samples per
// CPU second of the render threads (scaling efficiency).
#include "bench/bench_cluster.h"

#include <sys/resource.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <memory>
#include <mutex>
#include <thread>
#include <vector>

#include <nlohmann/json.hpp>

#include "bench/bench_options.h"
#include "bench/bench_report.h"
#include "bench/cluster_join.h"
#include "bench/latency_trial.h"
#include "display/display_thread.h"
#include "frameless/engine.h"

namespace frameless::bench {
namespace {

// One measurement of an engine (a single process, or a cluster master with `hook` attaching it).
nlohmann::json measure(const Scene& scene, const EngineConfig& c, const Camera& camera, double seconds,
                       const std::function<void(Engine*)>& hook, const cluster::Session* session) {
  Engine e(scene, c, camera);
  DisplayConfig dc;
  dc.refresh_hz = 240;  // fine coverage sampling for the latency curve
  DisplayThread d(e, dc);
  std::mutex m;
  uint32_t watched = 0;
  std::vector<std::pair<double, double>> series;  // (engine seconds, coverage of the new camera)
  d.set_on_tick_info([&](const FrameInfo& info) {
    std::lock_guard<std::mutex> lock(m);
    if (watched && info.newest_epoch == watched) series.push_back({info.virtual_time, info.coverage});
  });
  e.start();
  if (hook) hook(&e);
  d.start();
  sleep_s(0.5);  // warm-up: clients streaming, display ticking
  const EngineStats s0 = e.stats();
  const DisplayStats d0 = d.stats();
  const cluster::ClusterStats c0 = session ? session->stats() : cluster::ClusterStats{};
  const double cpu0 = process_cpu_seconds();
  const auto w0 = std::chrono::steady_clock::now();
  sleep_s(seconds);
  const double wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - w0).count();
  const EngineStats s1 = e.stats();
  const DisplayStats d1 = d.stats();
  const cluster::ClusterStats c1 = session ? session->stats() : cluster::ClusterStats{};
  const double cpu = process_cpu_seconds() - cpu0;
  // Camera-change latency: a small dolly, then coverage of the new camera per display tick.
  Camera moved = camera;
  moved.eye += 0.05f * (camera.look - camera.eye);
  double t0;
  {
    std::lock_guard<std::mutex> lock(m);
    t0 = e.now();
    watched = e.publish_camera(moved);
  }
  for (int k = 0; k < 2000; ++k) {
    sleep_s(0.005);
    std::lock_guard<std::mutex> lock(m);
    if (!series.empty() && series.back().second >= 1.0) break;
  }
  d.stop();
  if (hook) hook(nullptr);
  e.stop();
  if (auto err = e.error()) throw std::runtime_error(*err);

  double busy = 0;
  for (size_t t = 0; t < s1.threads.size(); ++t) busy += s1.threads[t].busy_seconds - s0.threads[t].busy_seconds;
  const double samples = double(s1.samples - s0.samples);
  const double updates = double(d1.pixels_updated - d0.pixels_updated);
  nlohmann::json j;
  j["render_threads"] = s1.threads.size();
  j["pixel_updates_per_s"] = updates / wall;
  j["samples_per_s"] = samples / wall;
  j["samples_per_render_cpu_s"] = busy > 0 ? samples / busy : 0.0;
  j["process_cpu_fraction"] = cpu / wall;  // of one core; the master's whole process in a cluster
  j["display_cpu_fraction"] = (d1.cpu_seconds - d0.cpu_seconds) / wall;
  if (session) {
    const double records = double(c1.pixel_records - c0.pixel_records);
    const double bytes = double(c1.bytes - c0.bytes);
    j["wire_bytes_per_update"] = records > 0 ? bytes / records : 0.0;
    j["wire_mbit_per_s"] = bytes * 8e-6 / wall;
    j["messages_per_s"] = double(c1.messages - c0.messages) / wall;
    j["comm_cpu_fraction"] = (c1.comm_cpu_seconds - c0.comm_cpu_seconds) / wall;
    if (c.mode == RenderMode::conventional) {
      // OpenRT's figures: pieces handed out, stolen, moved with their states; how long the
      // clients' render threads waited for a piece; a piece request's round trip (ask -> pieces).
      const double pieces = double(c1.pieces - c0.pieces);
      j["pieces_per_s"] = pieces / wall;
      j["steal_fraction"] = pieces > 0 ? double(c1.steals - c0.steals) / pieces : 0.0;
      j["handoff_fraction"] = pieces > 0 ? double(c1.handoffs - c0.handoffs) / pieces : 0.0;
      j["client_idle_fraction"] = (c1.client_idle_seconds - c0.client_idle_seconds) / (wall * double(s1.threads.size()));
      const double requests = double(c1.requests - c0.requests);
      j["piece_request_ms"] = requests > 0 ? (c1.request_seconds - c0.request_seconds) / requests * 1e3 : -1.0;
    }
  }
  if (c.mode == RenderMode::conventional)
    j["frames_per_s"] = double(s1.frames_completed - s0.frames_completed) / wall;
  const LatencyTrial lat = latency_from(series, t0);
  auto ms = [](double v) { return std::isnan(v) ? -1.0 : v; };
  j["latency_ms"] = {{"p50", ms(lat.p50)}, {"p95", ms(lat.p95)}, {"p100", ms(lat.p100)}};
  j["latency_ideal_ms"] = updates > 0 ? double(c.width) * c.height / (updates / wall) * 1e3 : -1.0;
  return j;
}

// Round trips of a 16-byte request (the size of a tile request) to client 1 before it renders,
// in microseconds (p50, p99): MPI's own latency on this link.
nlohmann::json ping(cluster::Session& s) {
  std::vector<double> us;
  for (int k = 0; k < 20; ++k) s.ping(1);  // warm-up: connections set up, the client spinning
  for (int k = 0; k < 400; ++k) us.push_back(s.ping(1) * 1e6);
  std::sort(us.begin(), us.end());
  return {{"p50", us[us.size() / 2]}, {"p99", us[us.size() * 99 / 100]}, {"count", us.size()}};
}

std::string shell_quote(const std::string& s) {
  std::string out = "'";
  for (char ch : s) out += ch == '\'' ? std::string("'\\''") : std::string(1, ch);
  return out + "'";
}

// Runs `mpirun -np ranks` of this very binary with --one and returns the master's JSON.
nlohmann::json run_job(const ClusterBenchOptions& a, int ranks, std::string& error) {
  char self[4096];
  const ssize_t n = readlink("/proc/self/exe", self, sizeof self - 1);
  if (n <= 0) {
    error = "cannot find this executable (/proc/self/exe)";
    return nullptr;
  }
  self[n] = 0;
  const std::string cmd = "OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1 mpirun --oversubscribe -np " +
                          std::to_string(ranks) + " " + shell_quote(self) + " bench cluster --one " +
                          shell_quote(a.scene) + " --size " + a.size + " --threads " + std::to_string(a.threads) +
                          " --seconds " + std::to_string(a.seconds) + " --cluster-wire " + shell_quote(a.cluster.wire) +
                          " --cluster-batch-ms " + std::to_string(a.cluster.batch_ms) +
                          " --cluster-prefetch " + std::to_string(a.cluster.prefetch) + " --mode " + a.mode + " 2>&1";
  FILE* p = popen(cmd.c_str(), "r");
  std::string out;
  char buf[4096];
  size_t got;
  while (p && (got = fread(buf, 1, sizeof buf, p)) > 0) out.append(buf, got);
  const int status = p ? pclose(p) : -1;
  const size_t brace = out.find('{');
  nlohmann::json j = brace == std::string::npos ? nlohmann::json(nullptr)
                                                : nlohmann::json::parse(out.substr(brace), nullptr, false);
  if (status != 0 || j.is_discarded() || j.is_null()) {
    const size_t nl = out.find('\n');
    error = "mpirun -np " + std::to_string(ranks) + " failed: " + out.substr(0, nl);
    return nullptr;
  }
  return j;
}

}  // namespace

int run_cluster(const ClusterBenchOptions& a) {
  std::string error;
  EngineConfig c;
  if (!parse_size(a.size, c.width, c.height, error)) return report_error(error);
  if (a.threads < 1 || a.threads > 256) return report_error("--threads: must be 1..256 per client");
  if (a.clients < 1 || a.clients > 64) return report_error("--clients: must be 1..64");
  if (!(a.seconds > 0 && a.seconds <= 600)) return report_error("--seconds: must be in (0, 600]");
  if (a.cluster.wire != "exact" && a.cluster.wire != "rgbe")
    return report_error("--cluster-wire: expected exact or rgbe, got '" + a.cluster.wire + "'");
  c.threads = a.threads;
  const std::optional<RenderMode> mode = parse_render_mode(a.mode);
  if (!mode) return report_error("--mode: expected frameless or conventional, got '" + a.mode + "'");
  c.mode = *mode;
  ClusterJoin cluster;
  cluster.requested = a.cluster;
  if (!cluster.start(error)) return report_error(error);
  if (!cluster.session && a.one) return report_error("--one: run under mpirun -np N (N >= 2)");
  std::string load_error;
  std::unique_ptr<Scene> scene = load_scene_checked(a.scene, &a.shadows, load_error);
  if (int code = cluster.join(scene.get(), load_error, c, scene ? scene->camera : Camera{}); code >= 0)
    return code;
  try {
    if (cluster.master()) {  // one job: this rank leads it
      cluster::Session& s = *cluster.session;
      nlohmann::json j = {{"ranks", s.size()}, {"clients", s.clients()}, {"threads_per_client", a.threads},
                          {"wire", a.cluster.wire}, {"mode", a.mode}};
      j["request_rtt_us"] = ping(s);
      j.update(measure(*scene, c, scene->camera, a.seconds,
                       [&](Engine* e) { e ? s.attach(*e, *scene, cluster.options) : s.detach(); }, &s));
      std::printf("%s\n", j.dump(2).c_str());
      return 0;
    }
    bench_progress("cluster", "one process, " + std::to_string(a.threads) + " render threads");
    nlohmann::json single = measure(*scene, c, scene->camera, a.seconds, nullptr, nullptr);
    nlohmann::json runs = nlohmann::json::array();
    for (int k = 1; k <= a.clients; ++k) {
      bench_progress("cluster", "mpirun -np " + std::to_string(k + 1));
      nlohmann::json j = run_job(a, k + 1, error);
      if (j.is_null()) return report_error(error);
      runs.push_back(j);
    }
    // Per CPU second of the render threads, against one process with as many threads per
    // process: what distribution costs each sample (1: nothing).
    const double base = single["samples_per_render_cpu_s"].get<double>();
    const int cores = hardware_threads();
    for (auto& j : runs) {
      j["efficiency_per_cpu_s"] = base > 0 ? j["samples_per_render_cpu_s"].get<double>() / base : 0.0;
      j["oversubscribed"] = j["clients"].get<int>() * a.threads + 1 > cores;
    }
    nlohmann::json out = bench_header("cluster", scene.get(), a.scene,
                                      {{"size", a.size}, {"threads_per_client", a.threads},
                                       {"wire", a.cluster.wire}, {"batch_ms", a.cluster.batch_ms},
                                       {"mode", a.mode}, {"prefetch", a.cluster.prefetch},
                                       {"seconds", a.seconds}, {"max_clients", a.clients}});
    out["single_process"] = single;
    out["cluster"] = runs;
    if (a.json) {
      std::printf("%s\n", out.dump(2).c_str());
      return 0;
    }
    std::printf("bench cluster: %s at %s, %s mode, %d render thread(s) per client, %d cores here\n",
                a.scene.c_str(), a.size.c_str(), a.mode.c_str(), a.threads, cores);
    std::printf("%-10s %12s %12s %10s %9s %9s %9s %9s %9s %8s\n", "run", "updates/s", "samples/cpu-s",
                "effic.", "B/update", "master", "rtt us", "lat50 ms", "lat100", "");
    auto row = [&](const std::string& name, const nlohmann::json& j, bool cl) {
      std::printf("%-10s %12.0f %12.0f %10s %9s %8.0f%% %9s %9.1f %9.1f %8s\n", name.c_str(),
                  j["pixel_updates_per_s"].get<double>(), j["samples_per_render_cpu_s"].get<double>(),
                  cl ? csv_number(j["efficiency_per_cpu_s"].get<double>()).c_str() : "-",
                  cl ? csv_number(j["wire_bytes_per_update"].get<double>()).c_str() : "-",
                  100 * j["process_cpu_fraction"].get<double>(),
                  cl ? csv_number(j["request_rtt_us"]["p50"].get<double>()).c_str() : "-",
                  j["latency_ms"]["p50"].get<double>(), j["latency_ms"]["p100"].get<double>(),
                  cl && j["oversubscribed"].get<bool>() ? "(over)" : "");
    };
    row("1 process", single, false);
    for (const auto& j : runs) row(std::to_string(j["clients"].get<int>()) + " client", j, true);
    if (c.mode == RenderMode::conventional) {
      std::printf("%-10s %9s %10s %9s %9s %10s %12s\n", "run", "frames/s", "pieces/s", "stolen", "handoff",
                  "idle", "request ms");
      std::printf("%-10s %9.1f\n", "1 process", single["frames_per_s"].get<double>());
      for (const auto& j : runs)
        std::printf("%-10s %9.1f %10.0f %8.1f%% %8.1f%% %9.1f%% %12.3f\n",
                    (std::to_string(j["clients"].get<int>()) + " client").c_str(), j["frames_per_s"].get<double>(),
                    j["pieces_per_s"].get<double>(), 100 * j["steal_fraction"].get<double>(),
                    100 * j["handoff_fraction"].get<double>(), 100 * j["client_idle_fraction"].get<double>(),
                    j["piece_request_ms"].get<double>());
      std::printf("idle: the clients' render threads waiting for a piece; request: asking for pieces to\n"
                  "receiving them (waiting for the next frame's pieces included).\n");
    }
    std::printf("(over): more render threads + master than cores, so clients share cores; 'master' is the\n"
                "master's whole process CPU (one process: every thread) in %% of one core.\n");
  } catch (const std::exception& ex) {
    return report_error(ex.what());
  }
  return 0;
}

}  // namespace frameless::bench
