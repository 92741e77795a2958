#include "display/glfw_viewer.h"

#define GLFW_INCLUDE_NONE
#include <GLFW/glfw3.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>

#include "core/scene/dynamic.h"
#include "display/camera_controls.h"
#include "display/camera_path.h"
#include "display/capture.h"
#include "display/display_thread.h"
#include "display/exr_io.h"
#include "display/gl_presenter.h"
#include "display/levels_view.h"
#include "display/manifest.h"
#include "display/png_io.h"
#include "display/volume_keys.h"
#include "frameless/engine.h"

namespace frameless {
namespace {

const std::vector<std::string> kHelp = {
    "drag: orbit  right/middle drag: pan",   "wheel: zoom  WASD, Q/E: fly  R: reset",
    "M: frameless/conventional  V: view",    "[ ]: alpha -/+   - =: refresh -/+",
    ", .: update % -/+   G T: threads -/+",  "P: save EXR snapshot  H/F1: help",
    "arrows, PgUp/PgDn: move the light (or the grabbed instance)",
    "I: grab/release the instance at the centre of the view",     "O: overlay on/off  Esc: quit",
    "J: reprojection on/off  K: temporal blend weights on/off",
    "Z X: isovalue -/+   B: next transfer function (volumes)"};

std::string glfw_error_text;
void on_glfw_error(int, const char* text) { glfw_error_text = text ? text : "unknown error"; }

void* gl_proc(const char* name) { return reinterpret_cast<void*>(glfwGetProcAddress(name)); }

std::string si(double v) {
  char buf[32];
  if (v >= 1e6) std::snprintf(buf, sizeof buf, "%.2fM", v * 1e-6);
  else if (v >= 1e3) std::snprintf(buf, sizeof buf, "%.1fk", v * 1e-3);
  else std::snprintf(buf, sizeof buf, "%.0f", v);
  return buf;
}

int key_from_name(const std::string& n) {
  static const std::map<std::string, int> named = {
      {"LEFT_BRACKET", GLFW_KEY_LEFT_BRACKET}, {"RIGHT_BRACKET", GLFW_KEY_RIGHT_BRACKET},
      {"MINUS", GLFW_KEY_MINUS}, {"EQUAL", GLFW_KEY_EQUAL}, {"COMMA", GLFW_KEY_COMMA},
      {"PERIOD", GLFW_KEY_PERIOD}, {"F1", GLFW_KEY_F1}, {"ESCAPE", GLFW_KEY_ESCAPE}};
  if (n.size() == 1 && std::isalnum((unsigned char)n[0])) return std::toupper((unsigned char)n[0]);
  auto it = named.find(n);
  return it == named.end() ? -1 : it->second;
}

// Everything the window's callbacks and the loop share (main thread only).
struct Viewer {
  const Scene& scene;
  ViewerOptions opt;
  GLFWwindow* window = nullptr;
  Engine* engine = nullptr;
  DisplayThread* display = nullptr;
  GlPresenter* presenter = nullptr;
  Camera camera, home;
  ViewMode view = ViewMode::shaded;
  bool help = false, overlay_on = true, dirty = true, quit = false;
  double last_x = 0, last_y = 0;
  CameraPath recording;
  std::chrono::steady_clock::time_point t0 = std::chrono::steady_clock::now();
  std::string status;  // one-line message shown in the overlay (snapshot saved, errors)
  int pending_w = 0, pending_h = 0;
  double pending_since = 0;
  int64_t grabbed = -1;  // declared index of the instance the arrow keys move (-1: the light)

  double now() const {
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  }

  void set_camera(const Camera& c) {
    if (!camera_is_valid(c) || c == camera) return;
    camera = c;
    engine->publish_camera(c);
    if (!opt.record_path.empty()) recording.keyframes.push_back({now(), c});
    dirty = true;
  }

  void change_display(const std::function<void(DisplayConfig&)>& f) {
    DisplayConfig c = display->config();
    f(c);
    display->set_config(c);
    dirty = true;
  }

