// The viewer's session (scene, engine, display thread) and the edits that go through it.
#include "viewer/viewer_state.h"

#define GLFW_INCLUDE_NONE
#include <GLFW/glfw3.h>

#include <cstdio>

#include "core/scenes/scene_load.h"

namespace frameless {

Viewer::Viewer(const Scene& shown, const ViewerOptions& options)
    : opt(options), scene(&shown), editable(options.editable_scene) {}

Viewer::~Viewer() { stop_session(); }

double Viewer::now() const {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

bool Viewer::may_rebuild() {
  if (!opt.fixed_layout && editable) return true;
  status = opt.fixed_layout ? "cluster: the scene and the layout are fixed" : "this scene cannot be changed here";
  std::fprintf(stderr, "frameless: %s\n", status.c_str());
  dirty = true;
  return false;
}

// A reference shows the scene as loaded: an edit of what moves makes it another picture.
void Viewer::world_changed() {
  world_edited = true;
  if (reference_job.valid()) reference_outdated = true;
  reference.reset();
  rates.error.clear();
}

// The scene is about to change: a reference being rendered is waited for (it reads the scene)
// and thrown away with the one in use (another picture now).
void Viewer::drop_reference() {
  if (reference_job.valid()) reference_job.wait();
  reference_job = {};
  reference_outdated = false;
  reference.reset();
  rates.error.clear();
}

void Viewer::start_session() {
  engine = std::make_unique<Engine>(*scene, engine_config, camera);
  display = std::make_unique<DisplayThread>(*engine, display_config);
  // Each display tick wakes the main loop (glfwPostEmptyEvent is safe from any thread).
  display->set_on_tick_info([](const FrameInfo&) { glfwPostEmptyEvent(); });
  engine->start();
  if (opt.engine_hook) opt.engine_hook(engine.get());
  display->start();
  world = engine->world();
  rates = ViewerRates{};
  world_edited = false;
  captured_tick = ~uint64_t(0);  // the new display counts its ticks from 0
  dirty = true;
}

void Viewer::stop_session() {
  drop_reference();  // its job reads the scene
  if (!engine) return;
  display_config = display->config();
  display->stop();
  engine->stop();
  display->set_on_tick_info(nullptr);
  if (opt.engine_hook) opt.engine_hook(nullptr);
  engine_config = engine->config();
  display.reset();
  engine.reset();
}

void Viewer::rebuild(const std::string& what, const std::function<void(Scene&, EngineConfig&)>& edit) {
  if (!may_rebuild()) return;
  const WorldState kept = world;  // lights, materials and objects as edited so far
  const bool edited = world_edited;
  stop_session();
  edit(*editable, engine_config);
  start_session();
  // The new engine starts from the scene's own world: the edits carry over.
  if (edited && kept.lights.size() == world.lights.size() && kept.materials.size() == world.materials.size() &&
      kept.object_position.size() == world.object_position.size()) {
    world = kept;
    (void)publish_world();  // checked when it was edited
  }
  status = what + " (render threads restarted)";
  std::fprintf(stderr, "frameless: %s\n", status.c_str());
}

void Viewer::open_scene(const std::string& path) {
  if (!may_rebuild()) return;
  auto loaded = load_scene(path);
  if (!loaded.ok()) {
    status = loaded.error().message;
    std::fprintf(stderr, "frameless: %s\n", status.c_str());
    dirty = true;
    return;
  }
  stop_session();
  opened = std::move(loaded.value());
  scene = editable = opened.get();
  scene_label = path;
  camera = home = scene->camera;
  grabbed = -1;
  playing = {};
  start_session();
  glfwSetWindowTitle(window, ("frameless - " + path).c_str());
  status = "opened " + path;
  std::fprintf(stderr, "frameless: %s\n", status.c_str());
}

void Viewer::set_camera(const Camera& c) {
  if (!camera_is_valid(c) || c == camera) return;
  camera = c;
  engine->publish_camera(c);
  recording.keyframes.push_back({now(), c});
  dirty = true;
}

void Viewer::change_display(const std::function<void(DisplayConfig&)>& f) {
  DisplayConfig c = display->config();
  f(c);
  display->set_config(c);
  display_config = c;
  dirty = true;
}

Result<bool> Viewer::publish_world() {
  dirty = true;
  if (const std::string p = world_problem(world, initial_world(*scene)); !p.empty()) {
    world = engine->world();  // keep the last good one
    status = p;
    std::fprintf(stderr, "frameless: %s\n", status.c_str());
    return Error{p};
  }
  engine->publish_world(world);  // the render threads pick it up at their update percentage
  world_changed();
  return true;
}

// Volumes are read by the render threads without a lock: they stop while the scene changes, then
// every pixel restarts (the same camera, published again, is a new epoch).
void Viewer::edit_volumes(const std::function<std::string(Scene&)>& edit) {
  if (!may_rebuild()) return;
  drop_reference();
  engine->stop();
  status = edit(*editable);
  std::fprintf(stderr, "frameless: %s\n", status.c_str());
  engine->start();
  engine->publish_camera(camera);
  dirty = true;
}

void Viewer::set_instance_translation(uint32_t declared, const Vec3& t) {
  Affine a = engine->instance_transform(declared);
  a.t = t;
  InstanceUpdate u;
  try {
    engine->move_instances({{declared, a}}, &u);
  } catch (const std::exception& e) {
    status = e.what();
    std::fprintf(stderr, "frameless: %s\n", status.c_str());
    dirty = true;
    return;
  }
  world_changed();
  char buf[160];
  std::snprintf(buf, sizeof buf, "instance %u moved: top level %s in %.2f ms", declared,
                u.rebuilt ? "rebuilt" : "refit", u.copy_ms + u.refit_ms + u.rebuild_ms);
  status = buf;
  dirty = true;
}

}  // namespace frameless
