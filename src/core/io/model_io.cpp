// Mesh and model files by extension: PLY, OBJ (with MTL when named), glTF/GLB (with its shared
// meshes and their placements: add_mesh copies or instances them).
#include "core/io/file_util.h"
#include "core/io/mesh_readers.h"

namespace frameless {

Result<MeshData> load_mesh(const std::string& path) {
  const std::string ext = file_extension(path);
  if (ext != ".obj" && ext != ".ply")
    return Error{path + ": unknown mesh format '" + ext + "' (expected .obj or .ply)"};
  auto bytes = read_file_bytes(path);
  if (!bytes) return bytes.error();
  return ext == ".obj" ? parse_obj(*bytes, path) : parse_ply(*bytes, path);
}

Result<MeshData> load_model_mesh(const std::string& path, ImageCache& images) {
  const std::string ext = file_extension(path);
  if (ext == ".gltf" || ext == ".glb") {
    auto model = load_gltf(path, images);
    if (!model) return model.error();
    return std::move(model->mesh);
  }
  if (ext == ".obj") {
    auto text = read_file_bytes(path);
    if (!text) return text.error();
    // Only files that name a material library need the material path.
    const bool has_mtllib = text->find("mtllib") != std::string::npos;
    if (has_mtllib) return load_obj_with_materials(path, images);
    return parse_obj(*text, path);
  }
  return load_mesh(path);
}

}  // namespace frameless
