// The `frameless` Python module (issue 29; docs/python.md): pybind11 over the C++ API
// (include/frameless/api.h). Images come back as numpy arrays that own the API's buffers (no
// copy); every error is a ValueError with the command line's one-line message; rendering,
// starting, advancing and stopping release the GIL.
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "frameless/api.h"

namespace py = pybind11;
using namespace frameless::api;

namespace {

template <class T>
T unwrap(Result<T>&& r) {
  if (!r) throw py::value_error(r.error());
  return std::move(*r);
}

// Runs a library call without the GIL (it may render for seconds), then unwraps its result with it.
template <class F>
auto without_gil(F&& call) {
  auto r = [&] {
    py::gil_scoped_release release;
    return call();
  }();
  return unwrap(std::move(r));
}

// An H x W x C (or H x W for one channel) float32 array over the image's own buffer.
py::array to_numpy(Image&& image) {
  auto* data = new std::vector<float>(std::move(image.data));
  py::capsule owner(data, [](void* p) { delete static_cast<std::vector<float>*>(p); });
  const py::ssize_t h = image.height, w = image.width, c = image.channels, f = sizeof(float);
  if (c == 1) return py::array_t<float>({h, w}, {w * f, f}, data->data(), owner);
  return py::array_t<float>({h, w, c}, {w * c * f, c * f, f}, data->data(), owner);
}

Vec3 vec3(const py::object& o, const char* what) {
  const std::vector<float> v = o.cast<std::vector<float>>();
  if (v.size() != 3) throw py::value_error(std::string(what) + ": expected three numbers");
  return {v[0], v[1], v[2]};
}

Camera make_camera(const py::object& eye, const py::object& look, const py::object& up, float fov) {
  Camera c;
  c.eye = vec3(eye, "eye");
  c.look = vec3(look, "look");
  if (!up.is_none()) c.up = vec3(up, "up");
  c.fov_deg = fov;
  return c;
}

py::dict camera_dict(const Camera& c) {
  py::dict d;
  d["eye"] = py::make_tuple(c.eye[0], c.eye[1], c.eye[2]);
  d["look"] = py::make_tuple(c.look[0], c.look[1], c.look[2]);
  d["up"] = py::make_tuple(c.up[0], c.up[1], c.up[2]);
  d["fov"] = c.fov_deg;
  return d;
}

// A scene given as a Scene or as anything Scene.load takes.
Scene as_scene(const py::object& scene) {
  if (py::isinstance<Scene>(scene)) return scene.cast<Scene>();
  return unwrap(Scene::load(scene.cast<std::string>()));
}

std::pair<int, int> size_of(const py::object& size) {
  if (size.is_none()) return {0, 0};
  const auto s = size.cast<std::pair<int, int>>();
  if (s.first < 1 || s.second < 1) throw py::value_error("size: width and height must be at least 1");
  return s;
}

}  // namespace

