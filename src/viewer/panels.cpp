// The panels' window: ImGui on the viewer's GLFW window and GL context, one column of collapsing
// panels at the left, drawn after the image.
#include "viewer/panels.h"

#define GLFW_INCLUDE_NONE
#include <GLFW/glfw3.h>
#include <imgui.h>
#include <backends/imgui_impl_glfw.h>
#include <backends/imgui_impl_opengl3.h>

#include "viewer/panel_state.h"

namespace frameless {
Panels::Panels(GLFWwindow* window) : window_(window), state_(std::make_unique<PanelState>()) {}

std::unique_ptr<Panels> Panels::create(GLFWwindow* window, std::string& why) {
  IMGUI_CHECKVERSION();
  ImGui::CreateContext();
  ImGuiIO& io = ImGui::GetIO();
  io.IniFilename = nullptr;  // no imgui.ini left in the user's folder
  ImGui::StyleColorsDark();
  ImGui::GetStyle().WindowRounding = 0.0f;
  if (!ImGui_ImplGlfw_InitForOpenGL(window, true)) {
    why = "ImGui cannot use this window";
    ImGui::DestroyContext();
    return nullptr;
  }
  if (!ImGui_ImplOpenGL3_Init("#version 330 core")) {
    why = "ImGui cannot draw with this OpenGL context";
    ImGui_ImplGlfw_Shutdown();
    ImGui::DestroyContext();
    return nullptr;
  }
  return std::unique_ptr<Panels>(new Panels(window));
}

Panels::~Panels() {
  ImGui_ImplOpenGL3_Shutdown();
  ImGui_ImplGlfw_Shutdown();
  ImGui::DestroyContext();
}

void Panels::open(const std::string& name) {
  visible_ = true;
  state_->force_open = name;
}

bool Panels::wants_mouse() const { return visible_ && ImGui::GetIO().WantCaptureMouse; }
bool Panels::wants_keyboard() const { return visible_ && ImGui::GetIO().WantCaptureKeyboard; }

void Panels::draw(Viewer& v, const ViewScale& scale) {
  ImGui_ImplOpenGL3_NewFrame();
  ImGui_ImplGlfw_NewFrame();
  ImGui::NewFrame();
  int fw = 0, fh = 0;
  glfwGetWindowSize(window_, &fw, &fh);
  const float width = std::min(340.0f, 0.5f * float(fw));
  ImGui::SetNextWindowPos(ImVec2(0, 0), ImGuiCond_Always);
  ImGui::SetNextWindowSize(ImVec2(width, float(fh)), ImGuiCond_Always);
  ImGui::SetNextWindowBgAlpha(0.82f);
  ImGui::Begin("frameless", nullptr,
               ImGuiWindowFlags_NoMove | ImGuiWindowFlags_NoResize | ImGuiWindowFlags_NoCollapse);
  ImGui::PushItemWidth(-118.0f);  // room for the labels right of the widgets
  ImGui::TextUnformatted(v.scene_label.c_str());
  ImGui::Text("%dx%d  %s samples/s  Tab hides", v.engine->width(), v.engine->height(),
              si(v.rates.last(v.rates.samples_per_s)).c_str());
  if (!v.status.empty()) ImGui::TextWrapped("%s", v.status.c_str());
  PanelState& p = *state_;
  for (const PanelName& named : panel_list()) {
    if (p.force_open == named.name) ImGui::SetNextItemOpen(true);
    if (!ImGui::CollapsingHeader(named.title)) continue;
    ImGui::PushID(named.name);
    const std::string n = named.name;
    if (n == "settings") settings_panel(v, p);
    else if (n == "camera") camera_panel(v, p);
    else if (n == "lights") lights_panel(v, p);
    else if (n == "materials") materials_panel(v, p);
    else if (n == "objects") objects_panel(v, p);
    else if (n == "volumes") volumes_panel(v, p);
    else if (n == "plots") plots_panel(v, p, scale);
    else if (n == "files") files_panel(v, p);
    ImGui::PopID();
  }
  p.force_open.clear();
  ImGui::PopItemWidth();
  ImGui::End();
  ImGui::Render();
  ImGui_ImplOpenGL3_RenderDrawData(ImGui::GetDrawData());
}

}  // namespace frameless
