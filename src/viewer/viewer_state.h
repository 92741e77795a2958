// What the viewer's window, keys, script, controls and panels share: the scene shown, its engine
// and display thread (a "session", rebuilt when the scene or a scene-level setting changes), the
// camera, and the edits in flight. Main (window) thread only.
#pragma once
#include <chrono>
#include <cstdint>
#include <functional>
#include <future>
#include <memory>
#include <string>
#include <vector>

#include "core/scene/dynamic.h"
#include "display/camera_path.h"
#include "display/display_thread.h"
#include "frameless/engine.h"
#include "frameless/reference_cache.h"
#include "viewer/viewer.h"

struct GLFWwindow;

namespace frameless {

class Panels;

// Live figures sampled four times a second for the overlay and the plots.
struct ViewerRates {
  static constexpr size_t kHistory = 120;  // 30 s of samples
  std::vector<float> samples_per_s, updates_per_s, display_cpu, coverage, error;
  double time = -1.0;  // when the last sample was taken (viewer seconds)
  uint64_t samples = 0, updates = 0;
  double display_cpu_seconds = 0;
  float last(const std::vector<float>& v) const { return v.empty() ? 0.0f : v.back(); }
};

struct Viewer {
  explicit Viewer(const Scene& shown, const ViewerOptions& options);
  ~Viewer();

  ViewerOptions opt;
  GLFWwindow* window = nullptr;
  GlPresenter* presenter = nullptr;
  Panels* panels = nullptr;  // null: overlay and keys only

  // The session.
  const Scene* scene;              // the scene shown (the caller's, or one opened here)
  Scene* editable = nullptr;       // the same scene when it may be changed
  std::unique_ptr<Scene> opened;   // a scene opened from the window (owns it)
  std::string scene_label;         // what the title and overlay call it
  EngineConfig engine_config;      // settings a rebuild starts with
  DisplayConfig display_config;
  std::unique_ptr<Engine> engine;
  std::unique_ptr<DisplayThread> display;
  WorldState world;                // lights, materials and objects as edited (published)

  Camera camera, home;
  ViewMode view = ViewMode::shaded;
  bool help = false, overlay_on = true, dirty = true, quit = false;
  double last_x = 0, last_y = 0;
  CameraPath recording;            // poses since the window opened (--record, the camera panel)
  CameraPath playing;              // a loaded camera path being played (empty: none)
  double playing_since = 0;
  std::string status;              // one-line message (overlay and panels)
  int pending_w = 0, pending_h = 0;
  double pending_since = 0;
  int64_t grabbed = -1;            // declared index of the instance the arrow keys move (-1: light)
  ViewerRates rates;
  // A converged reference of one view, rendered beside the engine when asked (the error plot).
  std::future<Result<Reference>> reference_job;
  std::shared_ptr<const Reference> reference;
  Camera reference_camera;
  bool reference_outdated = false;  // the world changed while the job rendered: drop its result
  bool world_edited = false;        // lights, materials, objects or instances moved this session
  // Capture from the window: every newly displayed image as PNG into capture_dir.
  std::string capture_dir;
  int capture_frames = 0;
  uint64_t captured_tick = ~uint64_t(0);

  double now() const;
  bool may_rebuild();  // false (with a status line) on the cluster master, whose layout is fixed

  // Session life: start with the current scene and settings; stop (display, engine, hooks).
  void start_session();
  void stop_session();
  // Stops the session, applies `edit` to the scene and the settings, starts a new one; `what`
  // becomes the status line.
  void rebuild(const std::string& what, const std::function<void(Scene&, EngineConfig&)>& edit);
  // Opens a scene file (the dialog, a dropped file, the script): one-line status on failure.
  void open_scene(const std::string& path);

  // Edits the panels, keys and script share.
  void set_camera(const Camera& c);
  void change_display(const std::function<void(DisplayConfig&)>& f);
  Result<bool> publish_world();  // `world` after its check; refused: back to the engine's
  void edit_volumes(const std::function<std::string(Scene&)>& edit);
  void set_instance_translation(uint32_t declared, const Vec3& t);
  void save_image(const std::string& format);  // "exr" (image and layers) or "png" (as shown)
  void start_capture();
  void stop_capture();
  void capture_frame();
  void request_reference(int spp);
  void drop_reference();
  void world_changed();
  void update_rates();
  void key(int k);
  void grab_or_release();
  void move_grabbed(const Vec3& d);
  void screenshot(const std::string& path);
  void draw(int fw, int fh);
  std::vector<std::string> overlay(const ViewScale& s);

  std::chrono::steady_clock::time_point t0 = std::chrono::steady_clock::now();
};

// Runs one validated script line (a failing "set" or "open" prints FILE:LINE: and the error).
void run_script_line(Viewer& v, const ViewerScriptLine& line);

// GLFW key code of a key name as the script writes it ("M", "LEFT_BRACKET", "TAB"); -1: none.
int key_from_name(const std::string& name);
// "1.2M", "3.4k", "56": compact counts for the overlay and panels.
std::string si(double v);

}  // namespace frameless
