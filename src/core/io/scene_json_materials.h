// Textures and materials of JSON scene files; loading thread only (throws Failure).
#pragma once
#include <map>
#include <set>
#include <string>

#include "core/io/image_io.h"
#include "core/io/scene_json_util.h"
#include "core/scene/scene.h"

namespace frameless::scene_json {

using TextureNames = std::map<std::string, uint32_t>;

// The "textures" object: image files (shared through `images`) and procedural solid textures;
// the ids of solid textures with "space": "object" go to object_space.
void parse_textures(const json& j, Scene& s, const std::string& base_dir, ImageCache& images,
                    TextureNames& names, std::set<uint32_t>& object_space);

// One entry of "materials", with its texture slots resolved by name.
Material parse_material(const std::string& name, const json& j, const std::string& f,
                        const TextureNames& textures, const Scene& scene);

// One entry of "materials" that names a plug-in shader ({"shader": NAME, "params": {...}}): the
// library loaded from the search path (core/io/shader_library.h) and the parameters checked by
// its declaration (texture parameters name entries of `textures`); adds the binding to scene.shaders.
Material parse_shader_material(const std::string& name, const json& j, const std::string& f, Scene& scene,
                               const std::string& base_dir, const TextureNames& textures);

}  // namespace frameless::scene_json