  void save_snapshot() {
    const DisplayImage& img = display->acquire_latest();
    std::error_code ec;
    std::filesystem::create_directories(opt.snapshot_dir, ec);
    std::string path;
    for (int i = 0; i < 100000; ++i) {
      char name[64];
      std::snprintf(name, sizeof name, "snapshot_%03d.exr", i);
      path = (std::filesystem::path(opt.snapshot_dir) / name).string();
      if (!std::filesystem::exists(path)) break;
    }
    ExrAttributes a;
    a.world_to_camera = world_to_camera_matrix(camera);
    a.doubles["frameTime"] = img.info.virtual_time;
    a.strings["renderMode"] = to_string(img.info.mode);
    a.strings["seed"] = std::to_string(opt.engine.seed);
    auto r = write_display_exr(path, img, nullptr, {"age", "count", "variance", "epoch", "levels"}, a);
    status = r.ok() ? "saved " + path : r.error().message;
    std::fprintf(stderr, "frameless: %s\n", status.c_str());
    dirty = true;
  }

  void key(int k) {
    switch (k) {
      case GLFW_KEY_ESCAPE: quit = true; break;
      case GLFW_KEY_R: set_camera(home); break;
      case GLFW_KEY_M: case GLFW_KEY_COMMA: case GLFW_KEY_PERIOD: case GLFW_KEY_G: case GLFW_KEY_T:
      case GLFW_KEY_J:
        if (opt.fixed_layout) {
          status = "cluster: mode, threads, update %, reprojection fixed";
          dirty = true;
          return;
        }
        break;
      default: break;
    }
    if (opt.editable_scene && is_volume_key(*opt.editable_scene, k)) return edit_volume(k);
    switch (k) {
      case GLFW_KEY_M:
        engine->set_mode(engine->config().mode == RenderMode::frameless ? RenderMode::conventional
                                                                        : RenderMode::frameless);
        break;
      case GLFW_KEY_V: view = next_view(view); break;
      case GLFW_KEY_H: case GLFW_KEY_F1: help = !help; break;
      case GLFW_KEY_O: overlay_on = !overlay_on; break;
      case GLFW_KEY_P: save_snapshot(); break;
      case GLFW_KEY_J: change_display([](DisplayConfig& c) { c.blend.reproject = !c.blend.reproject; }); break;
      case GLFW_KEY_K: change_display([](DisplayConfig& c) { c.blend.temporal = !c.blend.temporal; }); break;
      case GLFW_KEY_LEFT_BRACKET:
        change_display([](DisplayConfig& c) { c.blend.alpha = std::max(0.01f, c.blend.alpha / 1.25f); });
        break;
      case GLFW_KEY_RIGHT_BRACKET:
        change_display([](DisplayConfig& c) { c.blend.alpha = std::min(1.0f, c.blend.alpha * 1.25f); });
        break;
      case GLFW_KEY_MINUS:
        change_display([](DisplayConfig& c) { c.refresh_hz = std::max(1.0, std::round(c.refresh_hz / 1.25)); });
        break;
      case GLFW_KEY_EQUAL:
        change_display([](DisplayConfig& c) { c.refresh_hz = std::min(240.0, std::round(c.refresh_hz * 1.25 + 0.5)); });
        break;
      case GLFW_KEY_COMMA:
        engine->set_update_percent(std::max(0.01, engine->config().update_percent / 2.0));
        break;
      case GLFW_KEY_PERIOD:
        engine->set_update_percent(std::min(100.0, engine->config().update_percent * 2.0));
        break;
      case GLFW_KEY_G: engine->set_threads(std::max(1, engine->thread_count() - 1)); break;
      case GLFW_KEY_T: engine->set_threads(std::min(256, engine->thread_count() + 1)); break;
      case GLFW_KEY_I: grab_or_release(); break;
      default: return;
    }
    dirty = true;
  }

  // Volume keys (display/volume_keys.h): the render threads stop while the scene changes, then
  // every pixel restarts (the same camera, published again, is a new epoch).
  void edit_volume(int k) {
    if (opt.fixed_layout) {
      status = "cluster: volumes fixed";
    } else {
      engine->stop();
      status = edit_volumes(*opt.editable_scene, k);
      engine->start();
      engine->publish_camera(camera);
    }
    dirty = true;
  }

