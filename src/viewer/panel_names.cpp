// The panels by name (the script's "panel NAME") and title, with or without ImGui in the build.
#include <iterator>

#include "viewer/panels.h"

namespace frameless {

const std::vector<PanelName>& panel_list() {
  static const std::vector<PanelName> panels = {
      {"settings", "Render settings"}, {"camera", "Camera"}, {"lights", "Lights"},
      {"materials", "Materials"}, {"objects", "Objects and instances"}, {"volumes", "Volumes"},
      {"plots", "Views and live plots"}, {"files", "Files"}};
  return panels;
}

bool is_panel_name(const std::string& name) {
  for (const PanelName& p : panel_list())
    if (name == p.name) return true;
  return false;
}

std::string panel_names() {
  std::string s;
  for (const PanelName& p : panel_list()) s += (s.empty() ? "" : ", ") + std::string(p.name);
  return s;
}

}  // namespace frameless
