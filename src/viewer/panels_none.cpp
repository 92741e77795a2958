// Builds without Dear ImGui (libimgui-dev absent): no panels; the viewer keeps its keys and
// bitmap overlay, and scripts that name a panel still parse.
#include "viewer/panels.h"

namespace frameless {

struct PanelState {};

Panels::Panels(GLFWwindow* window) : window_(window) {}
Panels::~Panels() = default;

std::unique_ptr<Panels> Panels::create(GLFWwindow*, std::string& why) {
  why = "this build has no Dear ImGui (apt-get install libimgui-dev, then rebuild)";
  return nullptr;
}

void Panels::open(const std::string&) {}
bool Panels::wants_mouse() const { return false; }
bool Panels::wants_keyboard() const { return false; }
void Panels::draw(Viewer&, const ViewScale&) {}

}  // namespace frameless
