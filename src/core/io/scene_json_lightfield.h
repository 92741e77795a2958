// The "lightfield" objects of a scene file (issue 28): a baked light slab (docs/lightfields.md)
// placed by a transform.
#pragma once
#include <string>

#include "core/io/scene_json_util.h"
#include "core/scene/scene.h"

namespace frameless::scene_json {

// Reads object `o` (field path `f`) and appends it to s.lightfields; a relative file resolves
// against base_dir. Problems fail with the field and, for the file, what is wrong with it.
void parse_lightfield(const json& o, const std::string& f, Scene& s, const std::string& base_dir);

}  // namespace frameless::scene_json