PYBIND11_MODULE(frameless, m) {
  m.doc() = "frameless: a frameless interactive ray tracer (docs/python.md)";

  py::class_<Scene>(m, "Scene", "A loaded scene (immutable; may be shared by renders and engines).")
      .def_static(
          "load", [](const std::string& spec, std::vector<std::string> shader_path) {
            return without_gil([&] { return Scene::load(spec, shader_path); });
          },
          py::arg("spec"), py::arg("shader_path") = std::vector<std::string>{},
          "A built-in name ('default', 'office', ...), a .json scene or a mesh/model file.")
      .def_static(
          "from_json", [](const std::string& text, const std::string& base_dir) { return unwrap(Scene::from_json(text, base_dir)); },
          py::arg("text"), py::arg("base_dir") = ".", "A scene from JSON text (docs/scene-format.md).")
      .def_property_readonly("camera", [](const Scene& s) { return camera_dict(s.camera()); })
      .def_property_readonly("info", [](const Scene& s) {
        const SceneInfo i = s.info();
        py::dict d;
        d["name"] = i.name;
        d["size"] = py::make_tuple(i.width, i.height);
        d["triangles"] = i.triangles;
        d["spheres"] = i.spheres;
        d["patches"] = i.patches;
        d["instances"] = i.instances;
        d["volumes"] = i.volumes;
        d["lightfields"] = i.lightfields;
        d["moving_objects"] = i.moving_objects;
        d["materials"] = i.materials;
        d["lights"] = i.lights;
        return d;
      });

  m.def(
      "render",
      [](const py::object& scene, const py::object& size, int spp, int threads, const py::object& eye,
         const py::object& look, const py::object& up, float fov) {
        const Scene s = as_scene(scene);
        RenderOptions o;
        std::tie(o.width, o.height) = size_of(size);
        o.spp = spp;
        o.threads = threads;
        if (!eye.is_none() || !look.is_none()) {
          const Camera base = s.camera();
          o.camera = make_camera(eye.is_none() ? py::cast(std::vector<float>(base.eye.begin(), base.eye.end())) : eye,
                                 look.is_none() ? py::cast(std::vector<float>(base.look.begin(), base.look.end())) : look,
                                 up, fov > 0 ? fov : base.fov_deg);
        }
        return to_numpy(without_gil([&] { return render(s, o); }));
      },
      py::arg("scene") = "default", py::arg("size") = py::none(), py::arg("spp") = 0, py::arg("threads") = 0,
      py::arg("eye") = py::none(), py::arg("look") = py::none(), py::arg("up") = py::none(), py::arg("fov") = 0.0f,
      "Renders a scene once: an H x W x 3 float32 array of linear radiance.");

  m.def(
      "capture",
      [](const py::object& scene, const std::string& out, double duration, double refresh_hz, const std::string& mode,
         const py::object& size, int threads, bool deterministic, double orbit, std::vector<std::string> layers,
         bool contact_sheet) {
        const Scene s = as_scene(scene);
        CaptureOptions o;
        o.out_dir = out;
        o.duration = duration;
        o.refresh_hz = refresh_hz;
        o.mode = mode;
        std::tie(o.width, o.height) = size_of(size);
        o.threads = threads;
        o.deterministic = deterministic;
        o.orbit_degrees = orbit;
        o.layers = std::move(layers);
        o.contact_sheet = contact_sheet;
        const CaptureInfo info = without_gil([&] { return capture(s, o); });
        py::dict d;
        d["frames"] = info.frames;
        d["manifest"] = info.manifest;
        d["contact_sheet"] = info.contact_sheet;
        return d;
      },
      py::arg("scene"), py::arg("out"), py::arg("duration") = 2.0, py::arg("refresh_hz") = 30.0,
      py::arg("mode") = "frameless", py::arg("size") = py::none(), py::arg("threads") = 0,
      py::arg("deterministic") = false, py::arg("orbit") = 0.0, py::arg("layers") = std::vector<std::string>{},
      py::arg("contact_sheet") = true,
      "Headless capture of what the display shows over time: EXR frames, manifest.json, contact sheet.");

  m.def(
      "update_statistics",
      [](const py::object& scene, const py::object& size, int threads, double update_percent, uint64_t seed,
         double sweeps, bool shade) {
        const Scene s = as_scene(scene);
        UpdateStatisticsOptions o;
        if (!size.is_none()) std::tie(o.width, o.height) = size_of(size);
        o.threads = threads;
        o.update_percent = update_percent;
        o.seed = seed;
        o.sweeps = sweeps;
        o.shade = shade;
        const UpdateStatistics u = without_gil([&] { return update_statistics(s, o); });
        py::dict d;
        d["updates_min"] = u.updates_min;
        d["updates_max"] = u.updates_max;
        d["updates_mean"] = u.updates_mean;
        d["updates_cv"] = u.updates_cv;
        d["chi2"] = u.chi2;
        d["chi2_dof"] = u.chi2_dof;
        d["chi2_p"] = u.chi2_p;
        d["interval_mean_sweeps"] = u.interval_mean_sweeps;
        d["interval_cv"] = u.interval_cv;
        d["interval_max_sweeps"] = u.interval_max_sweeps;
        d["staleness_measured"] = u.staleness_measured;
        d["t50_sweeps"] = u.t50_sweeps;
        d["t95_sweeps"] = u.t95_sweeps;
        d["t100_sweeps"] = u.t100_sweeps;
        d["bound_sweeps"] = u.bound_sweeps;
        d["thread_pixels"] = u.thread_pixels;
        d["balanced"] = u.balanced;
        return d;
      },
      py::arg("scene") = "default", py::arg("size") = py::none(), py::arg("threads") = 1,
      py::arg("update_percent") = 1.0, py::arg("seed") = 1, py::arg("sweeps") = 4.0, py::arg("shade") = false,
      "Statistics of the pixel-update distribution (docs/stats.md) from a deterministic run.");

  py::class_<Engine>(m, "Engine", "The frameless engine and its display thread, running until stop().")
      .def(py::init([](const py::object& scene, const std::string& mode, const py::object& size, int threads,
                       double update_percent, double alpha, double refresh_hz, bool reproject, bool deterministic,
                       uint64_t samples_per_tick) {
             const Scene s = as_scene(scene);
             EngineOptions o;
             o.mode = mode;
             std::tie(o.width, o.height) = size_of(size);
             o.threads = threads;
             o.update_percent = update_percent;
             o.alpha = alpha;
             o.refresh_hz = refresh_hz;
             o.reproject = reproject;
             o.deterministic = deterministic;
             o.samples_per_tick = samples_per_tick;
             return without_gil([&] { return Engine::start(s, o); });
           }),
           py::arg("scene") = "default", py::arg("mode") = "frameless", py::arg("size") = py::none(),
           py::arg("threads") = 0, py::arg("update_percent") = 1.0, py::arg("alpha") = 0.5,
           py::arg("refresh_hz") = 60.0, py::arg("reproject") = true, py::arg("deterministic") = false,
           py::arg("samples_per_tick") = 0)
      .def(
          "set_camera",
          [](Engine& e, const py::object& eye, const py::object& look, const py::object& up, float fov) {
            unwrap(e.set_camera(make_camera(eye, look, up, fov)));
          },
          py::arg("eye"), py::arg("look"), py::arg("up") = py::none(), py::arg("fov") = 45.0f)
      .def_property_readonly("camera", [](const Engine& e) { return camera_dict(e.camera()); })
      .def(
          "set_light",
          [](Engine& e, int index, const py::object& position, const py::object& color, float radius) {
            unwrap(e.set_light(index, Light{vec3(position, "position"), vec3(color, "color"), radius, false}));
          },
          py::arg("index"), py::arg("position"), py::arg("color") = std::vector<float>{1, 1, 1}, py::arg("radius") = 0.0f)
      .def(
          "set_material_color",
          [](Engine& e, const std::string& name, const py::object& kd) { unwrap(e.set_material_color(name, vec3(kd, "kd"))); },
          py::arg("name"), py::arg("kd"))
      .def(
          "set_object_position",
          [](Engine& e, int index, const py::object& center) { unwrap(e.set_object_position(index, vec3(center, "center"))); },
          py::arg("index"), py::arg("center"), "Moves a scene's moving ('dynamic') object.")
      .def(
          "set_instance_transform",
          [](Engine& e, int index, const py::object& matrix) {
            // Any nesting (3x4, 4x4, flat, numpy): read row-major.
            const py::array_t<float, py::array::c_style | py::array::forcecast> a(matrix);
            if (a.size() != 12 && a.size() != 16) throw py::value_error("matrix: expected 3x4 or 4x4 numbers, row-major");
            std::array<float, 12> m{};
            for (size_t k = 0; k < 12; ++k) m[k] = a.data()[k];
            unwrap(e.set_instance_transform(index, m));
          },
          py::arg("index"), py::arg("matrix"), "Places a declared instance: a row-major 3x4 (or 4x4) matrix.")
      .def("advance", [](Engine& e, int ticks) {
            py::gil_scoped_release release;
            for (int k = 0; k < ticks; ++k)
              if (auto r = e.advance(); !r) {
                py::gil_scoped_acquire again;
                throw py::value_error(r.error());
              }
          }, py::arg("ticks") = 1, "Deterministic engines: render and blend this many display ticks.")
      .def("image", [](const Engine& e) { return to_numpy(e.image()); }, "The display's newest image (H x W x 3).")
      .def("state", [](const Engine& e, const std::string& layer) { return to_numpy(unwrap(e.state(layer))); },
           py::arg("layer"), "A per-pixel layer: age, count, variance, epoch or levels (H x W).")
      .def("stats", [](const Engine& e) {
        const EngineStats s = e.stats();
        py::dict d;
        d["seconds"] = s.seconds;
        d["samples"] = s.samples;
        d["samples_per_s"] = s.samples_per_s;
        d["pixel_updates"] = s.pixel_updates;
        d["display_ticks"] = s.display_ticks;
        d["display_hz"] = s.display_hz;
        d["display_cpu_fraction"] = s.display_cpu_fraction;
        d["coverage"] = s.coverage;
        d["dropped"] = s.dropped;
        return d;
      })
      .def("stop", [](Engine& e) {
        py::gil_scoped_release release;
        e.stop();
      })
      .def_property_readonly("running", &Engine::running)
      .def("__enter__", [](Engine& e) -> Engine& { return e; }, py::return_value_policy::reference)
      .def("__exit__", [](Engine& e, const py::object&, const py::object&, const py::object&) {
        py::gil_scoped_release release;
        e.stop();
      });
}
