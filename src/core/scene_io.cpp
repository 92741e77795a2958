// Scene input entry points: dispatch a scene spec to the built-ins, the JSON reader or the mesh
// readers; loading thread only.
#include "core/scene_io.h"

#include "core/scene_build.h"

namespace frameless {

Result<MeshData> load_mesh(const std::string& path) {
  const std::string ext = file_extension(path);
  if (ext != ".obj" && ext != ".ply")
    return Error{path + ": unknown mesh format '" + ext + "' (expected .obj or .ply)"};
  auto bytes = read_file_bytes(path);
  if (!bytes) return bytes.error();
  return ext == ".obj" ? parse_obj(*bytes, path) : parse_ply(*bytes, path);
}

Result<std::unique_ptr<Scene>> load_scene_json(const std::string& path) {
  auto bytes = read_file_bytes(path);
  if (!bytes) return bytes.error();
  const size_t slash = path.find_last_of('/');
  const std::string base_dir = slash == std::string::npos ? "." : path.substr(0, slash);
  return parse_scene_json(*bytes, path, base_dir.empty() ? "/" : base_dir);
}

Result<std::unique_ptr<Scene>> load_scene(const std::string& spec) {
  const std::string ext = file_extension(spec);
  if (ext == ".json") return load_scene_json(spec);
  if (ext == ".obj" || ext == ".ply") {
    auto mesh = load_mesh(spec);
    if (!mesh) return mesh.error();
    const size_t slash = spec.find_last_of('/');
    auto scene = make_mesh_scene(std::move(*mesh),
                                 slash == std::string::npos ? spec : spec.substr(slash + 1));
    finalize_scene(*scene);
    return scene;
  }
  return make_builtin_scene(spec);
}

}  // namespace frameless
