// Radiance HDR (.hdr, .pic: RGBE, Ward 1991) decoding, the format most environment maps come in.
#pragma once
#include <memory>
#include <string>

#include "core/base/error.h"
#include "core/scene/texture.h"

namespace frameless {

// True when `bytes` starts like a Radiance file ("#?RADIANCE" or "#?RGBE").
bool looks_like_rgbe(const std::string& bytes);

// Decodes a Radiance file to linear RGB floats (Image::hdr, 3 channels): flat, old-style and
// new-style run-length scanlines, -Y or +Y row order with +X columns, RGB (not XYZ) pixels, an
// EXPOSURE line divided out. Refuses images over kMaxTexturePixels before allocating; errors
// name the file and what is wrong, on one line.
Result<std::shared_ptr<const Image>> decode_rgbe(const std::string& bytes, const std::string& path);

}  // namespace frameless
