// The frameless C++ API (issue 29; docs/api.md): load a scene, render it once, or run the
// frameless engine and its display, move the camera, lights and materials, read the displayed
// image and the per-pixel state, stop. Errors are results carrying the one-line message the
// command line prints; nothing here exits or aborts the host program.
//
// Threading: Scene is immutable once loaded and may be shared. An Engine's methods may be called
// from any thread, one call at a time per Engine (calls on one Engine are serialised inside; they
// never wait for a render thread: the engine's render and display threads run on their own).
#pragma once
#include <array>
#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <utility>
#include <vector>

namespace frameless::api {

// A value, or the one-line error that stopped it.
template <class T>
class Result {
 public:
  Result(T value) : value_(std::move(value)) {}
  static Result failure(std::string message) { return Result(std::move(message), 0); }
  bool ok() const { return value_.has_value(); }
  explicit operator bool() const { return ok(); }
  T& value() { return *value_; }
  const T& value() const { return *value_; }
  T& operator*() { return *value_; }
  T* operator->() { return &*value_; }
  const std::string& error() const { return error_; }

 private:
  Result(std::string message, int) : error_(std::move(message)) {}
  std::optional<T> value_;
  std::string error_;
};

using Vec3 = std::array<float, 3>;

// A pinhole camera: eye, look-at point, up vector, vertical field of view in degrees.
struct Camera {
  Vec3 eye{0.0f, 0.0f, 5.0f};
  Vec3 look{0.0f, 0.0f, 0.0f};
  Vec3 up{0.0f, 1.0f, 0.0f};
  float fov_deg = 45.0f;
};

// Linear float pixels, rows from the top, `channels` floats per pixel (3 for colour).
struct Image {
  int width = 0, height = 0, channels = 0;
  std::vector<float> data;
  float at(int x, int y, int c = 0) const { return data[(size_t(y) * size_t(width) + size_t(x)) * size_t(channels) + size_t(c)]; }
};

struct Light {
  Vec3 position{0.0f, 0.0f, 0.0f};  // a directional light's direction
  Vec3 color{1.0f, 1.0f, 1.0f};
  float radius = 0.0f;
  bool directional = false;
};

struct SceneInfo {
  std::string name;
  int width = 0, height = 0;         // the scene's own image size
  uint64_t triangles = 0, spheres = 0, patches = 0, instances = 0, volumes = 0, lightfields = 0;
  uint64_t moving_objects = 0;       // "dynamic" spheres set_object_position moves
  std::vector<std::string> materials;  // names, in index order
  int lights = 0;
};

class Scene {
 public:
  // A built-in name ("default", "office", ...), a .json scene, or a mesh/model file, as the
  // command line takes it; shader_path: folders searched first for plug-in shaders.
  static Result<Scene> load(const std::string& spec, const std::vector<std::string>& shader_path = {});
  // A scene given as JSON text (docs/scene-format.md); relative files resolve against base_dir.
  static Result<Scene> from_json(const std::string& json, const std::string& base_dir = ".");

  SceneInfo info() const;
  Camera camera() const;
  std::vector<Light> lights() const;

  struct Impl;
  const Impl& impl() const { return *impl_; }

 private:
  explicit Scene(std::shared_ptr<const Impl> impl) : impl_(std::move(impl)) {}
  std::shared_ptr<const Impl> impl_;
};

struct RenderOptions {
  int width = 0, height = 0;  // 0: the scene's
  int spp = 0;                // 0: the scene's
  int threads = 0;            // 0: all cores
  std::optional<Camera> camera;  // default: the scene's
};

// One image, as `frameless render` makes it (mean of spp jittered samples per pixel).
Result<Image> render(const Scene& scene, const RenderOptions& options = {});

struct EngineOptions {
  std::string mode = "frameless";  // or "conventional"
  int width = 0, height = 0;       // 0: the scene's
  int threads = 0;                 // 0: all cores
  double update_percent = 1.0;     // a render thread re-reads the camera after this share of its pixels
  double alpha = 0.5;              // the display's blend weight of a new sample
  double refresh_hz = 60.0;        // display ticks per second
  bool reproject = true;           // move what is shown when the camera moves (frameless mode)
  bool deterministic = false;      // virtual clock: the engine renders only inside advance()
  uint64_t samples_per_tick = 0;   // deterministic: samples per advance() (0: one per pixel)
  std::optional<Camera> camera;    // default: the scene's
};

struct EngineStats {
  double seconds = 0;            // engine seconds since start
  uint64_t samples = 0;          // samples traced
  double samples_per_s = 0;
  uint64_t pixel_updates = 0;    // updates the display blended
  uint64_t display_ticks = 0;
  double display_hz = 0;         // measured
  double display_cpu_fraction = 0;  // the display thread's CPU over wall time
  double coverage = 0;           // share of pixels whose newest sample used the newest camera
  uint64_t dropped = 0;          // samples dropped for NaN/Inf
};

class Engine {
 public:
  // Starts render threads and the display thread (wall clock), or an engine that renders only in
  // advance() (deterministic).
  static Result<Engine> start(const Scene& scene, const EngineOptions& options = {});
  Engine(Engine&&) noexcept;
  Engine& operator=(Engine&&) noexcept;
  ~Engine();  // stops

