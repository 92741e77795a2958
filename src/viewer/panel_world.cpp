// The lights, materials and objects panels: edits published through the world channel (lights,
// materials, moving objects) and the instance top level, so render threads never wait for them.
#include <imgui.h>

#include <algorithm>
#include <cstdio>
#include <string>

#include "core/accel/instance_top.h"
#include "viewer/panel_state.h"
#include "viewer/viewer_controls.h"

namespace frameless {
namespace {

// A slider over [0, count) picking one of the scene's items; false when there are none.
bool pick(const char* what, int& index, size_t count) {
  if (count == 0) {
    ImGui::TextDisabled("the scene has no %s", what);
    return false;
  }
  index = std::clamp(index, 0, int(count) - 1);
  if (count > 1) ImGui::SliderInt(what, &index, 0, int(count) - 1);
  return true;
}

// Drag speed for positions: a hundredth of the camera's distance to what it looks at.
float step(const Viewer& v) { return 0.01f * glm::length(v.camera.eye - v.camera.look) + 1e-4f; }

}  // namespace

void lights_panel(Viewer& v, PanelState& p) {
  if (!pick("light", p.light, v.world.lights.size())) return;
  Light l = v.world.lights[size_t(p.light)];
  const bool directional = l.kind == LightKind::kDirectional;
  bool changed = false;
  if (directional) {
    ImGui::TextDisabled("directional light (its direction is fixed here)");
  } else {
    changed |= ImGui::DragFloat3("position", &l.position.x, step(v));
    changed |= ImGui::DragFloat("radius", &l.radius, 0.2f * step(v), 0.0f, 1e6f);
  }
  changed |= ImGui::ColorEdit3("colour", &l.color.x, ImGuiColorEditFlags_Float | ImGuiColorEditFlags_HDR);
  float intensity = std::max({l.color.x, l.color.y, l.color.z});
  if (ImGui::SliderFloat("intensity", &intensity, 0.0f, 10.0f, "%.2f", ImGuiSliderFlags_Logarithmic)) {
    const float now = std::max({l.color.x, l.color.y, l.color.z});
    l.color = now > 1e-20f ? l.color * (intensity / now) : Vec3(intensity);
    changed = true;
  }
  l.radius = std::max(0.0f, l.radius);
  l.color = glm::max(l.color, Vec3(0.0f));
  if (changed) (void)set_light(v, size_t(p.light), l);  // a refusal is in the status line
  ImGui::TextDisabled("arrows and PgUp/PgDn move light 0 too");
}

void materials_panel(Viewer& v, PanelState& p) {
  if (!pick("material", p.material, v.world.materials.size())) return;
  const size_t i = size_t(p.material);
  if (i < v.scene->materials.size()) ImGui::Text("%s", v.scene->materials[i].name.c_str());
  MaterialParams m = v.world.materials[i];
  bool changed = ImGui::ColorEdit3("kd (diffuse)", &m.kd.x, ImGuiColorEditFlags_Float);
  changed |= ImGui::ColorEdit3("ks (mirror)", &m.ks.x, ImGuiColorEditFlags_Float);
  changed |= ImGui::ColorEdit3("kh (highlight)", &m.kh.x, ImGuiColorEditFlags_Float);
  changed |= ImGui::SliderFloat("phong exponent", &m.phong_exponent, 1.0f, 10000.0f, "%.0f", ImGuiSliderFlags_Logarithmic);
  changed |= ImGui::ColorEdit3("emission", &m.emission.x, ImGuiColorEditFlags_Float | ImGuiColorEditFlags_HDR);
  m.kd = glm::max(m.kd, Vec3(0.0f)), m.ks = glm::max(m.ks, Vec3(0.0f)), m.kh = glm::max(m.kh, Vec3(0.0f));
  m.emission = glm::max(m.emission, Vec3(0.0f)), m.phong_exponent = std::max(m.phong_exponent, 0.0f);
  if (changed) (void)set_material(v, i, m);  // a refusal is in the status line
}

void objects_panel(Viewer& v, PanelState& p) {
  ImGui::TextUnformatted("moving objects");
  if (pick("object", p.object, v.world.object_position.size())) {
    Vec3 pos = v.world.object_position[size_t(p.object)];
    if (ImGui::DragFloat3("position##object", &pos.x, step(v))) (void)set_object_position(v, size_t(p.object), pos);
  }
  ImGui::Separator();
  ImGui::TextUnformatted("instances");
  const size_t instances = v.scene->geometry.instances.size();
  if (!pick("instance", p.instance, instances)) return;
  if (v.grabbed >= 0) p.instance = int(v.grabbed);
  if (ImGui::Button(v.grabbed >= 0 ? "release (I)" : "select the one at the centre (I)")) v.grab_or_release();
  Vec3 t = v.engine->instance_transform(uint32_t(p.instance)).t;
  if (ImGui::DragFloat3("translation", &t.x, step(v))) v.set_instance_translation(uint32_t(p.instance), t);
}

}  // namespace frameless
