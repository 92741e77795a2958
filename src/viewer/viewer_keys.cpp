// The viewer's keys (the help lists them): settings, views, snapshots, grabbing instances.
#define GLFW_INCLUDE_NONE
#include <GLFW/glfw3.h>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdio>
#include <map>

#include "display/volume_keys.h"
#include "viewer/panels.h"
#include "viewer/viewer_state.h"

namespace frameless {

int key_from_name(const std::string& n) {
  static const std::map<std::string, int> named = {
      {"LEFT_BRACKET", GLFW_KEY_LEFT_BRACKET}, {"RIGHT_BRACKET", GLFW_KEY_RIGHT_BRACKET},
      {"MINUS", GLFW_KEY_MINUS}, {"EQUAL", GLFW_KEY_EQUAL}, {"COMMA", GLFW_KEY_COMMA},
      {"PERIOD", GLFW_KEY_PERIOD}, {"F1", GLFW_KEY_F1}, {"ESCAPE", GLFW_KEY_ESCAPE},
      {"TAB", GLFW_KEY_TAB}};
  if (n.size() == 1 && std::isalnum((unsigned char)n[0])) return std::toupper((unsigned char)n[0]);
  auto it = named.find(n);
  return it == named.end() ? -1 : it->second;
}

void Viewer::key(int k) {
  switch (k) {
    case GLFW_KEY_ESCAPE: quit = true; return;
    case GLFW_KEY_R: set_camera(home); return;
    case GLFW_KEY_TAB:
      if (panels) panels->set_visible(!panels->visible());
      dirty = true;
      return;
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
  if (editable && is_volume_key(*editable, k)) {
    edit_volumes([k](Scene& s) { return frameless::edit_volumes(s, k); });
    return;
  }
  switch (k) {
    case GLFW_KEY_M:
      engine->set_mode(engine->config().mode == RenderMode::frameless ? RenderMode::conventional
                                                                      : RenderMode::frameless);
      break;
    case GLFW_KEY_V: view = next_view(view); break;
    case GLFW_KEY_H: case GLFW_KEY_F1: help = !help; break;
    case GLFW_KEY_O: overlay_on = !overlay_on; break;
    case GLFW_KEY_P: save_image("exr"); break;
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

// Grabs the instance seen at the centre of the view (OpenRT's "move parts of the power plant
// around"), or releases the one grabbed.
void Viewer::grab_or_release() {
  if (grabbed >= 0) {
    status = "released instance " + std::to_string(grabbed);
    grabbed = -1;
    return;
  }
  const std::shared_ptr<const InstanceTop> top = engine->instance_top();
  const CameraBasis b = make_camera_basis(camera, engine->width(), engine->height());
  Hit hit;
  const Ray r = camera_ray(b, 0.5f * float(engine->width()), 0.5f * float(engine->height()));
  if (top && scene->accel.intersect(r, hit, top.get()) && hit.inst != kInvalidId) {
    grabbed = top->declared[hit.inst];
    status = "grabbed instance " + std::to_string(grabbed) + ": arrows and PgUp/PgDn move it, I releases";
  } else {
    status = "no instance at the centre of the view";
  }
}

// Moves the grabbed instance by `d` (world units); a refit top level is published.
void Viewer::move_grabbed(const Vec3& d) {
  set_instance_translation(uint32_t(grabbed), engine->instance_transform(uint32_t(grabbed)).t + d);
}

}  // namespace frameless