  Result<bool> set_camera(const Camera& camera);
  Camera camera() const;
  // Lights and materials of the scene, edited while rendering (the world channel: render
  // threads pick them up at their next sample; they never wait for the caller).
  Result<bool> set_light(int index, const Light& light);
  Result<bool> set_material_color(const std::string& name, const Vec3& kd);
  // Moving objects (a scene's "dynamic" spheres): the base centre of object `index`.
  Result<bool> set_object_position(int index, const Vec3& center);
  // Instances (a scene's "instance" objects): the world placement of declared instance `index`,
  // a 3x4 row-major affine matrix (the top level is refit and published; render threads pick it
  // up like the camera).
  Result<bool> set_instance_transform(int index, const std::array<float, 12>& row_major_3x4);
  // Deterministic engines: render one display tick's samples and blend them.
  Result<bool> advance();
  // The display's newest image (linear RGB) and a per-pixel state layer: "age" (seconds since
  // the last update), "count" (samples since the camera last changed), "variance", "epoch",
  // "levels" (reflection depth). Unknown names are an error.
  Image image() const;
  Result<Image> state(const std::string& layer) const;
  EngineStats stats() const;
  void stop();  // idempotent
  bool running() const;

  struct Impl;

 private:
  explicit Engine(std::unique_ptr<Impl> impl);
  std::unique_ptr<Impl> impl_;
};

struct CaptureOptions {
  std::string out_dir;             // frames (frame_NNNNN.exr), manifest.json, contact_sheet.png
  double duration = 2.0;           // seconds (wall, or virtual when deterministic)
  double refresh_hz = 30.0;        // display refreshes per second = frames per second
  std::string mode = "frameless";  // or "conventional"
  int width = 0, height = 0;       // 0: the scene's
  int threads = 0;                 // 0: all cores
  bool deterministic = false;      // virtual clock: the same call gives the same frames
  double orbit_degrees = 0.0;      // the camera orbits this far about its look-at point
  std::vector<std::string> layers; // per-pixel layers in each EXR: age, count, variance, epoch, levels
  bool contact_sheet = true;
};
struct CaptureInfo {
  int frames = 0;
  std::string manifest;       // path of manifest.json
  std::string contact_sheet;  // path, empty when not written
};
// What the display shows over time, headless (as `frameless capture`, without the MP4).
Result<CaptureInfo> capture(const Scene& scene, const CaptureOptions& options);

struct UpdateStatisticsOptions {
  int width = 128, height = 96;
  int threads = 1;
  double update_percent = 1.0;
  uint64_t seed = 1;
  double sweeps = 4.0;  // run length in sweeps of every pixel (deterministic clock)
  bool shade = false;   // false: a flat shader (where pixels update does not depend on shading)
};
// The pixel-update distribution of the frameless order (docs/stats.md): per-pixel update counts
// (uniformity and a chi-square test against equal rates), gaps between a pixel's updates, and how
// soon pixels show a camera change (in sweeps, against the bound 1 + update % / 100).
struct UpdateStatistics {
  uint32_t updates_min = 0, updates_max = 0;
  double updates_mean = 0, updates_cv = 0;
  double chi2 = 0, chi2_dof = 0, chi2_p = 1;
  double interval_mean_sweeps = 0, interval_cv = 0, interval_max_sweeps = 0;
  bool staleness_measured = false;
  double t50_sweeps = 0, t95_sweeps = 0, t100_sweeps = 0, bound_sweeps = 0;
  std::vector<uint64_t> thread_pixels;
  bool balanced = true;  // threads own pixel counts within one chunk of each other
};
Result<UpdateStatistics> update_statistics(const Scene& scene, const UpdateStatisticsOptions& options = {});

}  // namespace frameless::api
