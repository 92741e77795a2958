// Dear ImGui panels over the frameless image (Tab shows and hides them): render settings, camera,
// lights, materials, objects, volumes, views and live plots, files. Main (window) thread: it owns
// GL and the panels; every edit goes through viewer_controls.h, so nothing here blocks a render
// thread or the display tick. Where ImGui cannot run (a build without it, a context it refuses)
// create() returns null and the viewer keeps its keys and bitmap overlay.
#pragma once
#include <memory>
#include <string>
#include <vector>

#include "display/gl_presenter.h"

struct GLFWwindow;

namespace frameless {

struct Viewer;
struct PanelState;

class Panels {
 public:
  // Installs ImGui on the window (its callbacks chain to the ones already installed). Null, with
  // the reason in `why`, when ImGui is not available.
  static std::unique_ptr<Panels> create(GLFWwindow* window, std::string& why);
  ~Panels();
  Panels(const Panels&) = delete;
  Panels& operator=(const Panels&) = delete;

  bool visible() const { return visible_; }
  void set_visible(bool on) { visible_ = on; }
  // Shows the panels with panel `name` expanded (the script's "panel NAME").
  void open(const std::string& name);
  // Whether ImGui uses the mouse or keyboard now (the viewer's camera controls then keep off).
  bool wants_mouse() const;
  bool wants_keyboard() const;
  // Builds the panels for this frame and draws them over the image in the bound framebuffer.
  void draw(Viewer& v, const ViewScale& scale);

 private:
  explicit Panels(GLFWwindow* window);
  GLFWwindow* window_;
  bool visible_ = false;
  std::unique_ptr<PanelState> state_;
};

// The panels in their order: the name "panel NAME" takes and the header's title.
struct PanelName {
  const char* name;
  const char* title;
};
const std::vector<PanelName>& panel_list();
// Whether `name` is one (settings, camera, lights, materials, objects, volumes, plots, files).
bool is_panel_name(const std::string& name);
std::string panel_names();

}  // namespace frameless
