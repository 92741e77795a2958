// `frameless render`: one-shot render of a scene to EXR (half RGB, Z, N, sample count) and PNG.
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <memory>

#include "core/io/file_util.h"
#include "core/scenes/scene_load.h"
#include "display/atomic_file.h"
#include "display/exr_io.h"
#include "display/levels_view.h"
#include "display/png_io.h"
#include "frameless/tile_render.h"
#include "tools/command_registry.h"
#include "tools/tool_options.h"

namespace frameless::cli {
namespace {

struct RenderArgs {
  ShadowOptions shadows;
  std::string scene = "default";
  std::string size;
  int spp = 0;
  std::string out = "captures/render.exr";
  std::string png;
  std::string levels_png;
  bool no_jitter = false;
  int threads = 0;
  double time = 0.0;
  CameraOptions camera;
};

int run_render(const RenderArgs& a) {
  std::string error;
  // Check every output before spending minutes rendering.
  if (!output_dir_ok(a.out, error)) return report_error(error);
  if (!a.png.empty() && !output_dir_ok(a.png, error)) return report_error(error);
  if (!a.levels_png.empty() && !output_dir_ok(a.levels_png, error)) return report_error(error);
  // Each file in the format its name says (an EXR named x.png opens nowhere as a PNG).
  if (file_extension(a.out) != ".exr")
    return report_error("--out: " + a.out + ": the render is written as EXR: name it .exr (--png adds a PNG)");
  for (const auto& [flag, path] : {std::pair<const char*, const std::string*>{"--png", &a.png}, {"--levels-png", &a.levels_png}})
    if (!path->empty() && file_extension(*path) != ".png")
      return report_error(std::string(flag) + ": " + *path + ": a PNG is written here: name it .png");
  if (a.spp < 0 || a.spp > 1 << 20) return report_error("--spp: must be between 1 and 1048576");
  if (!valid_threads(a.threads, error)) return report_error(error);

  std::unique_ptr<Scene> scene = load_scene_or_report(a.scene, &a.shadows);
  if (!scene) return 2;
  int width = scene->settings.width, height = scene->settings.height;
  if (!a.size.empty() && !parse_size(a.size, width, height, error)) return report_error(error);
  Camera camera = scene->camera;
  if (!a.camera.apply(camera, error)) return report_error(error);

  TileRenderOptions o;
  o.spp = a.spp > 0 ? a.spp : scene->settings.spp;
  o.threads = a.threads > 0 ? a.threads : hardware_threads();
  o.jitter = !a.no_jitter;
  if (!std::isfinite(a.time)) return report_error("--time: must be a finite number of seconds");
  o.time = a.time;
  if (show_progress())
    o.progress = [](double f) {
      std::fprintf(stderr, "\rrendering %5.1f%%", 100.0 * f);
      if (f >= 1.0) std::fprintf(stderr, "\n");
    };
  const RenderedImage img = render_tiles(*scene, make_camera_basis(camera, width, height), o);

  ExrAttributes attrs;
  attrs.strings["frameless:scene"] = a.scene;
  attrs.ints["frameless:spp"] = o.spp;
  attrs.ints["frameless:dropped_samples"] = int(img.dropped);
  attrs.doubles["frameless:render_seconds"] = img.seconds;
  const std::vector<ExrChannel> channels = {
      {"R", true, img.rgb.data(), 3},         {"G", true, img.rgb.data() + 1, 3},
      {"B", true, img.rgb.data() + 2, 3},     {"Z", false, img.depth.data(), 1},
      {"N.X", false, img.normal.data(), 3},   {"N.Y", false, img.normal.data() + 1, 3},
      {"N.Z", false, img.normal.data() + 2, 3}, {"samples", false, img.samples.data(), 1}};
  if (auto r = write_exr(a.out, width, height, channels, attrs); !r) return report_error(r.error().message);
  if (!a.png.empty())
    if (auto r = write_png(a.png, width, height, img.rgb.data()); !r)
      return report_error(r.error().message);
  if (!a.levels_png.empty()) {
    // The viewer's levels view: the deepest level over each pixel's samples, as false colour.
    std::vector<float> rgb(3 * img.levels.size());
    for (size_t i = 0; i < img.levels.size(); ++i) {
      const Vec3 c = levels_color(img.levels[i]);
      rgb[3 * i] = c.x, rgb[3 * i + 1] = c.y, rgb[3 * i + 2] = c.z;
    }
    if (auto r = write_png(a.levels_png, width, height, rgb.data()); !r)
      return report_error(r.error().message);
  }
  const double rays = double(width) * height * o.spp;
  std::printf("rendered %s: %dx%d, %d spp, %d threads, %.2f s (%.2f M samples/s), %llu dropped\n",
              a.scene.c_str(), width, height, o.spp, o.threads, img.seconds,
              rays / img.seconds * 1e-6, (unsigned long long)img.dropped);
  std::printf("wrote %s%s%s%s%s\n", a.out.c_str(), a.png.empty() ? "" : " and ", a.png.c_str(),
              a.levels_png.empty() ? "" : " and ", a.levels_png.c_str());
  return 0;
}

const bool render_registered = register_command(
    "", "render", "Render a scene once to an EXR (half RGB + Z + N + samples), optionally a PNG",
    [](CLI::App& app) {
      auto a = std::make_shared<RenderArgs>();
      app.add_option("scene", a->scene,
                     "built-in name, .json scene or .obj/.ply/.gltf/.glb model (default: default)");
      add_shadow_flags(app, a->shadows);
      app.add_option("--size", a->size, "image size WxH (default: the scene's)");
      app.add_option("--spp", a->spp, "samples per pixel (default: the scene's)");
      app.add_option("--out", a->out, "output EXR file")->capture_default_str();
      app.add_option("--png", a->png, "also write an sRGB PNG here");
      app.add_option("--levels-png", a->levels_png,
                     "also write the reflection/refraction levels per pixel here, in the viewer's "
                     "false colour (0 dark blue .. 25+ red)");
      app.add_flag("--no-jitter", a->no_jitter, "sample pixel centres only");
      app.add_option("--threads", a->threads, "render threads (default: all cores)");
      app.add_option("--time", a->time, "seconds: the instant moving objects are shown at (default 0)");
      add_camera_flags(app, a->camera);
      app.footer(std::string("Scenes: ") + builtin_scene_help());
      return [a] { return run_render(*a); };
    });

}  // namespace
}  // namespace frameless::cli
