// The mesh and model readers' entry points: OBJ (with MTL), PLY, glTF 2.0 (loading thread).
// Each returns the file's MeshData or a one-line error naming the file, line or field.
#pragma once
#include <string>

#include "core/base/error.h"
#include "core/io/image_io.h"
#include "core/scene/mesh_data.h"

namespace frameless {

Result<MeshData> load_mesh(const std::string& path);  // by extension: .obj, .ply
// Any model file by extension: .ply, .obj (with its MTL materials when it names a library),
// .gltf or .glb (the mesh and materials only); textures shared through `images`.
Result<MeshData> load_model_mesh(const std::string& path, ImageCache& images);
Result<MeshData> parse_obj(const std::string& text, const std::string& path);
Result<MeshData> parse_ply(const std::string& bytes, const std::string& path);
// OBJ with its MTL materials and textures (mtllib resolved relative to the OBJ's folder;
// texture paths relative to the MTL's folder, Windows separators and spaces accepted).
Result<MeshData> load_obj_with_materials(const std::string& path, ImageCache& images);
// glTF 2.0, .gltf or .glb (tinygltf): meshes, node transforms, PBR materials mapped onto
// Parker's classes, textures, cameras and KHR_lights_punctual lights.
Result<ModelData> load_gltf(const std::string& path, ImageCache& images);
Result<ModelData> parse_gltf(const std::string& bytes, const std::string& path,
                             const std::string& base_dir, ImageCache& images);

}  // namespace frameless
