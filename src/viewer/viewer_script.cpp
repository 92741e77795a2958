// The viewer's timed scripts (tests, demos): parsed and checked before the window opens, run by
// the main loop when their time comes.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <map>
#include <sstream>

#define GLFW_INCLUDE_NONE
#include <GLFW/glfw3.h>

#include "display/camera_controls.h"
#include "viewer/panels.h"
#include "viewer/viewer_controls.h"
#include "viewer/viewer_state.h"

namespace frameless {

Result<std::vector<ViewerScriptLine>> parse_viewer_script(const std::string& text,
                                                           const std::string& path) {
  // Arguments per command; -1: one or more.
  static const std::map<std::string, int> arity = {
      {"orbit", 2}, {"pan", 2}, {"zoom", 1}, {"fly", 4}, {"key", 1}, {"resize", 2},
      {"screenshot", 1}, {"quit", 0}, {"panel", 1}, {"set", -1}, {"open", 1}};
  std::vector<ViewerScriptLine> out;
  std::istringstream in(text);
  std::string line;
  for (int n = 1; std::getline(in, line); ++n) {
    if (auto h = line.find('#'); h != std::string::npos) line.resize(h);
    std::istringstream ls(line);
    ViewerScriptLine l;
    l.line = n;
    std::string t;
    if (!(ls >> t)) continue;
    const std::string where = path + ":" + std::to_string(n) + ": ";
    char* end = nullptr;
    l.time = std::strtod(t.c_str(), &end);
    if (*end || !std::isfinite(l.time) || l.time < 0) return Error{where + "time: expected seconds >= 0, got '" + t + "'"};
    if (!(ls >> l.command)) return Error{where + "command: missing"};
    auto it = arity.find(l.command);
    if (it == arity.end()) return Error{where + "command: unknown '" + l.command + "'"};
    for (std::string a; ls >> a;) l.args.push_back(a);
    if (it->second < 0 ? l.args.size() < 2 : l.args.size() != size_t(it->second))
      return Error{where + l.command + ": expected " +
                   (it->second < 0 ? std::string("a control and its values") : std::to_string(it->second) + " arguments")};
    if (l.command == "key" && key_from_name(l.args[0]) < 0)
      return Error{where + "key: unknown key '" + l.args[0] + "'"};
    if (l.command == "orbit" || l.command == "pan" || l.command == "zoom" || l.command == "fly" ||
        l.command == "resize")
      for (const std::string& a : l.args) {
        char* e = nullptr;
        const double x = std::strtod(a.c_str(), &e);
        if (e == a.c_str() || *e || !std::isfinite(x) || std::abs(x) > 1e6)
          return Error{where + l.command + ": '" + a + "' is not a number (at most 1e6 in size)"};
        if (l.command == "resize" && !(x >= 1 && x <= 16384 && x == std::floor(x)))
          return Error{where + "resize: '" + a + "' is not a size in pixels (1..16384)"};
      }
    if (l.command == "panel" && !is_panel_name(l.args[0]))
      return Error{where + "panel: unknown panel '" + l.args[0] + "' (" + panel_names() + ")"};
    out.push_back(l);
  }
  std::stable_sort(out.begin(), out.end(), [](auto& a, auto& b) { return a.time < b.time; });
  return out;
}

void run_script_line(Viewer& v, const ViewerScriptLine& l) {
  auto f = [&](size_t i) { return i < l.args.size() ? std::strtof(l.args[i].c_str(), nullptr) : 0.0f; };
  int fw = 0, fh = 0;
  glfwGetFramebufferSize(v.window, &fw, &fh);
  const std::string where = v.opt.script_path + ":" + std::to_string(l.line) + ": ";
  if (l.command == "orbit") v.set_camera(orbit_camera(v.camera, f(0), f(1)));
  else if (l.command == "pan") v.set_camera(pan_camera(v.camera, f(0), f(1), fh));
  else if (l.command == "zoom") v.set_camera(zoom_camera(v.camera, f(0)));
  else if (l.command == "fly") v.set_camera(fly_camera(v.camera, f(0), f(1), f(2), f(3)));
  else if (l.command == "key") v.key(key_from_name(l.args[0]));
  else if (l.command == "resize") glfwSetWindowSize(v.window, int(f(0)), int(f(1)));
  else if (l.command == "screenshot") v.screenshot(l.args[0]);
  else if (l.command == "quit") v.quit = true;
  else if (l.command == "open") v.open_scene(l.args[0]);
  else if (l.command == "panel") {
    if (v.panels) v.panels->open(l.args[0]);
    else std::fprintf(stderr, "frameless: %spanel: the panels are not available here\n", where.c_str());
  } else if (l.command == "set") {
    auto r = apply_control(v, l.args[0], std::vector<std::string>(l.args.begin() + 1, l.args.end()));
    if (!r.ok()) {
      v.status = r.error().message;
      std::fprintf(stderr, "frameless: %s%s\n", where.c_str(), r.error().message.c_str());
    }
  }
  v.dirty = true;
}

}  // namespace frameless
