// Flags of the shared options: see tool_options.h.
#include "tools/tool_options.h"

#include <filesystem>

#include "core/io/shader_library.h"
#include "display/atomic_file.h"

namespace frameless::cli {

bool output_dir_ok(const std::string& path, std::string& error) {
  const std::string dir = std::filesystem::path(path).parent_path().string();
  if (!dir.empty() && !std::filesystem::exists(dir)) {
    std::error_code ec;
    std::filesystem::create_directories(dir, ec);
  }
  return directory_writable(dir, error);
}

void add_camera_flags(CLI::App& app, CameraOptions& camera) {
  app.add_option("--eye", camera.eye, "camera position x,y,z")->delimiter(',')->expected(3);
  app.add_option("--look", camera.look, "look-at point x,y,z")->delimiter(',')->expected(3);
  app.add_option("--up", camera.up, "up vector x,y,z")->delimiter(',')->expected(3);
  app.add_option("--fov", camera.fov, "vertical field of view in degrees (0, 180)");
}

void add_shadow_flags(CLI::App& app, ShadowOptions& shadows) {
  app.add_option("--shadows", shadows.mode,
                 "shadows of lights with a radius: soft (single-sample, default), hard, area "
                 "(reference: --shadow-samples rays per light) or beam (Parker's: 4 fixed rays across the "
                 "light, traced as one packet)");
  app.add_option("--shadow-samples", shadows.samples, "rays per light for --shadows area (1..4096)");
  app.add_flag("--transparent-shadows", shadows.transparent,
               "dielectrics attenuate shadow rays (k_t and absorption) instead of blocking them");
  app.add_option("--accel", shadows.accel,
                 "acceleration structure: bvh (default), grid (Parker's hybrid grid) or auto "
                 "(whichever does less work on a trial of the scene's rays)");
  app.add_option("--integrator", shadows.integrator,
                 "light transport: whitted (Parker's model), path (unbiased path tracing) or igi "
                 "(instant global illumination); "
                 "default: path for scenes with emitters, whitted otherwise, or the scene's own");
  // Read as the command line is parsed: scenes load after it.
  app.add_option_function<std::vector<std::string>>(
         "--shader-path", [](const std::vector<std::string>& folders) { set_shader_search_path(folders); },
         "folders searched first for plug-in shaders NAME.so (then $FRAMELESS_SHADER_PATH, then the scene's folder)")
      ->delimiter(':');
}

}  // namespace frameless::cli