  // Grabs the instance seen at the centre of the view (OpenRT's "move parts of the power plant
  // around"), or releases the one grabbed.
  void grab_or_release() {
    if (grabbed >= 0) {
      status = "released instance " + std::to_string(grabbed);
      grabbed = -1;
      return;
    }
    const std::shared_ptr<const InstanceTop> top = engine->instance_top();
    const CameraBasis b = make_camera_basis(camera, engine->width(), engine->height());
    Hit hit;
    const Ray r = camera_ray(b, 0.5f * float(engine->width()), 0.5f * float(engine->height()));
    if (top && scene.accel.intersect(r, hit, top.get()) && hit.inst != kInvalidId) {
      grabbed = top->declared[hit.inst];
      status = "grabbed instance " + std::to_string(grabbed) + ": arrows and PgUp/PgDn move it, I releases";
    } else {
      status = "no instance at the centre of the view";
    }
  }

  // Moves the grabbed instance by `d` (world units); a refit top level is published.
  void move_grabbed(const Vec3& d) {
    Affine a = engine->instance_transform(uint32_t(grabbed));
    a.t += d;
    InstanceUpdate u;
    engine->move_instances({{uint32_t(grabbed), a}}, &u);
    char buf[160];
    std::snprintf(buf, sizeof buf, "instance %lld moved: top level %s in %.2f ms",
                  (long long)grabbed, u.rebuilt ? "rebuilt" : "refit",
                  u.copy_ms + u.refit_ms + u.rebuild_ms);
    status = buf;
    dirty = true;
  }

  // Runs one (already validated) script command.
  void run_script(const ViewerScriptLine& l) {
    auto f = [&](size_t i) { return i < l.args.size() ? std::strtof(l.args[i].c_str(), nullptr) : 0.0f; };
    int fw = 0, fh = 0;
    glfwGetFramebufferSize(window, &fw, &fh);
    if (l.command == "orbit") set_camera(orbit_camera(camera, f(0), f(1)));
    else if (l.command == "pan") set_camera(pan_camera(camera, f(0), f(1), fh));
    else if (l.command == "zoom") set_camera(zoom_camera(camera, f(0)));
    else if (l.command == "fly") set_camera(fly_camera(camera, f(0), f(1), f(2), f(3)));
    else if (l.command == "key") key(key_from_name(l.args.empty() ? "" : l.args[0]));
    else if (l.command == "resize") glfwSetWindowSize(window, int(f(0)), int(f(1)));
    else if (l.command == "screenshot") screenshot(l.args.empty() ? "screenshot.png" : l.args[0]);
    else if (l.command == "quit") quit = true;
  }

  void screenshot(const std::string& path) {
    int fw = 0, fh = 0;
    glfwGetFramebufferSize(window, &fw, &fh);
    draw(fw, fh);
    std::vector<unsigned char> rgb8;
    presenter->read_rgb8(fw, fh, rgb8);
    // .exr: the window's 8-bit sRGB values as floats in [0, 1] (tests read them back); else PNG.
    Result<bool> r = true;
    if (path.size() > 4 && path.substr(path.size() - 4) == ".exr") {
      std::vector<float> f(rgb8.size());
      for (size_t i = 0; i < f.size(); ++i) f[i] = float(rgb8[i]) / 255.0f;
      r = write_exr(path, fw, fh, {{"R", false, f.data(), 3}, {"G", false, f.data() + 1, 3},
                                   {"B", false, f.data() + 2, 3}});
    } else {
      r = write_png_rgb8(path, fw, fh, rgb8.data());
    }
    std::fprintf(stderr, "frameless: %s\n", r.ok() ? ("screenshot " + path).c_str() : r.error().message.c_str());
  }

