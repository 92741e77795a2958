// 8-bit sRGB PNG output of a linear float RGB image (for people to look at); any thread.
#pragma once
#include <string>

#include "core/base/error.h"

namespace frameless {

// rgb: width*height*3 linear floats, row 0 at the top. Clamped to [0,1], sRGB-encoded.
// Written to a temporary name and renamed.
Result<bool> write_png(const std::string& path, int width, int height, const float* rgb);
// Same, for an 8-bit RGB buffer already encoded.
Result<bool> write_png_rgb8(const std::string& path, int width, int height,
                            const unsigned char* rgb8);
// Linear -> sRGB 8-bit encoding of one value (clamped).
unsigned char linear_to_srgb8(float v);

}  // namespace frameless
