// Scenes and one-shot renders through the public API.
#include <cmath>
#include <mutex>
#include <thread>

#include "api/api_impl.h"
#include "core/io/scene_json.h"
#include "core/io/shader_library.h"
#include "core/scene/scene_finalize.h"
#include "core/scenes/scene_load.h"
#include "frameless/thread_executor.h"
#include "frameless/tile_render.h"

namespace frameless::api {
namespace {

std::mutex g_loading;  // the shader search path and the loaders' caches are the loading thread's

bool finite3(const Vec3& v) { return std::isfinite(v[0]) && std::isfinite(v[1]) && std::isfinite(v[2]); }

}  // namespace

::frameless::Camera to_camera(const Camera& c) {
  ::frameless::Camera out;
  out.eye = ::frameless::Vec3(c.eye[0], c.eye[1], c.eye[2]);
  out.look = ::frameless::Vec3(c.look[0], c.look[1], c.look[2]);
  out.up = ::frameless::Vec3(c.up[0], c.up[1], c.up[2]);
  out.fov_deg = c.fov_deg;
  return out;
}

Camera from_camera(const ::frameless::Camera& c) {
  return Camera{{c.eye.x, c.eye.y, c.eye.z}, {c.look.x, c.look.y, c.look.z}, {c.up.x, c.up.y, c.up.z}, c.fov_deg};
}

std::string camera_problem(const Camera& c) {
  if (!finite3(c.eye) || !finite3(c.look) || !finite3(c.up) || !std::isfinite(c.fov_deg)) return "camera: every number must be finite";
  if (!camera_is_valid(to_camera(c)))
    return "camera: eye and look must differ, up must not be parallel to the view, fov must lie in (0, 180)";
  return "";
}

namespace {
// Scenes the API loads build their BVH on every core (unless the host set an executor).
void ensure_build_executor() {
  static std::once_flag once;
  std::call_once(once, [] {
    if (!default_build_executor()) set_default_build_executor(thread_executor(0));
  });
}
}  // namespace

Result<Scene> Scene::load(const std::string& spec, const std::vector<std::string>& shader_path) {
  return guarded<Scene>([&]() -> Result<Scene> {
    std::lock_guard<std::mutex> lock(g_loading);
    ensure_build_executor();
    set_shader_search_path(shader_path);
    auto s = load_scene(spec);
    set_shader_search_path({});
    if (!s) return Result<Scene>::failure(s.error().message);
    auto impl = std::make_shared<Impl>();
    impl->scene = std::shared_ptr<const ::frameless::Scene>(std::move(*s));
    return Scene(std::move(impl));
  });
}

Result<Scene> Scene::from_json(const std::string& json, const std::string& base_dir) {
  return guarded<Scene>([&]() -> Result<Scene> {
    std::lock_guard<std::mutex> lock(g_loading);
    ensure_build_executor();
    auto s = parse_scene_json(json, "<json>", base_dir);
    if (!s) return Result<Scene>::failure(s.error().message);
    auto impl = std::make_shared<Impl>();
    impl->scene = std::shared_ptr<const ::frameless::Scene>(std::move(*s));
    return Scene(std::move(impl));
  });
}

SceneInfo Scene::info() const {
  const ::frameless::Scene& s = *impl_->scene;
  SceneInfo i;
  i.name = s.name;
  i.width = s.settings.width;
  i.height = s.settings.height;
  i.triangles = s.geometry.num_triangles();
  i.spheres = s.geometry.spheres.size();
  i.patches = s.geometry.patches.size();
  i.instances = s.geometry.instances.size();
  i.volumes = s.volumes.size();
  i.lightfields = s.lightfields.size();
  i.moving_objects = s.dynamic.size();
  for (const Material& m : s.materials) i.materials.push_back(m.name);
  i.lights = int(s.lights.size());
  return i;
}

Camera Scene::camera() const { return from_camera(impl_->scene->camera); }

std::vector<Light> Scene::lights() const {
  std::vector<Light> out;
  for (const ::frameless::Light& l : impl_->scene->lights) {
    const bool dir = l.kind == LightKind::kDirectional;
    const ::frameless::Vec3 p = dir ? l.direction : l.position;
    out.push_back(Light{{p.x, p.y, p.z}, {l.color.x, l.color.y, l.color.z}, l.radius, dir});
  }
  return out;
}

Result<Image> render(const Scene& scene, const RenderOptions& o) {
  return guarded<Image>([&]() -> Result<Image> {
    const ::frameless::Scene& s = *scene.impl().scene;
    const int w = o.width > 0 ? o.width : s.settings.width, h = o.height > 0 ? o.height : s.settings.height;
    if (o.width < 0 || o.height < 0 || w > 16384 || h > 16384 || uint64_t(w) * uint64_t(h) > (uint64_t(1) << 28))
      return Result<Image>::failure("size: width and height must be 1..16384 (at most 2^28 pixels)");
    if (o.spp < 0 || o.spp > (1 << 20)) return Result<Image>::failure("spp: must be between 1 and 1048576");
    if (o.threads < 0 || o.threads > 1024) return Result<Image>::failure("threads: must be 0 (all cores) to 1024");
    Camera cam = o.camera ? *o.camera : from_camera(s.camera);
    if (const std::string p = camera_problem(cam); !p.empty()) return Result<Image>::failure(p);
    TileRenderOptions t;
    t.spp = o.spp > 0 ? o.spp : s.settings.spp;
    const unsigned hw = std::thread::hardware_concurrency();
    t.threads = o.threads > 0 ? o.threads : int(hw ? hw : 1);
    RenderedImage img = render_tiles(s, make_camera_basis(to_camera(cam), w, h), t);
    return Image{w, h, 3, std::move(img.rgb)};
  });
}

}  // namespace frameless::api
