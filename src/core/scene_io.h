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
struct MeshData {
  std::vector<Vec3> positions;
  std::vector<Vec3> normals;  // empty or one per position
  std::vector<UVec3> triangles;
};
Result<MeshData> load_mesh(const std::string& path);  // by extension: .obj, .ply
Result<MeshData> parse_obj(const std::string& text, const std::string& path);
Result<MeshData> parse_ply(const std::string& bytes, const std::string& path);

// Built-in scenes; nullopt-like error for unknown names.
Result<std::unique_ptr<Scene>> make_builtin_scene(const std::string& name);
// Names for --help.
const char* builtin_scene_help();

}  // namespace frameless
