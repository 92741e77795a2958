// Scene input: JSON scene files, OBJ/PLY meshes given directly, and built-in scenes by name.
// Runs on the loading thread; returns a finalized Scene or a one-line error.
#pragma once
#include <memory>
#include <optional>
#include <string>

#include "core/error.h"
#include "core/scene.h"

namespace frameless {

// Loads SPEC: a built-in name ("default", "balls", "spheres:N", "bunny"), a .json scene file,
// or a mesh file (.obj, .ply) shown with a default material, light and framing camera.
// The returned scene is finalized (accel built).
Result<std::unique_ptr<Scene>> load_scene(const std::string& spec);

// Lower-level pieces (tests and the fuzzer call them directly).
Result<std::unique_ptr<Scene>> load_scene_json(const std::string& path);
Result<std::unique_ptr<Scene>> parse_scene_json(const std::string& text, const std::string& path,
                                                const std::string& base_dir);
// One placement of a shared mesh of a model: model space = to_model * the mesh's object space.
struct MeshPlacement {
  uint32_t mesh = 0;  // index into MeshData::shared
  glm::mat4 to_model{1.0f};
};

// A mesh as read from a file. Files that carry materials (OBJ+MTL, glTF) fill `materials`
// (their texture slots index `textures`) and give each triangle one of them in face_material;
// add_mesh maps both into the scene. Otherwise the caller's material applies to every face.
struct MeshData {
  std::vector<Vec3> positions;
  std::vector<Vec3> normals;  // empty or one per position
  std::vector<Vec2> uvs;      // empty or one per position
  std::vector<UVec3> triangles;
  std::vector<uint16_t> face_material;  // empty, or one index into materials per triangle
  std::vector<Material> materials;
  std::vector<Texture> textures;
  // Meshes the file places more than once (glTF meshes that two or more nodes reference), each
  // stored once in its own object space with the same invariants as above, except that their
  // face_material indexes this mesh's `materials` (their own materials and textures stay
  // empty). add_mesh copies them per placement, or places one shared InstancedMesh each.
  std::vector<MeshData> shared;
  std::vector<MeshPlacement> placements;
};

// What a model file brings besides its mesh (glTF): its cameras and lights, in model space
// after the node transforms, and warnings to print once (unsupported features).
struct ModelData {
  MeshData mesh;
  std::vector<Camera> cameras;
  std::vector<Light> lights;
  std::vector<std::string> warnings;
};

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

// Built-in scenes; nullopt-like error for unknown names.
Result<std::unique_ptr<Scene>> make_builtin_scene(const std::string& name);
// Names for --help.
const char* builtin_scene_help();

}  // namespace frameless
