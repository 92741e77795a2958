// Scene input entry points: dispatch a scene spec to the built-ins, the JSON reader or the mesh
// and model readers; loading thread only.
#include "core/scenes/scene_load.h"

#include <cstdio>
#include <filesystem>

#include <nlohmann/json.hpp>

#include "core/io/file_util.h"
#include "core/io/mesh_obj.h"
#include "core/io/scene_json.h"
#include "core/io/sphere_file.h"
#include "core/scene/scene_build.h"
#include "core/scene/scene_finalize.h"
#include "core/shading/irradiance_bake.h"

namespace frameless {

namespace {

// A binary sphere file (core/io/sphere_file.h; figure 15's data set): diffuse spheres coloured by
// their scalar through a 64-entry colour map, or grey; framed from above like spheres:N.
Result<std::unique_ptr<Scene>> load_sphere_scene(const std::string& path, const std::string& name) {
  constexpr int kColours = 64;
  auto s = std::make_unique<Scene>();
  s->name = name;
  auto info = load_sphere_file(path, s->geometry, 0, kColours);
  if (!info) return info.error();
  if (info->has_scalar) {
    const std::vector<Vec3> colours = colormap_colors(kColours);
    for (int i = 0; i < kColours; ++i) {
      Material m;
      m.name = "map" + std::to_string(i);
      m.kd = colours[size_t(i)];
      add_material(*s, m);
    }
  } else {
    Material m;
    m.name = "grey";
    m.kd = Vec3(0.7f);
    add_material(*s, m);
  }
  Vec3 lo, hi;
  if (!geometry_bounds(s->geometry, lo, hi)) return Error{path + ": no spheres"};
  s->camera = frame_camera(lo, hi, s->settings.width, s->settings.height);
  const float extent = glm::length(hi - lo);
  s->lights.push_back(Light{0.5f * (lo + hi) + extent * Vec3(0.6f, 1.2f, 0.9f), Vec3(0.9f), 0.0f});
  s->ambient = default_hemisphere_ambient();
  finalize_scene(*s);
  return s;
}

// A volume file shown alone (OpenVDB, NRRD): a level set as its isosurface, densities through the
// volume shader in grayscale (the JSON reader's defaults), one light, framed by the camera.
Result<std::unique_ptr<Scene>> load_volume_file_scene(const std::string& path, const std::string& name) {
  nlohmann::json j = {
      {"objects", {{{"type", "volume"}, {"file", std::filesystem::absolute(path).string()}}}},
      {"lights", {{{"type", "point"}, {"position", {0, 1, 0}}, {"color", {0.9, 0.9, 0.9}}}}},
      {"ambient", {{"type", "hemisphere"}, {"a", {0.2, 0.2, 0.22}}, {"b", {0.06, 0.06, 0.06}}}}};
  auto scene = parse_scene_json(j.dump(), path, ".");
  // Only the file knows whether it holds a level set, whose surface needs a material: then again
  // with one (the one case a file is read twice).
  const std::string wants_material = "objects[0].material: missing";
  if (!scene && scene.error().message.size() >= wants_material.size() &&
      scene.error().message.compare(scene.error().message.size() - wants_material.size(), std::string::npos, wants_material) == 0) {
    j["materials"] = {{"surface", {{"class", "diffuse"}, {"kd", {0.75, 0.72, 0.68}}}}};
    j["objects"][0]["material"] = "surface";
    scene = parse_scene_json(j.dump(), path, ".");
  }
  if (!scene) return scene.error();
  Scene& s = **scene;
  const VolumeObject& v = s.volumes.front();
  s.name = name;
  s.camera = frame_camera(v.lo, v.hi, s.settings.width, s.settings.height);
  s.lights.front().position = 0.5f * (v.lo + v.hi) + glm::length(v.hi - v.lo) * Vec3(0.6f, 1.2f, 0.9f);
  return scene;
}

Result<std::unique_ptr<Scene>> load_scene_any_text(const std::string& spec) {
  const std::string ext = file_extension(spec);
  if (ext == ".json") return load_scene_json(spec);
  const size_t slash = spec.find_last_of('/');
  const std::string name = slash == std::string::npos ? spec : spec.substr(slash + 1);
  if (ext == ".spheres") return load_sphere_scene(spec, name);
  if (ext == ".vdb" || ext == ".nrrd" || ext == ".nhdr") return load_volume_file_scene(spec, name);
  if (ext == ".obj" || ext == ".ply") {
    // An OBJ that names MTL libraries keeps its materials and textures; others get the default.
    ImageCache images;
    auto bytes = read_file_bytes(spec);
    if (!bytes) return bytes.error();
    auto mesh = ext == ".obj" ? parse_obj_with_materials(*bytes, spec, images)
                              : parse_ply(*bytes, spec);
    if (!mesh) return mesh.error();
    auto scene = make_mesh_scene(std::move(*mesh), name);
    finalize_scene(*scene);
    return scene;
  }
  if (ext == ".gltf" || ext == ".glb") {
    ImageCache images;
    auto model = load_gltf(spec, images);
    if (!model) return model.error();
    for (const std::string& w : model->warnings) std::fprintf(stderr, "frameless: %s\n", w.c_str());
    auto scene = make_mesh_scene(std::move(model->mesh), name);
    // The model's first camera and its lights replace the framing camera and default light.
    if (!model->cameras.empty() && camera_is_valid(model->cameras.front()))
      scene->camera = model->cameras.front();
    if (!model->lights.empty()) scene->lights = std::move(model->lights);
    finalize_scene(*scene);
    return scene;
  }
  return make_builtin_scene(spec);
}

// What load_scene_any_text dispatches on, besides built-in names.
const char* const kSceneFileKinds[] = {".json", ".obj", ".ply", ".gltf", ".glb", ".vdb", ".nrrd", ".nhdr", ".spheres"};

}  // namespace

bool is_scene_file(const std::string& spec) {
  const std::string ext = file_extension(spec);
  for (const char* k : kSceneFileKinds)
    if (ext == k) return true;
  return false;
}

std::string scene_file_kinds() {
  std::string out;
  for (const char* k : kSceneFileKinds) out += (out.empty() ? "" : ", ") + std::string(k);
  return out;
}

// File names and strings from the input appear in errors: keep every message on one line.
Result<std::unique_ptr<Scene>> load_scene(const std::string& spec) {
  auto scene = one_line(load_scene_any_text(spec));
  // The radiosity-based ambient is baked by the path tracer once the scene is finalized.
  if (scene && (*scene)->ambient.kind == AmbientKind::kIrradianceVolume && !(*scene)->ambient.volume)
    bake_irradiance_volume(**scene);
  return scene;
}

}  // namespace frameless