  std::vector<std::string> overlay(const ViewScale& s) {
    const EngineConfig ec = engine->config();
    const DisplayConfig dc = display->config();
    const DisplayStats ds = display->stats();
    char l1[160], l2[160], l3[160], l4[160];
    std::snprintf(l1, sizeof l1, "%s %dx%d %s", scene.name.c_str(), engine->width(),
                  engine->height(), to_string(ec.mode));
    std::snprintf(l2, sizeof l2, "view %s  threads %d  update %.2g%%", to_string(view),
                  engine->thread_count(), ec.update_percent);
    std::snprintf(l3, sizeof l3, "alpha %.2f%s  %.0f Hz (got %.1f)%s%s", dc.blend.alpha,
                  dc.blend.temporal ? " temporal" : "", dc.refresh_hz,
                  ds.mean_interval > 0 ? 1.0 / ds.mean_interval : 0.0, dc.blend.reproject ? "  reproject" : "",
                  ec.closed_loop ? "  closed loop" : "");
    std::snprintf(l4, sizeof l4, "%s samples/s  coverage %.1f%%", si(samples_per_s).c_str(),
                  100.0 * s.coverage);
    std::vector<std::string> lines = {l1, l2, l3, l4};
    if (view == ViewMode::age) lines.push_back("age: black 0 .. white " + std::to_string(s.max_age).substr(0, 5) + " s");
    if (view == ViewMode::count) lines.push_back("count: log, white = " + si(s.max_count));
    if (view == ViewMode::variance) lines.push_back("variance: log scale");
    if (view == ViewMode::epoch) lines.push_back("epoch: green newest, red older");
    if (view == ViewMode::levels) {
      lines.push_back("reflection levels (max " + std::to_string(s.max_levels) + "):");
      lines.push_back(kLevelsLegend);
    }
    if (help) lines.insert(lines.end(), kHelp.begin(), kHelp.end());
    else lines.push_back("H: help");
    if (!status.empty()) lines.push_back(status);
    return lines;
  }

  double samples_per_s = 0, rate_time = 0;
  uint64_t rate_samples = 0;
  void update_rate() {
    const double t = now();
    if (t - rate_time < 0.5) return;
    const uint64_t s = engine->stats().samples;
    samples_per_s = s >= rate_samples ? double(s - rate_samples) / (t - rate_time) : 0.0;
    rate_samples = s, rate_time = t;
  }

