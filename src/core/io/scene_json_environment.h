// settings.environment of JSON scene files: an equirectangular radiance image; loading thread
// only (throws Failure).
#pragma once
#include <string>

#include "core/io/image_io.h"
#include "core/io/scene_json_util.h"
#include "core/scene/scene.h"

namespace frameless::scene_json {

// {"file": F, "rotate": degrees about +y (default 0), "scale": radiance factor (default 1)}.
void parse_environment(const json& j, Scene& s, const std::string& base_dir, ImageCache& images);

}  // namespace frameless::scene_json
