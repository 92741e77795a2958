// Writes OpenEXR files byte by byte for tests (core_tests has no include path for OpenEXR's C++
// API nor a link to its C API); test thread only.
#pragma once
#include <cstdint>
#include <cstring>
#include <fstream>
#include <string>
#include <vector>

namespace frameless::testing {

inline void put_le(std::string& out, uint64_t v, int bytes) {
  for (int i = 0; i < bytes; ++i) out += char(v >> (8 * i));
}

inline void put_f32(std::string& out, float f) {
  uint32_t bits;
  std::memcpy(&bits, &f, 4);
  put_le(out, bits, 4);
}

inline void put_attribute(std::string& out, const char* name, const char* type, const std::string& v) {
  out += std::string(name) + '\0' + type + '\0';
  put_le(out, v.size(), 4);
  out += v;
}

// Writes an uncompressed single-part scanline OpenEXR of FLOAT channels, byte by byte from the
// file-format spec (core_tests has no include path for OpenEXR's C++ API nor a link to its C
// API). names must be sorted; planes[c] holds w*h values of channel c, rows top to bottom.
inline void write_exr(const std::string& path, int w, int h, const std::vector<std::string>& names,
               const std::vector<std::vector<float>>& planes) {
  std::string f("\x76\x2f\x31\x01", 4);
  put_le(f, 2, 4);  // version 2, single-part scanline
  std::string channels, box, v2f, one;
  for (const std::string& n : names) {
    channels += n + '\0';
    put_le(channels, 2, 4);  // FLOAT
    put_le(channels, 0, 4);  // pLinear and three reserved bytes
    put_le(channels, 1, 4);  // x sampling
    put_le(channels, 1, 4);  // y sampling
  }
  channels += '\0';
  for (int v : {0, 0, w - 1, h - 1}) put_le(box, uint32_t(v), 4);
  put_f32(v2f, 0.0f);
  put_f32(v2f, 0.0f);
  put_f32(one, 1.0f);
  put_attribute(f, "channels", "chlist", channels);
  put_attribute(f, "compression", "compression", std::string(1, '\0'));
  put_attribute(f, "dataWindow", "box2i", box);
  put_attribute(f, "displayWindow", "box2i", box);
  put_attribute(f, "lineOrder", "lineOrder", std::string(1, '\0'));
  put_attribute(f, "pixelAspectRatio", "float", one);
  put_attribute(f, "screenWindowCenter", "v2f", v2f);
  put_attribute(f, "screenWindowWidth", "float", one);
  f += '\0';
  const size_t line_bytes = 8 + size_t(w) * names.size() * 4;
  const size_t first = f.size() + size_t(h) * 8;
  for (int y = 0; y < h; ++y) put_le(f, first + size_t(y) * line_bytes, 8);
  for (int y = 0; y < h; ++y) {
    put_le(f, uint32_t(y), 4);
    put_le(f, line_bytes - 8, 4);
    for (size_t c = 0; c < names.size(); ++c)
      for (int x = 0; x < w; ++x) put_f32(f, planes[c][size_t(y * w + x)]);
  }
  std::ofstream(path, std::ios::binary) << f;
}

}  // namespace frameless::testing
