// The interactive frameless viewer: a GLFW window showing the display thread's image through
// GlPresenter, with orbit/pan/zoom/fly controls, Dear ImGui panels (or, where ImGui cannot run,
// keys and a bitmap text overlay). Runs on the main thread, which owns the window, its GL context
// and the panels; the engine's render threads and the display thread run beside it.
#pragma once
#include <functional>
#include <string>
#include <vector>

#include "core/base/error.h"
#include "core/scene/scene.h"
#include "display/blend.h"
#include "display/gl_presenter.h"
#include "frameless/engine_config.h"

namespace frameless {

class Engine;

struct ViewerOptions {
  EngineConfig engine;            // size = initial window size; threads, mode, seed, ...
  BlendConfig blend;
  double refresh_hz = 60.0;       // display refresh (1..240); presentation follows it
  Camera camera;                  // start camera (R resets to it)
  std::string title = "frameless";
  std::string record_path;        // write the camera poses with timestamps here at exit (JSON path)
  std::string script_path;        // timed commands that drive the viewer (tests, demos)
  int max_frames = 0;             // quit after presenting this many frames (0: run until closed)
  std::string screenshot_path;    // PNG of the window when quitting through max_frames
  std::string snapshot_dir = "captures";  // where P saves EXR snapshots
  bool show_help = false;         // start with the help panel open
  ViewMode view = ViewMode::shaded;  // the view shown first (V cycles)
  // Cluster master (tools/cluster_join.h): called with the engine right after it started and
  // with null before it stops (on every exit); the clients render the layout they were given, so
  // the image keeps opt.engine's size (the window scales it) and M, G, T, ',' and '.' are off.
  std::function<void(Engine*)> engine_hook;
  bool fixed_layout = false;
  // The scene itself when the viewer may change it (volumes, render settings, opening another
  // file); null: it may not (the cluster master).
  Scene* editable_scene = nullptr;
  bool panels = true;             // Dear ImGui panels (Tab shows/hides them); false: overlay only
  bool panels_open = false;       // start with the panels shown
};

// Opens the window and runs until it is closed (Esc), the script quits or max_frames is reached.
// Error (one line) when no display is available or the window cannot be created.
Result<bool> run_viewer(const Scene& scene, const ViewerOptions& options);

// Script lines: "SECONDS COMMAND [ARGS]" ('#' starts a comment), times from the window's opening:
//   orbit DX DY | pan DX DY | zoom NOTCHES | fly RIGHT UP FORWARD SECONDS | key NAME
//   (NAME: a key as in the help, e.g. M, V, R, P, H, TAB, LEFT_BRACKET) | resize W H |
//   screenshot FILE.png (or .exr: the window's sRGB values as floats) | quit |
//   panel NAME (opens that panel: settings, camera, lights, materials, objects, volumes, plots,
//   files) | set CONTROL VALUE... (what the panel's widget of that name does; docs/viewer.md
//   lists them, e.g. "set alpha 0.2", "set light0.color 1 0 0") | open FILE (as the dialog does)
struct ViewerScriptLine {
  int line = 0;  // line number in the script (errors while running name it)
  double time = 0;
  std::string command;
  std::vector<std::string> args;
};
Result<std::vector<ViewerScriptLine>> parse_viewer_script(const std::string& text,
                                                           const std::string& path);

}  // namespace frameless
