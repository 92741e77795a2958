// `frameless view`: the interactive frameless viewer in a GLFW window. Main thread.
#include <cstdio>
#include <memory>

#include "core/scenes/scene_load.h"
#include "viewer/viewer.h"
#include "tools/cluster_flags.h"
#include "tools/command_registry.h"
#include "tools/engine_flags.h"
#include "tools/tool_options.h"

namespace frameless::cli {
namespace {

struct ViewArgs {
  ClusterJoinOptions cluster;
  ShadowOptions shadows;
  std::string scene = "default";
  std::string size = "640x480";
  double refresh = 60.0;
  EngineFlags engine;
  std::string record, script, screenshot, snapshot_dir = "captures";
  int frames = 0;
  bool help_overlay = false;
  bool panels = false, no_panels = false;
  std::string view = "shaded";
  CameraOptions camera;
};

int run(const ViewArgs& a) {
  ViewerOptions o;
  std::string error;
  EngineConfig& e = o.engine;
  if (!parse_size(a.size, e.width, e.height, error)) return report_error(error);
  if (!a.engine.apply(e, o.blend, error)) return report_error(error);
  e.track_variance = true;  // the viewer's variance view reads it
  if (const std::string bad = validate(e); !bad.empty()) return report_error(bad);
  if (!(a.refresh >= 1.0 && a.refresh <= 240.0)) return report_error("--refresh: must be 1..240 Hz");
  o.refresh_hz = a.refresh;
  o.record_path = a.record;
  o.script_path = a.script;
  o.max_frames = a.frames;
  o.screenshot_path = a.screenshot;
  o.snapshot_dir = a.snapshot_dir;
  o.show_help = a.help_overlay;
  o.panels = !a.no_panels;
  o.panels_open = a.panels;
  if (!parse_view(a.view, o.view))
    return report_error("--view: unknown view '" + a.view +
                        "' (shaded, age, count, variance, epoch, levels)");
  ClusterJoin cluster;
  cluster.requested = a.cluster;
  if (!cluster.start(error)) return report_error(error);
  if (cluster.session) fit_to_cluster(e, o.blend);
  std::string load_error;
  std::unique_ptr<Scene> scene = load_scene_checked(a.scene, &a.shadows, load_error);
  if (scene) {
    o.camera = scene->camera;
    if (!a.camera.apply(o.camera, load_error)) scene.reset();
  }
  // Under mpirun: clients serve here until the viewer closes; the master shows their pixels.
  if (int code = cluster.join(scene.get(), load_error, e, o.camera); code >= 0) return code;
  o.title = "frameless - " + a.scene;
  if (cluster.master()) {
    o.fixed_layout = true;
    o.engine_hook = [&](Engine* engine) {
      if (engine)
        cluster.session->attach(*engine, *scene, cluster.options);
      else
        cluster.session->detach();
    };
    o.title += " - " + std::to_string(cluster.session->clients()) + " clients";
  }
  if (!cluster.master()) o.editable_scene = scene.get();  // the volume keys
  auto r = run_viewer(*scene, o);
  if (!r.ok()) {
    std::fprintf(stderr, "frameless: %s\n", r.error().message.c_str());
    return 3;
  }
  return 0;
}

const bool view_registered = register_command(
    "", "view", "Interactive frameless viewer (GLFW window; Tab shows the panels, H the keys)",
    [](CLI::App& app) {
      auto a = std::make_shared<ViewArgs>();
      app.add_option("scene", a->scene, "built-in name, .json scene, .obj/.ply/.gltf/.glb model or .vdb/.nrrd volume")
          ->capture_default_str();
      add_shadow_flags(app, a->shadows);
      add_cluster_flags(app, a->cluster);
      app.add_option("--size", a->size, "window size WxH")->capture_default_str();
      app.add_option("--refresh", a->refresh, "display refresh rate, 1..240 Hz")->capture_default_str();
      a->engine.add_to(app);
      app.add_option("--record", a->record,
                     "write the camera poses with timestamps to FILE (replay: capture --path FILE)");
      app.add_option("--script", a->script,
                     "timed commands: 'SECONDS orbit DX DY|pan DX DY|zoom N|fly R U F S|key K|"
                     "resize W H|screenshot FILE|panel NAME|set CONTROL VALUE...|open FILE|quit' "
                     "(docs/viewer.md)");
      app.add_option("--frames", a->frames, "quit after presenting N frames");
      app.add_option("--screenshot", a->screenshot, "with --frames: save the last frame as PNG");
      app.add_option("--snapshot-dir", a->snapshot_dir, "where P saves EXR snapshots")
          ->capture_default_str();
      app.add_flag("--show-help", a->help_overlay, "start with the controls shown");
      app.add_flag("--panels", a->panels, "start with the panels shown (Tab shows and hides them)");
      app.add_flag("--no-panels", a->no_panels, "no Dear ImGui panels: keys and the text overlay only");
      app.add_option("--view", a->view,
                     "view shown first (V cycles): shaded, age, count, variance, epoch, or levels "
                     "(reflection/refraction levels per pixel: 0 dark blue .. 25+ red)")
          ->capture_default_str();
      add_camera_flags(app, a->camera);
      app.footer(std::string("Exit status 3: no display (use `frameless capture`). Scenes: ") +
                 builtin_scene_help());
      return [a] { return run(*a); };
    });

}  // namespace
}  // namespace frameless::cli
