// The render-settings and camera panels.
#include <imgui.h>

#include <algorithm>
#include <thread>

#include "viewer/panel_state.h"
#include "viewer/viewer_controls.h"

namespace frameless {
namespace {

// A combo over names; returns the index chosen this frame, or -1.
int choose(const char* label, const char* const* names, int count, int current) {
  int chosen = -1;
  if (ImGui::BeginCombo(label, names[std::clamp(current, 0, count - 1)])) {
    for (int i = 0; i < count; ++i)
      if (ImGui::Selectable(names[i], i == current) && i != current) chosen = i;
    ImGui::EndCombo();
  }
  return chosen;
}

// Shows a control's one-line error where it happened.
void report(Viewer& v, const Result<bool>& r) {
  if (!r.ok()) v.status = r.error().message;
}

}  // namespace

void settings_panel(Viewer& v, PanelState& p) {
  const EngineConfig ec = v.engine->config();
  DisplayConfig dc = v.display->config();
  const Scene& s = *v.scene;
  ImGui::BeginDisabled(v.opt.fixed_layout);
  static const char* const modes[] = {"frameless", "conventional"};
  if (int m = choose("mode", modes, 2, ec.mode == RenderMode::frameless ? 0 : 1); m >= 0)
    v.engine->set_mode(m == 0 ? RenderMode::frameless : RenderMode::conventional);
  ImGui::EndDisabled();
  ImGui::BeginDisabled(!v.editable || v.opt.fixed_layout);
  static const char* const integrators[] = {"whitted", "path", "igi"};
  if (int i = choose("integrator", integrators, 3, int(s.settings.integrator) - 1); i >= 0)
    set_integrator(v, Integrator(i + 1));
  static const char* const shadows[] = {"hard", "soft", "area", "beam"};
  if (int i = choose("shadows", shadows, 4, int(s.settings.shadows)); i >= 0) set_shadows(v, ShadowMode(i));
  static const char* const accels[] = {"bvh", "grid", "auto"};
  if (int i = choose("acceleration", accels, 3, int(s.settings.accel)); i >= 0) set_accel(v, AccelKind(i));
  bool closed = ec.closed_loop;
  if (ImGui::Checkbox("closed loop", &closed)) set_closed_loop(v, closed);
  ImGui::EndDisabled();
  if (ImGui::SliderFloat("alpha", &dc.blend.alpha, 0.01f, 1.0f, "%.3f", ImGuiSliderFlags_Logarithmic))
    v.change_display([&](DisplayConfig& c) { c.blend.alpha = std::clamp(dc.blend.alpha, 0.01f, 1.0f); });
  float hz = float(dc.refresh_hz);
  if (ImGui::SliderFloat("refresh Hz", &hz, 1.0f, 240.0f, "%.0f"))
    v.change_display([&](DisplayConfig& c) { c.refresh_hz = std::clamp(double(hz), 1.0, 240.0); });
  bool on = dc.blend.temporal;
  if (ImGui::Checkbox("temporal weights", &on)) v.change_display([&](DisplayConfig& c) { c.blend.temporal = on; });
  ImGui::SameLine();
  on = dc.blend.denoise;
  if (ImGui::Checkbox("denoise", &on)) v.change_display([&](DisplayConfig& c) { c.blend.denoise = on; });
  ImGui::BeginDisabled(v.opt.fixed_layout);
  on = dc.blend.reproject;
  if (ImGui::Checkbox("reprojection", &on)) v.change_display([&](DisplayConfig& c) { c.blend.reproject = on; });
  // Repartitioning as a slider moves would restart the threads every frame: apply on release.
  float& update = p.update_percent;
  int& threads = p.threads;
  if (!ImGui::IsAnyItemActive()) update = float(ec.update_percent), threads = v.engine->thread_count();
  ImGui::SliderFloat("update %", &update, 0.01f, 100.0f, "%.2f", ImGuiSliderFlags_Logarithmic);
  if (ImGui::IsItemDeactivatedAfterEdit()) v.engine->set_update_percent(std::clamp(double(update), 0.01, 100.0));
  const int most = std::max(8, 4 * int(std::thread::hardware_concurrency()));
  ImGui::SliderInt("threads", &threads, 1, most);
  if (ImGui::IsItemDeactivatedAfterEdit()) v.engine->set_threads(std::clamp(threads, 1, 256));
  ImGui::EndDisabled();
}

void camera_panel(Viewer& v, PanelState& p) {
  Camera c = v.camera;
  bool changed = ImGui::DragFloat3("eye", &c.eye.x, 0.01f * glm::length(c.eye - c.look) + 1e-3f);
  changed |= ImGui::DragFloat3("look at", &c.look.x, 0.01f * glm::length(c.eye - c.look) + 1e-3f);
  changed |= ImGui::DragFloat3("up", &c.up.x, 0.01f);
  changed |= ImGui::SliderFloat("fov", &c.fov_deg, 5.0f, 150.0f, "%.1f deg");
  if (changed && camera_is_valid(c)) v.set_camera(c);
  if (ImGui::Button("reset (R)")) v.set_camera(v.home);
  ImGui::Text("path: %zu poses recorded", v.recording.keyframes.size());
  ImGui::InputText("file", p.camera_file, sizeof p.camera_file);
  if (ImGui::Button("save path")) report(v, apply_control(v, "camera.save", {p.camera_file}));
  ImGui::SameLine();
  if (ImGui::Button("load and play")) report(v, apply_control(v, "camera.load", {p.camera_file}));
  if (!v.playing.keyframes.empty()) {
    ImGui::SameLine();
    if (ImGui::Button("stop")) v.playing = {};
    ImGui::ProgressBar(float(std::min(1.0, (v.now() - v.playing_since) / std::max(1e-6, v.playing.duration()))));
  }
}

}  // namespace frameless
