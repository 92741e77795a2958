// The volumes panel: isovalues, transfer-function presets, and a transfer-function editor drawn
// over the histogram of the data's values (drag a point: value across, opacity up).
#include <imgui.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <iterator>

#include "viewer/panel_state.h"
#include "viewer/viewer_controls.h"

namespace frameless {
namespace {

constexpr int kBins = 64;

// Log counts of the grid's values in kBins bins over its range, from at most ~64^3 voxels.
std::vector<float> histogram(const VolumeGrid& g) {
  std::vector<float> bins(kBins, 0.0f);
  const float span = g.max_value - g.min_value;
  const int sx = std::max(1, g.nx / 64), sy = std::max(1, g.ny / 64), sz = std::max(1, g.nz / 64);
  for (int z = 0; z < g.nz; z += sz)
    for (int y = 0; y < g.ny; y += sy)
      for (int x = 0; x < g.nx; x += sx) {
        const float t = span > 0 ? (g.at(x, y, z) - g.min_value) / span : 0.0f;
        bins[size_t(std::clamp(int(t * kBins), 0, kBins - 1))] += 1.0f;
      }
  float top = 0.0f;
  for (float& b : bins) top = std::max(top, b = std::log1p(b));
  for (float& b : bins) b = top > 0 ? b / top : 0.0f;
  return bins;
}

// Draws the function's opacity over the histogram just drawn and lets points be dragged; returns
// whether a drag ended (apply then).
bool edit_over_histogram(PanelState& p, const VolumeGrid& g, ImVec2 lo, ImVec2 size) {
  ImDrawList* draw = ImGui::GetWindowDrawList();
  const float span = std::max(g.max_value - g.min_value, 1e-30f);
  auto at = [&](const TransferPoint& q) {
    return ImVec2(lo.x + size.x * (q.value - g.min_value) / span, lo.y + size.y * (1.0f - q.opacity));
  };
  for (size_t k = 1; k < p.points.size(); ++k)
    draw->AddLine(at(p.points[k - 1]), at(p.points[k]), IM_COL32(255, 255, 255, 220), 2.0f);
  for (const TransferPoint& q : p.points)
    draw->AddCircleFilled(at(q), 5.0f, ImGui::ColorConvertFloat4ToU32(ImVec4(q.color.x, q.color.y, q.color.z, 1.0f)));
  ImGui::SetCursorScreenPos(lo);
  ImGui::InvisibleButton("editor", size);
  int& dragged = p.dragged_point;
  if (ImGui::IsItemActivated()) {
    const ImVec2 m = ImGui::GetIO().MousePos;
    float best = 1e30f;
    for (size_t k = 0; k < p.points.size(); ++k) {
      const ImVec2 q = at(p.points[k]);
      const float d = (q.x - m.x) * (q.x - m.x) + (q.y - m.y) * (q.y - m.y);
      if (d < best) best = d, dragged = int(k);
    }
  }
  if (ImGui::IsItemActive() && dragged >= 0 && size_t(dragged) < p.points.size()) {
    const ImVec2 m = ImGui::GetIO().MousePos;
    TransferPoint& q = p.points[size_t(dragged)];
    q.value = g.min_value + span * std::clamp((m.x - lo.x) / size.x, 0.0f, 1.0f);
    q.opacity = std::clamp(1.0f - (m.y - lo.y) / size.y, 0.0f, 1.0f);
  }
  const bool done = ImGui::IsItemDeactivated() && dragged >= 0;
  if (!ImGui::IsItemActive()) dragged = -1;
  return done;
}

void apply_points(Viewer& v, PanelState& p, size_t volume) {
  std::vector<TransferPoint> sorted = p.points;
  std::stable_sort(sorted.begin(), sorted.end(), [](auto& a, auto& b) { return a.value < b.value; });
  if (auto r = set_transfer(v, volume, sorted); !r.ok()) v.status = r.error().message;
  p.points_of = nullptr;  // copy the applied function back next frame
}

}  // namespace

void volumes_panel(Viewer& v, PanelState& p) {
  if (p.volumes_of != v.scene) {  // another scene: nothing cached belongs to it
    p.volumes_of = v.scene;
    p.histograms.clear();
    p.points_of = nullptr;
    p.volume = 0;
  }
  const std::vector<VolumeObject>& volumes = v.scene->volumes;
  if (volumes.empty()) {
    ImGui::TextDisabled("the scene has no volumes");
    return;
  }
  p.volume = std::clamp(p.volume, 0, int(volumes.size()) - 1);
  if (volumes.size() > 1) ImGui::SliderInt("volume", &p.volume, 0, int(volumes.size()) - 1);
  const size_t i = size_t(p.volume);
  const VolumeObject& vol = volumes[i];
  const VolumeGrid& g = *vol.grid;
  ImGui::Text("%s: %dx%dx%d, values %g..%g", vol.source.c_str(), g.nx, g.ny, g.nz, double(g.min_value), double(g.max_value));
  ImGui::BeginDisabled(!v.editable || v.opt.fixed_layout);
  if (vol.mode == VolumeMode::kIsosurface) {
    float iso = vol.isovalues.empty() ? g.min_value : vol.isovalues[0];
    ImGui::SliderFloat("isovalue", &iso, g.min_value, g.max_value, "%.4g");
    // Each change restarts the render threads: apply when the slider is let go.
    if (ImGui::IsItemDeactivatedAfterEdit()) set_isovalue(v, i, iso);
    ImGui::EndDisabled();
    return;
  }
  std::vector<float>& bins = p.histograms[&g];
  if (bins.empty()) bins = histogram(g);
  if (p.points_of != vol.tf.get()) p.points = vol.tf->points(), p.points_of = vol.tf.get();
  const char* current = vol.tf->preset().empty() ? "(points)" : vol.tf->preset().c_str();
  if (ImGui::BeginCombo("preset", current)) {
    for (const char* name : TransferFunction::kPresets)
      if (ImGui::Selectable(name, vol.tf->preset() == name))
        if (auto r = set_transfer_preset(v, i, name); !r.ok()) v.status = r.error().message;
    ImGui::EndCombo();
  }
  const ImVec2 size(ImGui::GetContentRegionAvail().x, 90.0f);
  const ImVec2 lo = ImGui::GetCursorScreenPos();
  ImGui::PlotHistogram("##histogram", bins.data(), int(bins.size()), 0, nullptr, 0.0f, 1.0f, size);
  if (edit_over_histogram(p, g, lo, size)) apply_points(v, p, i);
  ImGui::TextDisabled("histogram (log counts); drag a point: value, opacity");
  bool edited = false;
  int remove = -1;
  for (size_t k = 0; k < p.points.size(); ++k) {
    TransferPoint& q = p.points[k];
    ImGui::PushID(int(k));
    ImGui::SetNextItemWidth(80);
    ImGui::DragFloat("##value", &q.value, 0.002f * (g.max_value - g.min_value), g.min_value, g.max_value, "%.3g");
    edited |= ImGui::IsItemDeactivatedAfterEdit();
    ImGui::SameLine();
    edited |= ImGui::ColorEdit3("##colour", &q.color.x, ImGuiColorEditFlags_NoInputs);
    ImGui::SameLine();
    ImGui::SetNextItemWidth(80);
    ImGui::SliderFloat("##opacity", &q.opacity, 0.0f, 1.0f, "a %.2f");
    edited |= ImGui::IsItemDeactivatedAfterEdit();
    ImGui::SameLine();
    if (ImGui::SmallButton("x") && p.points.size() > 1) remove = int(k);
    ImGui::PopID();
  }
  if (remove >= 0) p.points.erase(p.points.begin() + remove), edited = true;
  if (ImGui::SmallButton("add a point")) {
    TransferPoint q = p.points.back();
    q.value = 0.5f * (q.value + g.max_value);
    p.points.push_back(q);
    edited = true;
  }
  if (edited) apply_points(v, p, i);
  ImGui::EndDisabled();
}

}  // namespace frameless
