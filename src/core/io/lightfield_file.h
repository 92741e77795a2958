// Lightfield files (docs/lightfields.md): an OpenEXR image, RGBA half, premultiplied, that is the
// mosaic of the slab's nu x nv views (each ns x nt texels), plus a small header of attributes:
// frameless:lightfield (int, format version 1), frameless:uv and frameless:st (V2i resolutions),
// frameless:slab (M44f, the slab frame [-1, 1]^3 in the model's coordinates) and frameless:scene
// (string, what was baked). Any EXR viewer shows the views side by side. Loading thread.
#pragma once
#include <memory>
#include <string>

#include "core/base/error.h"
#include "core/scene/lightfield.h"

namespace frameless {

inline constexpr int kLightfieldFormatVersion = 1;

// Reads and checks a lightfield file; every problem is one line naming the file.
Result<std::shared_ptr<const LightField>> load_lightfield(const std::string& path);
Result<std::shared_ptr<const LightField>> decode_lightfield(const std::string& bytes, const std::string& path);

// Writes `lf` to a temporary name beside `path` and renames it into place (no half-written
// file on failure).
Result<bool> write_lightfield(const std::string& path, const LightField& lf);

}  // namespace frameless
