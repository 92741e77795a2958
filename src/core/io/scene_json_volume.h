// The "volume" objects of a scene file (issue 27): where the grid comes from (raw, NRRD or a
// built-in generator), how it is rendered (isosurfaces, volume shader, MIP) and where it sits.
#pragma once
#include <functional>
#include <string>

#include "core/io/scene_json_util.h"
#include "core/scene/scene.h"

namespace frameless::scene_json {

// Names a material (the JSON string at `field`) -> its id; fails on an unknown one.
using MaterialLookup = std::function<uint16_t(const json& name, const std::string& field)>;

// Reads object `o` (field path `f`) and appends it to s.volumes; relative files resolve against
// base_dir. Every problem fails with the field and, for data, the file.
void parse_volume(const json& o, const std::string& f, Scene& s, const std::string& base_dir,
                  const MaterialLookup& material);

}  // namespace frameless::scene_json
