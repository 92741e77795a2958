// `frameless capture`: headless (OSMesa) capture of what a frameless display shows over time,
// as an OpenEXR sequence + manifest.json + contact sheet (+ MP4 with ffmpeg). Main thread.
#include <atomic>
#include <csignal>
#include <cstdio>
#include <memory>
#include <sstream>

#include "core/scenes/scene_load.h"
#include "display/capture.h"
#include "tools/cluster_flags.h"
#include "tools/command_registry.h"
#include "tools/engine_flags.h"
#include "tools/tool_options.h"

namespace frameless::cli {
namespace {

struct CaptureArgs {
  ClusterJoinOptions cluster;
  ShadowOptions shadows;
  std::string scene = "default";
  std::string out = "captures/capture";
  std::string size = "320x240";
  double duration = 2.0;
  double refresh = 30.0;
  bool deterministic = false;
  std::string layers;
  std::string views;
  std::string path_file;
  double orbit = 0.0, dolly = 1.0, cut_at = -1.0, cut_orbit = 90.0;
  EngineFlags engine;
  bool no_converge = false;
  uint64_t samples_per_tick = 0;
  bool no_sheet = false, no_mp4 = false;
  CameraOptions camera;
};

std::vector<std::string> split(const std::string& text) {
  std::vector<std::string> out;
  std::stringstream ss(text);
  std::string item;
  while (std::getline(ss, item, ','))
    if (!item.empty()) out.push_back(item);
  return out;
}

std::atomic<bool> g_cancel{false};
extern "C" void on_stop_signal(int) { g_cancel.store(true, std::memory_order_relaxed); }

int run(const CaptureArgs& a) {
  CaptureOptions o;
  o.out_dir = a.out;
  o.duration = a.duration;
  o.refresh_hz = a.refresh;
  o.layers = split(a.layers == "all" ? "age,count,variance,epoch,levels" : a.layers);
  o.views = split(a.views);
  o.progress = show_progress();
  o.mp4 = !a.no_mp4;
  o.contact_sheet = !a.no_sheet;
  std::string error;
  EngineConfig& e = o.engine;
  if (!parse_size(a.size, e.width, e.height, error)) return report_error(error);
  if (!a.engine.apply(e, o.blend, error)) return report_error(error);
  e.deterministic = a.deterministic;
  e.samples_per_tick = a.samples_per_tick;
  // Variance is tracked only when the capture writes the variance layer or view.
  for (const std::string& l : o.layers) e.track_variance |= l == "variance";
  for (const std::string& v : o.views) e.track_variance |= v == "variance";
  o.blend.converge = !a.no_converge;
  if (const std::string bad = validate(e); !bad.empty()) return report_error(bad);
  ClusterJoin cluster;
  cluster.requested = a.cluster;
  if (!cluster.start(error)) return report_error(error);
  if (cluster.session) fit_to_cluster(e, o.blend);
  std::string load_error;
  std::unique_ptr<Scene> scene;
  // The output folder is checked before the scene is even loaded: a bad --out fails at once
  // (only where the outputs go: a single process or the cluster master).
  if (!quiet_rank())
    if (auto d = prepare_output_dir(o.out_dir); !d.ok()) load_error = d.error().message;
  if (load_error.empty()) scene = load_scene_checked(a.scene, &a.shadows, load_error);
  if (scene) {
    o.camera = scene->camera;
    if (!a.camera.apply(o.camera, load_error)) scene.reset();
  }
  if (int code = cluster.join(scene.get(), load_error, e, o.camera); code >= 0) return code;
  if (cluster.master()) {
    o.engine_hook = [&](Engine* engine) {
      if (engine)
        cluster.session->attach(*engine, *scene, cluster.options);
      else
        cluster.session->detach();
    };
    o.settings["cluster"] = {{"ranks", cluster.session->size()}, {"render_threads", e.threads}};
  }
  // SIGTERM (mpirun ending the job when a rank failed) or Ctrl-C: stop between frames, so the
  // manifest lists exactly the frames on disk.
  std::signal(SIGTERM, on_stop_signal);
  std::signal(SIGINT, on_stop_signal);
  o.cancel = &g_cancel;
  if (!a.path_file.empty()) {
    auto p = load_camera_path(a.path_file);
    if (!p.ok()) return report_error(p.error().message);
    o.path = p.value();
  } else if (a.orbit != 0.0 || a.dolly != 1.0 || a.cut_at >= 0.0) {
    if (!(a.dolly > 0.0)) return report_error("--dolly: factor must be > 0");
    PathShorthand sh;
    sh.orbit_deg = a.orbit;
    sh.dolly_factor = a.dolly;
    sh.cut_at = a.cut_at;
    sh.cut_orbit_deg = a.cut_orbit;
    o.path = make_shorthand_path(o.camera, sh, a.duration);
  }
  o.settings["scene"] = {{"spec", a.scene}};
  o.settings["camera_path"] = a.path_file.empty() ? nlohmann::json(nullptr) : nlohmann::json(a.path_file);
  o.settings["orbit_deg"] = a.orbit;
  o.settings["dolly"] = a.dolly;
  o.settings["cut_at"] = a.cut_at;
  o.settings["cut_orbit_deg"] = a.cut_orbit;
  o.settings["start_camera"] = {{"eye", {o.camera.eye.x, o.camera.eye.y, o.camera.eye.z}},
                                {"look", {o.camera.look.x, o.camera.look.y, o.camera.look.z}},
                                {"up", {o.camera.up.x, o.camera.up.y, o.camera.up.z}},
                                {"fov", o.camera.fov_deg}};

  auto r = run_capture(*scene, o);
  if (!r.ok()) return report_error(r.error().message);
  std::printf("captured %d frames of %s at %g Hz (%s clock) into %s\n", r->frames, a.scene.c_str(),
              a.refresh, a.deterministic ? "virtual" : "wall", a.out.c_str());
  std::printf("  manifest: %s\n", r->manifest_path.c_str());
  if (!r->contact_sheet_path.empty())
    std::printf("  contact sheet: %s (open it in any image viewer)\n", r->contact_sheet_path.c_str());
  if (!r->mp4_path.empty()) std::printf("  video: %s\n", r->mp4_path.c_str());
  if (!r->note.empty()) std::printf("  %s\n", r->note.c_str());
  return 0;
}

const bool capture_registered = register_command(
    "", "capture",
    "Headless capture (OSMesa) of the frameless display over time: EXR sequence + manifest",
    [](CLI::App& app) {
      auto a = std::make_shared<CaptureArgs>();
      app.add_option("scene", a->scene, "built-in name, .json scene or .obj/.ply/.gltf/.glb model")
          ->capture_default_str();
      add_shadow_flags(app, a->shadows);
      add_cluster_flags(app, a->cluster);
      app.add_option("--out", a->out, "output folder (frames, manifest.json, contact_sheet.png)")
          ->capture_default_str();
      app.add_option("--size", a->size, "image size WxH")->capture_default_str();
      app.add_option("--duration", a->duration, "seconds to capture")->capture_default_str();
      app.add_option("--refresh", a->refresh, "display refresh rate = frame rate, 1..240 Hz")
          ->capture_default_str();
      app.add_flag("--deterministic", a->deterministic,
                   "virtual clock: same seed, same files (bit for bit)");
      app.add_option("--layers", a->layers,
                     "extra float layers: any of age,count,variance,epoch,levels (or 'all')");
      app.add_option("--view", a->views,
                     "also write these false-colour views per frame as NAME_NNNNN.png, drawn as "
                     "the viewer draws them: levels (reflection/refraction levels per pixel, 0 "
                     "dark blue .. 25+ red), age, count, variance, epoch; comma-separated");
      app.add_option("--path", a->path_file, "camera keyframes (JSON; a `view --record` file works)");
      app.add_option("--orbit", a->orbit, "orbit the look-at point by DEG over the capture");
      app.add_option("--dolly", a->dolly, "multiply the eye distance by F over the capture");
      app.add_option("--cut-at", a->cut_at, "sudden camera cut at T seconds");
      app.add_option("--cut-orbit", a->cut_orbit, "the cut jumps by this many degrees of orbit")
          ->capture_default_str();
      a->engine.add_to(app);
      app.add_flag("--no-converge", a->no_converge, "always blend (never show the running mean)");
      app.add_option("--samples-per-tick", a->samples_per_tick,
                     "deterministic: samples per refresh over all threads (0: engine default)");
      app.add_flag("--no-contact-sheet", a->no_sheet, "skip contact_sheet.png");
      app.add_flag("--no-mp4", a->no_mp4, "skip sequence.mp4 even when ffmpeg is installed");
      add_camera_flags(app, a->camera);
      app.footer(std::string("Scenes: ") + builtin_scene_help());
      return [a] { return run(*a); };
    });

}  // namespace
}  // namespace frameless::cli
