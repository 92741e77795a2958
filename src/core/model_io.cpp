// Model files by extension for JSON scenes: PLY, OBJ (with MTL when named), glTF/GLB (with its
// shared meshes and their placements: add_mesh copies or instances them).
#include "core/scene_build.h"
#include "core/scene_io.h"

namespace frameless {

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
