// `frameless bench lightfield`: for each slab resolution, the bake's time and memory, then from
// novel viewpoints inside the slab's range (between its uv nodes, nearer and farther than the uv
// plane's distance) the lightfield rendered alone against the model rendered directly: RMSE over
// the image (same background, same pixel samples) and the 1-thread time of each.
#include "bench/bench_lightfield.h"

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <memory>

#include <nlohmann/json.hpp>

#include "bench/bench_options.h"
#include "bench/bench_report.h"
#include "core/scene/scene_finalize.h"
#include "frameless/image_error.h"
#include "core/shading/lightfield_bake.h"

namespace frameless::bench {
namespace {

// Eyes in the slab's frame ([-1, 1]^3, uv plane at z = 1), looking at its centre.
constexpr float kViews[][3] = {{0.13f, 0.07f, 3.0f}, {-0.41f, 0.22f, 2.2f}, {0.30f, -0.35f, 4.5f}};

Camera slab_camera(const Affine& slab, const float* e) {
  Camera c;
  c.eye = slab.point(Vec3(e[0], e[1], e[2]));
  c.look = slab.t;
  c.up = glm::normalize(slab.m[1]);
  c.fov_deg = float(2.0 * std::atan(1.15 / e[2]) * 180.0 / 3.14159265358979);  // the slab (radius ~1.15) fills the view
  return c;
}

// The lightfield alone in a scene with the model's background and settings.
std::unique_ptr<Scene> lightfield_scene(const Scene& model, std::shared_ptr<const LightField> lf) {
  auto s = std::make_unique<Scene>();
  s->name = "lightfield";
  s->settings = model.settings;
  s->settings.integrator = Integrator::kWhitted;
  s->camera = model.camera;
  s->ambient = model.ambient;
  s->lightfields.push_back(place_lightfield(std::move(lf), Affine{}));
  finalize_scene(*s);
  return s;
}

}  // namespace

int run_lightfield(const LightfieldBenchOptions& a) {
  std::string error;
  int w = 0, h = 0;
  if (!parse_size(a.size, w, h, error)) return report_error(error);
  if (a.spp < 1 || a.spp > 1024) return report_error("--spp: must be 1..1024");
  if (a.repeats < 1 || a.repeats > 100) return report_error("--repeats: must be 1..100");
  if (!valid_threads(a.threads, error)) return report_error(error);
  struct Res { int nu, nv, ns, nt; std::string text; };
  std::vector<Res> res;
  for (const std::string& r : a.resolutions) {
    const size_t colon = r.find(':');
    Res x{0, 0, 0, 0, r};
    if (colon == std::string::npos || !parse_size(r.substr(0, colon), x.nu, x.nv, error, "--resolutions") ||
        !parse_size(r.substr(colon + 1), x.ns, x.nt, error, "--resolutions") || x.nu > 1024 || x.nv > 1024 ||
        x.ns > 8192 || x.nt > 8192)
      return report_error("--resolutions: '" + r + "' is not UVxUV:STxST (uv up to 1024, st up to 8192)");
    res.push_back(x);
  }
  if (!a.out.empty() && !prepare_out_dir(a.out, error)) return report_error(error);
  auto model = load_scene_or_report(a.model);
  if (!model) return 2;
  Affine slab;
  if (!slab_around_scene(*model, slab)) return report_error(a.model + ": nothing to bake (no geometry)");
  const int threads = a.threads > 0 ? a.threads : hardware_threads();
  nlohmann::json j = bench_header("lightfield", model.get(), a.model,
                                  {{"size", a.size}, {"spp", a.spp}, {"repeats", a.repeats}, {"bake_threads", threads}});
  j["model_bytes"] = model->accel.stats().bytes + model->accel.stats().geometry_bytes;
  // The model from each view, once: the reference and its time.
  std::vector<std::vector<float>> direct(std::size(kViews));
  std::vector<double> direct_s(std::size(kViews));
  for (size_t v = 0; v < std::size(kViews); ++v) {
    bench_progress("lightfield", "model, view " + std::to_string(v));
    model->camera = slab_camera(slab, kViews[v]);
    std::vector<double> t(size_t(a.repeats));
    for (double& x : t) direct[v] = render_one_thread(*model, w, h, a.spp, x);
    direct_s[v] = median(t);
  }
  for (const Res& r : res) {
    bench_progress("lightfield", "baking " + r.text);
    LightfieldBakeOptions o;
    o.nu = uint32_t(r.nu), o.nv = uint32_t(r.nv), o.ns = uint32_t(r.ns), o.nt = uint32_t(r.nt);
    o.spp = a.spp;
    const auto start = std::chrono::steady_clock::now();
    auto lf = std::make_shared<LightField>(bake_lightfield(*model, slab, o, thread_parallel_for(threads)));
    const double bake_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    const size_t bytes = lf->bytes();
    auto scene = lightfield_scene(*model, lf);
    nlohmann::json rj = {{"resolution", r.text}, {"bake_seconds", bake_s}, {"bytes", bytes}};
    for (size_t v = 0; v < std::size(kViews); ++v) {
      bench_progress("lightfield", r.text + ", view " + std::to_string(v));
      scene->camera = slab_camera(slab, kViews[v]);
      std::vector<double> t(size_t(a.repeats));
      std::vector<float> img;
      for (double& x : t) img = render_one_thread(*scene, w, h, a.spp, x);
      const ImageError e = image_error(img, direct[v], size_t(w) * h);
      rj["views"].push_back({{"eye_in_slab", {kViews[v][0], kViews[v][1], kViews[v][2]}},
                             {"rmse", e.rmse},
                             {"lightfield_seconds", median(t)},
                             {"model_seconds", direct_s[v]},
                             {"cost_vs_model", median(t) / direct_s[v]}});
    }
    j["resolutions"].push_back(rj);
  }
  if (a.json) {
    std::printf("%s\n", j.dump(2).c_str());
  } else {
    std::printf("lightfield of %s (model %.1f MB with its BVH); images %s, %d spp, 1 thread, median of %d\n",
                a.model.c_str(), j["model_bytes"].get<double>() / 1e6, a.size.c_str(), a.spp, a.repeats);
    std::printf("  %-16s %9s %8s  %-30s %-30s\n", "uv:st", "MB", "bake s", "RMSE per view", "time vs model per view");
    for (const auto& rj : j["resolutions"]) {
      std::string rmse, cost;
      char buf[64];
      for (const auto& vj : rj["views"]) {
        std::snprintf(buf, sizeof buf, "%.4f ", vj["rmse"].get<double>());
        rmse += buf;
        std::snprintf(buf, sizeof buf, "%.2fx ", vj["cost_vs_model"].get<double>());
        cost += buf;
      }
      std::printf("  %-16s %9.1f %8.2f  %-30s %-30s\n", rj["resolution"].get<std::string>().c_str(),
                  rj["bytes"].get<double>() / 1e6, rj["bake_seconds"].get<double>(), rmse.c_str(), cost.c_str());
    }
  }
  if (!a.out.empty() && !write_json(a.out + "/lightfield.json", j, error)) return report_error(error);
  return 0;
}

}  // namespace frameless::bench
