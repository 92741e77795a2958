// The engine and its display thread through the public API: one lock per handle serialises the
// caller's calls; render and display threads never take it.
#include <cmath>
#include <mutex>

#include "api/api_impl.h"
#include "core/scene/dynamic.h"
#include "display/display_thread.h"
#include "frameless/engine.h"

namespace frameless::api {

struct Engine::Impl {
  std::shared_ptr<const ::frameless::Scene> scene;
  std::unique_ptr<::frameless::Engine> engine;
  std::unique_ptr<DisplayThread> display;
  bool deterministic = false;
  bool running = false;
  mutable std::mutex mutex;

  void stop() {
    if (!running) return;
    if (!deterministic) display->stop();
    engine->stop();
    running = false;
  }
};

namespace {

Result<bool> fail(std::string message) { return Result<bool>::failure(std::move(message)); }

// Publishes `w` after the world's own check (core/scene/dynamic.h): its message, or the new epoch.
Result<bool> publish(::frameless::Engine& engine, const ::frameless::Scene& scene, const WorldState& w) {
  if (const std::string p = world_problem(w, initial_world(scene)); !p.empty()) return fail(p);
  engine.publish_world(w);
  return true;
}

std::string options_problem(const EngineOptions& o) {
  if (o.width < 0 || o.height < 0 || o.width > 16384 || o.height > 16384) return "size: width and height must be 1..16384";
  if (o.threads < 0 || o.threads > 1024) return "threads: must be 0 (all cores) to 1024";
  if (!(o.update_percent >= 0.01 && o.update_percent <= 100.0)) return "update_percent: must be in [0.01, 100]";
  if (!(o.alpha > 0.0 && o.alpha <= 1.0)) return "alpha: must be in (0, 1]";
  if (!(o.refresh_hz >= 1.0 && o.refresh_hz <= 240.0)) return "refresh_hz: must be in [1, 240]";
  if (!parse_render_mode(o.mode)) return "mode: expected frameless or conventional, got '" + o.mode + "'";
  if (o.camera) return camera_problem(*o.camera);
  return "";
}

}  // namespace

Engine::Engine(std::unique_ptr<Impl> impl) : impl_(std::move(impl)) {}
Engine::Engine(Engine&&) noexcept = default;
Engine& Engine::operator=(Engine&&) noexcept = default;
Engine::~Engine() { stop(); }

Result<Engine> Engine::start(const Scene& scene, const EngineOptions& o) {
  return guarded<Engine>([&]() -> Result<Engine> {
    if (const std::string p = options_problem(o); !p.empty()) return Result<Engine>::failure(p);
    auto impl = std::make_unique<Impl>();
    impl->scene = scene.impl().scene;
    const ::frameless::Scene& s = *impl->scene;
    EngineConfig c;
    c.width = o.width > 0 ? o.width : s.settings.width;
    c.height = o.height > 0 ? o.height : s.settings.height;
    c.threads = o.threads;
    c.update_percent = o.update_percent;
    c.mode = *parse_render_mode(o.mode);
    c.deterministic = o.deterministic;
    c.samples_per_tick = o.samples_per_tick > 0 ? o.samples_per_tick : uint64_t(c.width) * uint64_t(c.height);
    c.track_variance = true;  // the "variance" layer
    const ::frameless::Camera cam = o.camera ? to_camera(*o.camera) : s.camera;
    impl->engine = std::make_unique<::frameless::Engine>(s, c, cam);
    DisplayConfig dc;
    dc.refresh_hz = o.refresh_hz;
    dc.blend.alpha = float(o.alpha);
    dc.blend.reproject = o.reproject && c.mode == RenderMode::frameless;
    impl->display = std::make_unique<DisplayThread>(*impl->engine, dc);
    impl->deterministic = o.deterministic;
    impl->engine->start();
    if (!o.deterministic) impl->display->start();
    impl->running = true;
    return Engine(std::move(impl));
  });
}

Result<bool> Engine::set_camera(const Camera& camera) {
  if (const std::string p = camera_problem(camera); !p.empty()) return fail(p);
  std::lock_guard<std::mutex> lock(impl_->mutex);
  impl_->engine->publish_camera(to_camera(camera));
  return true;
}

Camera Engine::camera() const {
  std::lock_guard<std::mutex> lock(impl_->mutex);
  return from_camera(impl_->engine->camera());
}

Result<bool> Engine::set_light(int index, const Light& light) {
  std::lock_guard<std::mutex> lock(impl_->mutex);
  WorldState w = impl_->engine->world();
  if (index < 0 || size_t(index) >= w.lights.size())
    return fail("light " + std::to_string(index) + ": the scene has " + std::to_string(w.lights.size()) + " lights");
  ::frameless::Light& l = w.lights[size_t(index)];
  const ::frameless::Vec3 p(light.position[0], light.position[1], light.position[2]);
  if (l.kind == LightKind::kDirectional) {
    if (!(glm::length(p) > 0.0f) || !is_finite(p))
      return fail("light " + std::to_string(index) + ": a direction must be finite and not zero");
    l.direction = glm::normalize(p);
  } else {
    l.position = p;
  }
  l.color = ::frameless::Vec3(light.color[0], light.color[1], light.color[2]);
  l.radius = light.radius;
  return publish(*impl_->engine, *impl_->scene, w);
}

Result<bool> Engine::set_material_color(const std::string& name, const Vec3& kd) {
  std::lock_guard<std::mutex> lock(impl_->mutex);
  const auto& mats = impl_->scene->materials;
  size_t i = 0;
  while (i < mats.size() && mats[i].name != name) ++i;
  if (i == mats.size()) return fail("material '" + name + "': no such material in the scene");
  WorldState w = impl_->engine->world();
  w.materials[i].kd = ::frameless::Vec3(kd[0], kd[1], kd[2]);
  return publish(*impl_->engine, *impl_->scene, w);
}

Result<bool> Engine::set_object_position(int index, const Vec3& center) {
  std::lock_guard<std::mutex> lock(impl_->mutex);
  WorldState w = impl_->engine->world();
  if (index < 0 || size_t(index) >= w.object_position.size())
    return fail("object " + std::to_string(index) + ": the scene has " + std::to_string(w.object_position.size()) +
                " moving objects");
  w.object_position[size_t(index)] = ::frameless::Vec3(center[0], center[1], center[2]);
  return publish(*impl_->engine, *impl_->scene, w);
}

Result<bool> Engine::set_instance_transform(int index, const std::array<float, 12>& m) {
  std::lock_guard<std::mutex> lock(impl_->mutex);
  const size_t n = impl_->scene->geometry.instances.size();
  if (index < 0 || size_t(index) >= n)
    return fail("instance " + std::to_string(index) + ": the scene has " + std::to_string(n) + " instances");
  InstanceMove move;
  move.index = uint32_t(index);
  for (int r = 0; r < 3; ++r) {
    for (int c = 0; c < 3; ++c) move.to_world.m[c][r] = m[size_t(4 * r + c)];
    move.to_world.t[r] = m[size_t(4 * r + 3)];
  }
  try {
    impl_->engine->move_instances({move});
  } catch (const std::exception& e) {  // singular or non-finite: the engine's one line
    return fail(one_line(e.what()));
  }
  return true;
}

Result<bool> Engine::advance() {
  std::lock_guard<std::mutex> lock(impl_->mutex);
  if (!impl_->deterministic) return fail("advance: only a deterministic engine advances by calls");
  if (!impl_->running) return fail("advance: the engine is stopped");
  impl_->display->step();
  return true;
}

Image Engine::image() const {
  std::lock_guard<std::mutex> lock(impl_->mutex);
  const DisplayImage& d = impl_->display->acquire_latest();
  return Image{d.width, d.height, 3, d.rgb};
}

Result<Image> Engine::state(const std::string& layer) const {
  // The layer picked once, not per pixel.
  float (*value)(const DisplayImage&, size_t) = nullptr;
  if (layer == "age") value = [](const DisplayImage& d, size_t i) { return d.age(i); };
  else if (layer == "count") value = [](const DisplayImage& d, size_t i) { return float(d.sample_count[i]); };
  else if (layer == "variance") value = [](const DisplayImage& d, size_t i) { return d.variance[i]; };
  else if (layer == "epoch") value = [](const DisplayImage& d, size_t i) { return float(d.epoch[i]); };
  else if (layer == "levels") value = [](const DisplayImage& d, size_t i) { return float(d.levels[i]); };
  else return Result<Image>::failure("state: unknown layer '" + layer + "' (age, count, variance, epoch or levels)");
  std::lock_guard<std::mutex> lock(impl_->mutex);
  const DisplayImage& d = impl_->display->acquire_latest();
  Image out{d.width, d.height, 1, std::vector<float>(d.pixels())};
  for (size_t i = 0; i < d.pixels(); ++i) out.data[i] = value(d, i);
  return out;
}

EngineStats Engine::stats() const {
  std::lock_guard<std::mutex> lock(impl_->mutex);
  const ::frameless::EngineStats e = impl_->engine->stats();
  const DisplayStats d = impl_->display->stats();
  EngineStats s;
  s.seconds = e.seconds;
  s.samples = e.samples;
  s.samples_per_s = e.samples_per_s;
  s.dropped = e.dropped;
  s.pixel_updates = d.pixels_updated;
  s.display_ticks = d.ticks;
  s.display_hz = d.mean_interval > 0 ? 1.0 / d.mean_interval : 0.0;
  s.display_cpu_fraction = d.wall_seconds > 0 ? d.cpu_seconds / d.wall_seconds : 0.0;
  s.coverage = impl_->display->acquire_latest().info.coverage;
  return s;
}

void Engine::stop() {
  if (!impl_) return;
  std::lock_guard<std::mutex> lock(impl_->mutex);
  impl_->stop();
}

bool Engine::running() const {
  std::lock_guard<std::mutex> lock(impl_->mutex);
  return impl_->running;
}

}  // namespace frameless::api
