#include "tools/common_options.h"

#include <cstdio>
#include <thread>

#include "core/scene_io.h"

namespace frameless::cli {

void CameraFlags::add_to(CLI::App& app) {
  app.add_option("--eye", eye, "camera position x,y,z")->delimiter(',')->expected(3);
  app.add_option("--look", look, "look-at point x,y,z")->delimiter(',')->expected(3);
  app.add_option("--up", up, "up vector x,y,z")->delimiter(',')->expected(3);
  app.add_option("--fov", fov, "vertical field of view in degrees (0, 180)");
}

bool CameraFlags::apply(Camera& camera, std::string& error) const {
  Camera c = camera;
  if (eye.size() == 3) c.eye = Vec3(eye[0], eye[1], eye[2]);
  if (look.size() == 3) c.look = Vec3(look[0], look[1], look[2]);
  if (up.size() == 3) c.up = Vec3(up[0], up[1], up[2]);
  if (fov) c.fov_deg = *fov;
  if (!camera_is_valid(c)) {
    error = "camera flags: invalid camera (need finite values, eye != look, up not parallel to "
            "the view direction, 0 < fov < 180)";
    return false;
  }
  camera = c;
  return true;
}

bool parse_size(const std::string& text, int& width, int& height, std::string& error) {
  int w = 0, h = 0;
  char x = 0, extra = 0;
  if (std::sscanf(text.c_str(), "%d%c%d%c", &w, &x, &h, &extra) != 3 || (x != 'x' && x != 'X')) {
    error = "--size: expected WxH (e.g. 640x480), got '" + text + "'";
    return false;
  }
  if (w < 1 || h < 1 || w > 16384 || h > 16384) {
    error = "--size: " + text + " is out of range (each side 1..16384)";
    return false;
  }
  width = w, height = h;
  return true;
}

int hardware_threads() {
  const unsigned n = std::thread::hardware_concurrency();
  return n ? int(n) : 1;
}

bool valid_threads(int threads, std::string& error) {
  if (threads >= 0 && threads <= 1024) return true;
  error = "--threads: must be 0 (all cores) to 1024, got " + std::to_string(threads);
  return false;
}

std::unique_ptr<Scene> load_scene_or_report(const std::string& spec) {
  auto result = load_scene(spec);
  if (!result.ok()) {
    std::fprintf(stderr, "frameless: %s\n", result.error().message.c_str());
    return nullptr;
  }
  return std::move(result.value());
}

int report_error(const std::string& message) {
  std::fprintf(stderr, "frameless: %s\n", message.c_str());
  return 2;
}

}  // namespace frameless::cli
