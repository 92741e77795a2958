// The scene-name dispatcher: a built-in scene by name, a JSON scene file, or a mesh or model file
// shown alone. Runs on the loading thread; returns a finalized Scene or a one-line error.
#pragma once
#include <memory>
#include <optional>
#include <string>

#include "core/base/error.h"
#include "core/io/mesh_readers.h"  // the readers it dispatches to
#include "core/io/scene_json.h"
#include "core/scene/scene.h"

namespace frameless {

// Loads SPEC: a built-in name ("default", "balls", "spheres:N", "bunny"), a .json scene file,
// a mesh file (.obj, .ply, .gltf, .glb) shown with a default material, light and framing camera,
// or a volume file (.vdb, .nrrd, .nhdr) shown alone the same way.
// The returned scene is finalized (accel built).
Result<std::unique_ptr<Scene>> load_scene(const std::string& spec);

// Whether SPEC names a file load_scene reads (by its extension: scenes, meshes, models, sphere
// lists, volumes) rather than a built-in scene; callers check such a file exists before long work.
bool is_scene_file(const std::string& spec);
// The extensions is_scene_file accepts, as a list for messages (".json, .obj, ...").
std::string scene_file_kinds();

// Built-in scenes; nullopt-like error for unknown names.
Result<std::unique_ptr<Scene>> make_builtin_scene(const std::string& name);
// Names for --help.
const char* builtin_scene_help();

}  // namespace frameless
