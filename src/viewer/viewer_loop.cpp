// The viewer's window and main loop: input, the script, held keys, resizes, presentation.
#include <sys/resource.h>

#define GLFW_INCLUDE_NONE
#include <GLFW/glfw3.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <sstream>

#include "display/manifest.h"
#include "frameless/cpu_clock.h"
#include "display/camera_controls.h"
#include "viewer/panels.h"
#include "viewer/viewer_state.h"

namespace frameless {
namespace {

std::string glfw_error_text;
void on_glfw_error(int, const char* text) { glfw_error_text = text ? text : "unknown error"; }

void* gl_proc(const char* name) { return reinterpret_cast<void*>(glfwGetProcAddress(name)); }

Viewer* viewer_of(GLFWwindow* w) { return static_cast<Viewer*>(glfwGetWindowUserPointer(w)); }

// Our callbacks go in first; ImGui's backend chains to them and they keep off what it uses.
void install_callbacks(GLFWwindow* window) {
  glfwSetKeyCallback(window, [](GLFWwindow* w, int key, int, int action, int) {
    Viewer& v = *viewer_of(w);
    v.dirty = true;
    if (v.panels && v.panels->wants_keyboard() && key != GLFW_KEY_TAB) return;
    if (action == GLFW_PRESS || (action == GLFW_REPEAT && key != GLFW_KEY_P && key != GLFW_KEY_TAB)) v.key(key);
  });
  glfwSetCursorPosCallback(window, [](GLFWwindow* w, double x, double y) {
    Viewer& v = *viewer_of(w);
    const float dx = float(x - v.last_x), dy = float(y - v.last_y);
    v.last_x = x, v.last_y = y;
    if (v.panels && v.panels->visible()) v.dirty = true;  // hover highlights
    if (v.panels && v.panels->wants_mouse()) return;
    int fw = 0, fh = 0;
    glfwGetFramebufferSize(w, &fw, &fh);
    if (glfwGetMouseButton(w, GLFW_MOUSE_BUTTON_LEFT) == GLFW_PRESS)
      v.set_camera(orbit_camera(v.camera, dx, dy));
    else if (glfwGetMouseButton(w, GLFW_MOUSE_BUTTON_RIGHT) == GLFW_PRESS ||
             glfwGetMouseButton(w, GLFW_MOUSE_BUTTON_MIDDLE) == GLFW_PRESS)
      v.set_camera(pan_camera(v.camera, dx, dy, fh));
  });
  glfwSetMouseButtonCallback(window, [](GLFWwindow* w, int, int, int) { viewer_of(w)->dirty = true; });
  glfwSetScrollCallback(window, [](GLFWwindow* w, double, double y) {
    Viewer& v = *viewer_of(w);
    v.dirty = true;
    if (v.panels && v.panels->wants_mouse()) return;
    v.set_camera(zoom_camera(v.camera, float(y)));
  });
  glfwSetFramebufferSizeCallback(window, [](GLFWwindow* w, int fw, int fh) {
    Viewer& v = *viewer_of(w);
    v.pending_w = fw, v.pending_h = fh, v.pending_since = v.now();
  });
  // A dropped scene, mesh, model or volume file opens like the files panel's dialog.
  glfwSetDropCallback(window, [](GLFWwindow* w, int count, const char** paths) {
    if (count > 0) viewer_of(w)->open_scene(paths[0]);
  });
}

// Held keys: fly (WASD, Q/E) and move the first light or the grabbed instance (arrows, PgUp/PgDn).
void held_keys(Viewer& v, double dt) {
  if (v.panels && v.panels->wants_keyboard()) return;
  auto held = [&](int k) { return glfwGetKey(v.window, k) == GLFW_PRESS ? 1.0f : 0.0f; };
  const float right = held(GLFW_KEY_D) - held(GLFW_KEY_A), up = held(GLFW_KEY_E) - held(GLFW_KEY_Q),
              fwd = held(GLFW_KEY_W) - held(GLFW_KEY_S);
  if (right != 0 || up != 0 || fwd != 0)
    v.set_camera(fly_camera(v.camera, right, up, fwd, float(std::min(dt, 0.1))));
  // At the camera's orbit distance per second.
  const Vec3 d(held(GLFW_KEY_RIGHT) - held(GLFW_KEY_LEFT), held(GLFW_KEY_PAGE_UP) - held(GLFW_KEY_PAGE_DOWN),
               held(GLFW_KEY_DOWN) - held(GLFW_KEY_UP));
  if (d == Vec3(0.0f)) return;
  const float speed = glm::length(v.camera.eye - v.camera.look) * float(std::min(dt, 0.1));
  if (v.grabbed >= 0) {
    v.move_grabbed(speed * d);
  } else if (!v.world.lights.empty()) {
    v.world.lights[0].position += speed * d;
    (void)v.publish_world();  // a refusal is in the status line
  }
}

Result<std::vector<ViewerScriptLine>> read_script(const std::string& path) {
  if (path.empty()) return std::vector<ViewerScriptLine>{};
  std::ifstream in(path);
  if (!in) return Error{path + ": cannot open script"};
  std::stringstream ss;
  ss << in.rdbuf();
  return parse_viewer_script(ss.str(), path);
}

}  // namespace

Result<bool> run_viewer(const Scene& scene, const ViewerOptions& opt) {
  auto script = read_script(opt.script_path);
  if (!script.ok()) return script.error();
  glfwSetErrorCallback(on_glfw_error);
  if (!glfwInit())
    return Error{"no display available (" + glfw_error_text +
                 "); for headless output use `frameless capture` (see frameless capture --help)"};
  struct Terminate {
    ~Terminate() { glfwTerminate(); }
  } terminate;
  glfwWindowHint(GLFW_CONTEXT_VERSION_MAJOR, 3);
  glfwWindowHint(GLFW_CONTEXT_VERSION_MINOR, 3);
  glfwWindowHint(GLFW_OPENGL_PROFILE, GLFW_OPENGL_CORE_PROFILE);
  glfwWindowHint(GLFW_OPENGL_FORWARD_COMPAT, GLFW_TRUE);
  GLFWwindow* window = glfwCreateWindow(opt.engine.width, opt.engine.height, opt.title.c_str(),
                                        nullptr, nullptr);
  if (!window) return Error{"cannot open a window with OpenGL 3.3 (" + glfw_error_text +
                            "); for headless output use `frameless capture`"};
  struct Destroy {
    GLFWwindow* w;
    ~Destroy() { glfwDestroyWindow(w); }
  } destroy{window};
  glfwMakeContextCurrent(window);
  glfwSwapInterval(0);  // the display thread sets the pace, not the monitor
  auto presenter = GlPresenter::create(&gl_proc);
  if (!presenter.ok()) return presenter.error();

  Viewer v(scene, opt);
  v.window = window, v.presenter = presenter.value().get();
  v.scene_label = scene.name;
  v.camera = v.home = opt.camera;
  v.help = opt.show_help;
  v.view = opt.view;
  v.recording.keyframes.push_back({0.0, opt.camera});
  // The framebuffer may differ from the requested size (HiDPI, window managers): render that size.
  v.engine_config = opt.engine;
  if (!opt.fixed_layout) {
    glfwGetFramebufferSize(window, &v.engine_config.width, &v.engine_config.height);
    v.engine_config.width = std::max(v.engine_config.width, 1), v.engine_config.height = std::max(v.engine_config.height, 1);
  }
  v.display_config.refresh_hz = opt.refresh_hz;
  v.display_config.blend = opt.blend;
  glfwSetWindowUserPointer(window, &v);
  install_callbacks(window);
  std::unique_ptr<Panels> panels;
  if (opt.panels) {
    std::string why;
    panels = Panels::create(window, why);
    if (!panels) std::fprintf(stderr, "frameless: panels off, keys and overlay only: %s\n", why.c_str());
  }
  v.panels = panels.get();
  if (panels && opt.panels_open) panels->set_visible(true);
  v.start_session();

  size_t next_script = 0;
  int presented = 0, presented_with_panels = 0;
  double last_loop = v.now(), last_animation = -1.0, ui_cpu = 0, ui_cpu_panels = 0;
  while (!glfwWindowShouldClose(window) && !v.quit) {
    glfwWaitEventsTimeout(0.1);
    const double t = v.now(), dt = t - last_loop;
    last_loop = t;
    held_keys(v, dt);
    if (!v.playing.keyframes.empty()) {
      v.set_camera(evaluate_camera_path(v.playing, t - v.playing_since, v.camera));
      if (t - v.playing_since > v.playing.duration()) v.playing = {};
    }
    // Instances with a "motion" move at the display's pace (each move publishes a refit top).
    if (!v.scene->instance_motions.empty() && t - last_animation >= 1.0 / 60.0) {
      v.engine->animate_instances(v.engine->now());
      last_animation = t;
      v.dirty = true;
    }
    while (next_script < script.value().size() && script.value()[next_script].time <= t)
      run_script_line(v, script.value()[next_script++]);
    // Re-partition once the window has stopped changing size for a moment.
    if (v.pending_w > 0 && t - v.pending_since > 0.15) {
      if (!opt.fixed_layout && (v.pending_w != v.engine->width() || v.pending_h != v.engine->height()))
        v.engine->resize(v.pending_w, v.pending_h);
      v.pending_w = v.pending_h = 0;
    }
    if (auto e = v.engine->error()) return Error{"render thread failed: " + *e};
    if (auto e = v.display->error()) return Error{*e};
    v.update_rates();
    bool is_new = false;
    v.display->acquire_latest(&is_new);
    if (!is_new && !v.dirty) continue;
    v.dirty = false;
    int fw = 0, fh = 0;
    glfwGetFramebufferSize(window, &fw, &fh);
    if (fw <= 0 || fh <= 0) continue;  // minimised
    const double cpu0 = thread_cpu_seconds();
    const bool with_panels = v.panels && v.panels->visible();
    v.draw(fw, fh);
    v.capture_frame();
    ++presented;
    if (opt.max_frames > 0 && presented >= opt.max_frames) {
      if (!opt.screenshot_path.empty()) v.screenshot(opt.screenshot_path);
      v.quit = true;
    }
    glfwSwapBuffers(window);
    const double used = thread_cpu_seconds() - cpu0;
    ui_cpu += used;
    if (with_panels) ui_cpu_panels += used, ++presented_with_panels;
  }
  const DisplayStats ds = v.display->stats();
  if (!v.rates.error.empty())
    std::fprintf(stderr, "frameless: view: RMSE against the reference of the view: %.5f first, %.5f last (%zu points)\n",
                 double(v.rates.error.front()), double(v.rates.error.back()), v.rates.error.size());
  v.stop_capture();
  v.stop_session();
  // The cost of showing: the display thread's share of a core, and the window thread's per frame.
  const int plain = presented - presented_with_panels;
  std::fprintf(stderr,
               "frameless: view: %d frames (%d with panels); display thread %.1f %% of a core; "
               "window thread %.2f ms a frame without panels, %.2f ms with\n",
               presented, presented_with_panels,
               ds.wall_seconds > 0 ? 100.0 * ds.cpu_seconds / ds.wall_seconds : 0.0,
               plain > 0 ? 1e3 * (ui_cpu - ui_cpu_panels) / plain : 0.0,
               presented_with_panels > 0 ? 1e3 * ui_cpu_panels / presented_with_panels : 0.0);
  if (!opt.record_path.empty()) {
    v.recording.keyframes.push_back({v.now(), v.camera});
    if (auto r = write_text_file_atomic(opt.record_path, camera_path_to_json(v.recording, "frameless view --record"));
        !r.ok())
      return r.error();
    std::fprintf(stderr, "frameless: recorded %zu camera poses to %s (replay: frameless capture --path %s)\n",
                 v.recording.keyframes.size(), opt.record_path.c_str(), opt.record_path.c_str());
  }
  panels.reset();     // ImGui's GL objects go while their context still exists
  presenter.value().reset();
  return true;
}

}  // namespace frameless