  void draw(int fw, int fh) {
    const DisplayImage& img = display->acquire_latest();
    const ViewScale s = presenter->upload(img, view);
    presenter->draw(fw, fh, true);
    if (overlay_on) presenter->draw_text(overlay(s), fw, fh, fw >= 1600 ? 2 : 1);
  }
};

Viewer* viewer_of(GLFWwindow* w) { return static_cast<Viewer*>(glfwGetWindowUserPointer(w)); }

}  // namespace

Result<std::vector<ViewerScriptLine>> parse_viewer_script(const std::string& text,
                                                           const std::string& path) {
  static const std::map<std::string, size_t> arity = {
      {"orbit", 2}, {"pan", 2}, {"zoom", 1}, {"fly", 4}, {"key", 1},
      {"resize", 2}, {"screenshot", 1}, {"quit", 0}};
  std::vector<ViewerScriptLine> out;
  std::istringstream in(text);
  std::string line;
  for (int n = 1; std::getline(in, line); ++n) {
    if (auto h = line.find('#'); h != std::string::npos) line.resize(h);
    std::istringstream ls(line);
    ViewerScriptLine l;
    std::string t;
    if (!(ls >> t)) continue;
    const std::string where = path + ":" + std::to_string(n) + ": ";
    char* end = nullptr;
    l.time = std::strtod(t.c_str(), &end);
    if (*end || !std::isfinite(l.time) || l.time < 0) return Error{where + "time: expected seconds >= 0, got '" + t + "'"};
    if (!(ls >> l.command)) return Error{where + "command: missing"};
    auto it = arity.find(l.command);
    if (it == arity.end()) return Error{where + "command: unknown '" + l.command + "'"};
    for (std::string a; ls >> a;) l.args.push_back(a);
    if (l.args.size() != it->second)
      return Error{where + l.command + ": expected " + std::to_string(it->second) + " arguments"};
    if (l.command == "key" && key_from_name(l.args[0]) < 0)
      return Error{where + "key: unknown key '" + l.args[0] + "'"};
    out.push_back(l);
  }
  std::stable_sort(out.begin(), out.end(), [](auto& a, auto& b) { return a.time < b.time; });
  return out;
}

Result<bool> run_viewer(const Scene& scene, const ViewerOptions& opt) {
  std::vector<ViewerScriptLine> script;
  if (!opt.script_path.empty()) {
    std::ifstream in(opt.script_path);
    if (!in) return Error{opt.script_path + ": cannot open script"};
    std::stringstream ss;
    ss << in.rdbuf();
    auto s = parse_viewer_script(ss.str(), opt.script_path);
    if (!s.ok()) return s.error();
    script = s.value();
  }
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
  glfwMakeContextCurrent(window);
  glfwSwapInterval(0);  // the display thread sets the pace, not the monitor
  auto presenter = GlPresenter::create(&gl_proc);
  if (!presenter.ok()) return presenter.error();

  // The framebuffer may differ from the requested size (HiDPI, window managers): render that size.
  EngineConfig ec = opt.engine;
  if (!opt.fixed_layout) {
    glfwGetFramebufferSize(window, &ec.width, &ec.height);
    ec.width = std::max(ec.width, 1), ec.height = std::max(ec.height, 1);
  }
  Engine engine(scene, ec, opt.camera);
  DisplayConfig dc;
  dc.refresh_hz = opt.refresh_hz;
  dc.blend = opt.blend;
  DisplayThread display(engine, dc);
  // Each display tick wakes the main loop (glfwPostEmptyEvent is safe from any thread).
  display.set_on_tick_info([](const FrameInfo&) { glfwPostEmptyEvent(); });

  Viewer v{scene, opt};
  v.window = window, v.engine = &engine, v.display = &display, v.presenter = presenter.value().get();
  v.camera = v.home = opt.camera;
  v.help = opt.show_help;
  v.view = opt.view;
  if (!opt.record_path.empty()) v.recording.keyframes.push_back({0.0, opt.camera});
  glfwSetWindowUserPointer(window, &v);
  glfwSetKeyCallback(window, [](GLFWwindow* w, int key, int, int action, int) {
    if (action == GLFW_PRESS || (action == GLFW_REPEAT && key != GLFW_KEY_P)) viewer_of(w)->key(key);
  });
  glfwSetCursorPosCallback(window, [](GLFWwindow* w, double x, double y) {
    Viewer& v = *viewer_of(w);
    const float dx = float(x - v.last_x), dy = float(y - v.last_y);
    v.last_x = x, v.last_y = y;
    int fw = 0, fh = 0;
    glfwGetFramebufferSize(w, &fw, &fh);
    if (glfwGetMouseButton(w, GLFW_MOUSE_BUTTON_LEFT) == GLFW_PRESS)
      v.set_camera(orbit_camera(v.camera, dx, dy));
    else if (glfwGetMouseButton(w, GLFW_MOUSE_BUTTON_RIGHT) == GLFW_PRESS ||
             glfwGetMouseButton(w, GLFW_MOUSE_BUTTON_MIDDLE) == GLFW_PRESS)
      v.set_camera(pan_camera(v.camera, dx, dy, fh));
  });
  glfwSetScrollCallback(window, [](GLFWwindow* w, double, double y) {
    Viewer& v = *viewer_of(w);
    v.set_camera(zoom_camera(v.camera, float(y)));
  });
  glfwSetFramebufferSizeCallback(window, [](GLFWwindow* w, int fw, int fh) {
    Viewer& v = *viewer_of(w);
    v.pending_w = fw, v.pending_h = fh, v.pending_since = v.now();
  });

  engine.start();
  // Detaches on every way out of this function, before the engine goes.
  struct Hooked {
    const std::function<void(Engine*)>& hook;
    ~Hooked() {
      if (hook) hook(nullptr);
    }
  } hooked{opt.engine_hook};
  if (opt.engine_hook) opt.engine_hook(&engine);
  display.start();
  WorldState world = engine.world();  // lights the arrow keys move (published like the camera)
  size_t next_script = 0;
  int presented = 0;
  double last_loop = v.now(), last_animation = -1.0;
  while (!glfwWindowShouldClose(window) && !v.quit) {
    glfwWaitEventsTimeout(0.1);
    const double t = v.now(), dt = t - last_loop;
    last_loop = t;
    // Fly keys move while held, at a speed independent of the refresh rate.
    auto held = [&](int k) { return glfwGetKey(window, k) == GLFW_PRESS ? 1.0f : 0.0f; };
    const float right = held(GLFW_KEY_D) - held(GLFW_KEY_A), up = held(GLFW_KEY_E) - held(GLFW_KEY_Q),
                fwd = held(GLFW_KEY_W) - held(GLFW_KEY_S);
    if (right != 0 || up != 0 || fwd != 0)
      v.set_camera(fly_camera(v.camera, right, up, fwd, float(std::min(dt, 0.1))));
    // Arrow keys and page up/down move the first light, at the camera's orbit distance per second.
    const float lx = held(GLFW_KEY_RIGHT) - held(GLFW_KEY_LEFT),
                ly = held(GLFW_KEY_PAGE_UP) - held(GLFW_KEY_PAGE_DOWN),
                lz = held(GLFW_KEY_DOWN) - held(GLFW_KEY_UP);
    const float speed = glm::length(v.camera.eye - v.camera.look) * float(std::min(dt, 0.1));
    if ((lx != 0 || ly != 0 || lz != 0) && v.grabbed >= 0) {
      v.move_grabbed(speed * Vec3(lx, ly, lz));
    } else if ((lx != 0 || ly != 0 || lz != 0) && !world.lights.empty()) {
      world.lights[0].position += speed * Vec3(lx, ly, lz);
      engine.publish_world(world);
    }
    // Instances with a "motion" move at the display's pace (each move publishes a refit top).
    if (!scene.instance_motions.empty() && t - last_animation >= 1.0 / 60.0) {
      engine.animate_instances(engine.now());
      last_animation = t;
      v.dirty = true;
    }
    while (next_script < script.size() && script[next_script].time <= t) v.run_script(script[next_script++]);
    // Re-partition once the window has stopped changing size for a moment.
    if (v.pending_w > 0 && t - v.pending_since > 0.15) {
      if (!opt.fixed_layout && (v.pending_w != engine.width() || v.pending_h != engine.height()))
        engine.resize(v.pending_w, v.pending_h);
      v.pending_w = v.pending_h = 0;
    }
    if (auto e = engine.error()) return Error{"render thread failed: " + *e};
    bool is_new = false;
    display.acquire_latest(&is_new);
    if (!is_new && !v.dirty) continue;
    v.dirty = false;
    v.update_rate();
    int fw = 0, fh = 0;
    glfwGetFramebufferSize(window, &fw, &fh);
    if (fw <= 0 || fh <= 0) continue;  // minimised
    v.draw(fw, fh);
    ++presented;
    if (opt.max_frames > 0 && presented >= opt.max_frames) {
      if (!opt.screenshot_path.empty()) v.screenshot(opt.screenshot_path);
      v.quit = true;
    }
    glfwSwapBuffers(window);
  }
  display.stop();
  engine.stop();
  display.set_on_tick_info(nullptr);
  if (!opt.record_path.empty()) {
    v.recording.keyframes.push_back({v.now(), v.camera});
    if (auto r = write_text_file_atomic(opt.record_path, camera_path_to_json(v.recording, "frameless view --record"));
        !r.ok())
      return r.error();
    std::fprintf(stderr, "frameless: recorded %zu camera poses to %s (replay: frameless capture --path %s)\n",
                 v.recording.keyframes.size(), opt.record_path.c_str(), opt.record_path.c_str());
  }
  presenter.value().reset();  // GL objects go while their context still exists
  glfwDestroyWindow(window);
  return true;
}

}  // namespace frameless
