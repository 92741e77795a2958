// JSON scene files (docs/scene-format.md): read, validated field by field, finalized (loading
// thread). Errors name the file, the field and what is wrong, on one line.
#pragma once
#include <memory>
#include <string>

#include "core/base/error.h"
#include "core/scene/scene.h"

namespace frameless {

// The file at `path`, or its text (relative paths inside resolve against base_dir).
Result<std::unique_ptr<Scene>> load_scene_json(const std::string& path);
Result<std::unique_ptr<Scene>> parse_scene_json(const std::string& text, const std::string& path,
                                                const std::string& base_dir);
}  // namespace frameless
