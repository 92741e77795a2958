// PNG chunk pieces for tests that craft PNG files byte by byte (test thread only).
#pragma once
#include <cstdint>
#include <string>

namespace frameless::testing {

// CRC-32 of PNG chunks (ISO 3309, reflected polynomial 0xedb88320).
inline uint32_t crc32(const std::string& s) {
  uint32_t c = 0xffffffffu;
  for (unsigned char b : s) {
    c ^= b;
    for (int k = 0; k < 8; ++k) c = (c >> 1) ^ (0xedb88320u & (0u - (c & 1u)));
  }
  return ~c;
}

inline std::string be32(uint32_t v) {
  return {char(v >> 24), char(v >> 16), char(v >> 8), char(v)};
}

// Length, type, data and CRC of one chunk.
inline std::string png_chunk(const std::string& type, const std::string& data) {
  return be32(uint32_t(data.size())) + type + data + be32(crc32(type + data));
}

}  // namespace frameless::testing
