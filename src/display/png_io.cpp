#include "display/png_io.h"

#include <png.h>

#include <cmath>
#include <cstdio>
#include <vector>

#include "display/atomic_file.h"

namespace frameless {

unsigned char linear_to_srgb8(float v) {
  if (!(v > 0.0f)) return 0;  // also maps NaN to black
  if (v >= 1.0f) return 255;
  const float s = v <= 0.0031308f ? 12.92f * v : 1.055f * std::pow(v, 1.0f / 2.4f) - 0.055f;
  return (unsigned char)std::lround(s * 255.0f);
}

Result<bool> write_png_rgb8(const std::string& path, int width, int height,
                            const unsigned char* rgb8) {
  if (width <= 0 || height <= 0) return Error{path + ": cannot write an empty image"};
  const std::string tmp = temporary_path_for(path);
  FILE* f = std::fopen(tmp.c_str(), "wb");
  if (!f) return Error{path + ": cannot open for writing"};
  png_structp png = png_create_write_struct(PNG_LIBPNG_VER_STRING, nullptr, nullptr, nullptr);
  png_infop info = png ? png_create_info_struct(png) : nullptr;
  volatile bool ok = png && info;
  if (ok && setjmp(png_jmpbuf(png))) ok = false;
  if (ok) {
    png_init_io(png, f);
    png_set_IHDR(png, info, width, height, 8, PNG_COLOR_TYPE_RGB, PNG_INTERLACE_NONE,
                 PNG_COMPRESSION_TYPE_DEFAULT, PNG_FILTER_TYPE_DEFAULT);
    png_write_info(png, info);
    for (int y = 0; y < height; ++y)
      png_write_row(png, const_cast<png_bytep>(rgb8 + size_t(y) * width * 3));
    png_write_end(png, nullptr);
  }
  png_destroy_write_struct(png ? &png : nullptr, info ? &info : nullptr);
  ok = (std::fclose(f) == 0) && ok;
  if (!ok) {
    std::remove(tmp.c_str());
    return Error{path + ": cannot write PNG"};
  }
  std::string err;
  if (!commit_temporary(tmp, path, err)) return Error{err};
  return true;
}

Result<bool> write_png(const std::string& path, int width, int height, const float* rgb) {
  std::vector<unsigned char> bytes(size_t(width > 0 ? width : 0) * (height > 0 ? height : 0) * 3);
  for (size_t i = 0; i < bytes.size(); ++i) bytes[i] = linear_to_srgb8(rgb[i]);
  return write_png_rgb8(path, width, height, bytes.data());
}

}  // namespace frameless
