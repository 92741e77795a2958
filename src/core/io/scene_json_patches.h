// JSON for spline surfaces (docs/scene-format.md, "bezier"): a POV-Ray bicubic_patch file or
// inline control points; loading thread.
#pragma once
#include <string>

#include "core/io/scene_json_util.h"
#include "core/scene/scene.h"

namespace frameless::scene_json {

// Subdivision depth of a patch's bottom-up BVH when the object does not set "depth".
inline constexpr int kDefaultPatchDepth = 4;

// Adds the patches of a {"type": "bezier"} object (already checked to be an object) to s.
void parse_bezier(const json& o, const std::string& f, Scene& s, const std::string& base_dir,
                  uint16_t material, const glm::mat4& object_to_world);

}  // namespace frameless::scene_json
