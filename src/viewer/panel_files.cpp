// The files panel: open a scene, mesh, model or volume (a folder browser; dropping a file on the
// window does the same), save the displayed image, capture the window's images.
#include <imgui.h>

#include <algorithm>
#include <cstring>
#include <filesystem>

#include "core/scenes/scene_load.h"
#include "viewer/panel_state.h"
#include "viewer/viewer_controls.h"

namespace fs = std::filesystem;

namespace frameless {
namespace {

// Lists `folder` (folders first, then the files the viewer opens; hidden ones left out).
void list(PanelState& p) {
  p.entries.clear();
  std::error_code ec;
  for (const fs::directory_entry& e : fs::directory_iterator(p.folder, ec)) {
    const std::string name = e.path().filename().string();
    const bool folder = e.is_directory(ec);
    if (name.empty() || name[0] == '.' || (!folder && !is_scene_file(e.path().string()))) continue;
    p.entries.push_back({name, folder});
  }
  std::sort(p.entries.begin(), p.entries.end(), [](auto& a, auto& b) {
    return a.second != b.second ? a.second : a.first < b.first;
  });
}

}  // namespace

void files_panel(Viewer& v, PanelState& p) {
  if (p.folder.empty()) {
    std::error_code ec;
    p.folder = fs::current_path(ec).string();
    list(p);
  }
  ImGui::BeginDisabled(!v.editable || v.opt.fixed_layout);
  ImGui::TextWrapped("%s", p.folder.c_str());
  if (ImGui::BeginListBox("##files", ImVec2(-1, 120))) {
    if (ImGui::Selectable("..")) {
      p.folder = fs::path(p.folder).parent_path().string();
      list(p);
    }
    for (size_t k = 0; k < p.entries.size(); ++k) {
      const auto [name, folder] = p.entries[k];
      const std::string full = (fs::path(p.folder) / name).string();
      if (!ImGui::Selectable((folder ? name + "/" : name).c_str(), full == p.path,
                             ImGuiSelectableFlags_AllowDoubleClick))
        continue;
      if (folder) {
        p.folder = full;
        list(p);
        break;
      }
      std::snprintf(p.path, sizeof p.path, "%s", full.c_str());
      if (ImGui::IsMouseDoubleClicked(0)) v.open_scene(p.path);
    }
    ImGui::EndListBox();
  }
  ImGui::InputText("##path", p.path, sizeof p.path);
  ImGui::SameLine();
  if (ImGui::Button("open") && p.path[0]) v.open_scene(p.path);
  ImGui::TextDisabled("or drop a .json, .obj, .ply, .gltf, .glb or .vdb file on the window");
  ImGui::EndDisabled();
  ImGui::Separator();
  if (ImGui::Button("save EXR")) v.save_image("exr");
  ImGui::SameLine();
  if (ImGui::Button("save PNG")) v.save_image("png");
  ImGui::SameLine();
  ImGui::TextDisabled("into %s/", v.opt.snapshot_dir.c_str());
  if (v.capture_dir.empty()) {
    if (ImGui::Button("start capture")) v.start_capture();
  } else {
    if (ImGui::Button("stop capture")) v.stop_capture();
    ImGui::SameLine();
    ImGui::Text("%d frames", v.capture_frames);
  }
}

}  // namespace frameless
