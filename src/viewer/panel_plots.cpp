// The views-and-plots panel: the per-pixel state views, live plots of the engine and the display,
// and the error against a reference of the current view.
#include <imgui.h>

#include <algorithm>
#include <cstdio>

#include "display/levels_view.h"
#include "viewer/panel_state.h"
#include "viewer/viewer_controls.h"

namespace frameless {
namespace {

void plot(const char* label, const std::vector<float>& values, const char* unit, bool si_units) {
  char overlay[64];
  const float last = values.empty() ? 0.0f : values.back();
  if (si_units) std::snprintf(overlay, sizeof overlay, "%s%s", si(last).c_str(), unit);
  else std::snprintf(overlay, sizeof overlay, "%.3g%s", double(last), unit);
  const float top = values.empty() ? 1.0f : *std::max_element(values.begin(), values.end());
  ImGui::PlotLines(label, values.data(), int(values.size()), 0, overlay, 0.0f, std::max(top * 1.1f, 1e-6f),
                   ImVec2(ImGui::GetContentRegionAvail().x * 0.62f, 42.0f));
}

}  // namespace

void plots_panel(Viewer& v, PanelState& p, const ViewScale& s) {
  for (int m = 0; m < kViewModeCount; ++m) {
    if (m % 3) ImGui::SameLine();
    if (ImGui::RadioButton(to_string(ViewMode(m)), v.view == ViewMode(m))) v.view = ViewMode(m);
  }
  switch (v.view) {
    case ViewMode::age: ImGui::TextDisabled("age: black 0 .. white %.3g s", double(s.max_age)); break;
    case ViewMode::count: ImGui::TextDisabled("samples, log scale: white %s", si(s.max_count).c_str()); break;
    case ViewMode::variance: ImGui::TextDisabled("luminance variance, log scale: white %.3g", double(s.max_variance)); break;
    case ViewMode::epoch: ImGui::TextDisabled("camera epoch: green newest, red older"); break;
    case ViewMode::levels: ImGui::TextDisabled("levels (max %d): %s", s.max_levels, kLevelsLegend); break;
    default: break;
  }
  ImGui::Separator();
  const ViewerRates& r = v.rates;
  plot("samples/s", r.samples_per_s, "", true);
  plot("pixel updates/s", r.updates_per_s, "", true);
  plot("display CPU", r.display_cpu, " % of a core", false);
  plot("coverage", r.coverage, " %", false);
  ImGui::Separator();
  ImGui::SetNextItemWidth(120);
  ImGui::SliderInt("spp", &p.reference_spp, 8, 256, "%d", ImGuiSliderFlags_Logarithmic);
  ImGui::SameLine();
  ImGui::BeginDisabled(v.reference_job.valid());
  if (ImGui::Button(v.reference_job.valid() ? "rendering..." : "reference of this view"))
    if (auto e = apply_control(v, "reference", {std::to_string(p.reference_spp)}); !e.ok()) v.status = e.error().message;
  ImGui::EndDisabled();
  if (v.reference && v.reference_camera == v.camera)
    plot("RMSE", r.error, "", false);
  else
    ImGui::TextDisabled(v.reference ? "error: the camera moved off the reference's view"
                                    : "error: render a reference of this view to plot it");
}

}  // namespace frameless
