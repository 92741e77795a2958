// `frameless bake-lightfield`: renders a scene into a light slab file (docs/lightfields.md).
#include <Imath/half.h>

#include <chrono>
#include <cstdio>
#include <memory>

#include "core/io/lightfield_file.h"
#include "core/scenes/scene_load.h"
#include "display/png_io.h"
#include "core/shading/lightfield_bake.h"
#include "tools/command_registry.h"
#include "tools/tool_options.h"

namespace frameless::cli {
namespace {

struct BakeArgs {
  ShadowOptions shadows;
  std::string scene = "default";
  std::string uv = "16x16", st = "256x256";
  int spp = 4;
  int threads = 0;
  std::string out = "captures/lightfield.exr";
  std::string png;
  CameraOptions camera;
};

// The mosaic over black, for a quick look (the EXR holds the same, premultiplied, in half).
std::vector<float> mosaic_rgb(const LightField& lf) {
  std::vector<float> rgb(size_t(lf.width()) * lf.height() * 3);
  for (size_t k = 0; k < rgb.size() / 3; ++k)
    for (int c = 0; c < 3; ++c) rgb[3 * k + c] = imath_half_to_float(lf.rgba[4 * k + c]);
  return rgb;
}

int run_bake(const BakeArgs& a) {
  std::string error;
  int nu, nv, ns, nt;
  if (!parse_size(a.uv, nu, nv, error, "--uv") || !parse_size(a.st, ns, nt, error, "--st")) return report_error(error);
  if (nu > 1024 || nv > 1024) return report_error("--uv: at most 1024x1024 views");
  if (ns > 8192 || nt > 8192) return report_error("--st: at most 8192x8192 texels per view");
  if (uint64_t(nu) * nv * ns * nt > (uint64_t(1) << 31)) return report_error("--uv x --st: more than 2^31 texels");
  if (a.spp < 1 || a.spp > 4096) return report_error("--spp: must be between 1 and 4096");
  if (!valid_threads(a.threads, error)) return report_error(error);
  for (const std::string& path : {a.out, a.png})
    if (!path.empty() && !output_dir_ok(path, error)) return report_error(error);
  std::unique_ptr<Scene> scene = load_scene_or_report(a.scene, &a.shadows);
  if (!scene) return 2;
  if (!a.camera.apply(scene->camera, error)) return report_error(error);
  Affine slab;
  if (!slab_around_scene(*scene, slab)) return report_error(a.scene + ": nothing to bake (the scene has no geometry)");

  LightfieldBakeOptions o;
  o.nu = uint32_t(nu), o.nv = uint32_t(nv), o.ns = uint32_t(ns), o.nt = uint32_t(nt);
  o.spp = a.spp;
  const int threads = a.threads > 0 ? a.threads : hardware_threads();
  if (show_progress())  // from the render threads: one short write each
    o.progress = [](double f) { std::fprintf(stderr, f >= 1.0 ? "\rbaking 100.0%%\n" : "\rbaking %5.1f%%", 100.0 * f); };
  const auto start = std::chrono::steady_clock::now();
  LightField lf = bake_lightfield(*scene, slab, o, thread_parallel_for(threads));
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  lf.source = a.scene;
  if (auto r = write_lightfield(a.out, lf); !r) return report_error(r.error().message);
  if (!a.png.empty())
    if (auto r = write_png(a.png, int(lf.width()), int(lf.height()), mosaic_rgb(lf).data()); !r)
      return report_error(r.error().message);
  const double samples = double(lf.width()) * lf.height() * a.spp;
  std::printf("baked %s: %dx%d views of %dx%d texels, %d spp, %d threads, %.2f s (%.2f M samples/s)\n",
              a.scene.c_str(), nu, nv, ns, nt, a.spp, threads, seconds, samples / seconds * 1e-6);
  std::printf("slab: centre %.4g %.4g %.4g, half-size %.4g; %.1f MB in memory\n", slab.t.x, slab.t.y, slab.t.z,
              glm::length(slab.m[0]), double(lf.bytes()) / 1e6);
  std::printf("wrote %s%s%s\n", a.out.c_str(), a.png.empty() ? "" : " and ", a.png.c_str());
  return 0;
}

const bool bake_lightfield_registered = register_command(
    "", "bake-lightfield", "Render a scene into a light slab (two-plane lightfield) file, placed by a scene's \"lightfield\" object",
    [](CLI::App& app) {
      auto a = std::make_shared<BakeArgs>();
      app.add_option("scene", a->scene, "built-in name, .json scene or model file to bake (default: default)");
      add_shadow_flags(app, a->shadows);
      app.add_option("--uv", a->uv, "views on the slab's uv (camera) plane, UxV")->capture_default_str();
      app.add_option("--st", a->st, "texels per view on the st (focal) plane, SxT")->capture_default_str();
      app.add_option("--spp", a->spp, "stratified samples per texel")->capture_default_str();
      app.add_option("--threads", a->threads, "render threads (default: all cores)");
      app.add_option("--out", a->out, "output lightfield (EXR mosaic)")->capture_default_str();
      app.add_option("--png", a->png, "also write the mosaic of views as an sRGB PNG here");
      add_camera_flags(app, a->camera);
      app.footer("The slab is a cube around the scene's bounding sphere facing its camera (--eye/--look move it); "
                 "docs/lightfields.md describes the file.");
      return [a] { return run_bake(*a); };
    });

}  // namespace
}  // namespace frameless::cli
