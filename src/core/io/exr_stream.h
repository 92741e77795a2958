// OpenEXR input from bytes already in memory: the readers check sizes before the library
// allocates, and the fuzzer feeds bytes without files (loading thread).
#pragma once
#include <algorithm>
#include <cstdint>
#include <cstring>
#include <string>

#include <IexBaseExc.h>
#include <ImfChannelList.h>
#include <ImfCompression.h>
#include <ImfHeader.h>
#include <ImfIO.h>

namespace frameless {

class ExrMemoryStream : public Imf::IStream {
 public:
  ExrMemoryStream(const std::string& bytes, const std::string& path)
      : Imf::IStream(path.c_str()), bytes_(bytes) {}
  bool read(char c[], int n) override {
    if (n < 0 || uint64_t(n) > bytes_.size() - pos_) throw Iex::InputExc("file is truncated");
    std::memcpy(c, bytes_.data() + pos_, size_t(n));
    pos_ += uint64_t(n);
    return pos_ < bytes_.size();
  }
  uint64_t tellg() override { return pos_; }
  void seekg(uint64_t pos) override { pos_ = std::min<uint64_t>(pos, bytes_.size()); }

 private:
  const std::string& bytes_;
  uint64_t pos_ = 0;
};

// Walks the first header's attribute list (name, type, size, value) and checks every size against
// the bytes that follow, before OpenEXR allocates what a size claims: "" or what is wrong.
inline std::string exr_header_problem(const std::string& bytes) {
  size_t at = 8;  // past the magic and the version field
  const auto c_string = [&](size_t& p) {
    const size_t end = bytes.find('\0', p);
    if (end == std::string::npos || end - p > 255) return false;
    p = end + 1;
    return true;
  };
  for (int attributes = 0; attributes < 4096; ++attributes) {
    if (at >= bytes.size()) return "header is truncated";
    if (bytes[at] == '\0') return "";  // the header's end
    if (!c_string(at) || !c_string(at)) return "header attribute " + std::to_string(attributes) + " has no valid name or type";
    if (bytes.size() - at < 4) return "header is truncated";
    const uint32_t size = uint32_t(uint8_t(bytes[at])) | uint32_t(uint8_t(bytes[at + 1])) << 8 |
                          uint32_t(uint8_t(bytes[at + 2])) << 16 | uint32_t(uint8_t(bytes[at + 3])) << 24;
    at += 4;
    if (size > bytes.size() - at) return "header attribute " + std::to_string(attributes) + " claims more bytes than the file holds";
    at += size;
  }
  return "header has more than 4096 attributes";
}

// The bytes OpenEXR sets aside to decode one chunk (a block of scan lines, or a tile) are at
// most this many; InputFile allocates them before reading a pixel.
inline constexpr uint64_t kMaxExrChunkBytes = uint64_t(256) << 20;

// Checks the chunk buffer a header implies (its width, its channels' bytes per pixel, the lines
// its compression decodes together, or its tile) against kMaxExrChunkBytes: "" or what is wrong.
// A file of few pixels can claim a buffer of gigabytes (16.7 M x 1 pixels, ZIP: 16 lines).
inline std::string exr_chunk_problem(const Imf::Header& header) {
  const Imath::Box2i dw = header.dataWindow();
  const uint64_t w = uint64_t(std::max<int64_t>(0, int64_t(dw.max.x) - dw.min.x + 1));
  uint64_t pixel_bytes = 0;
  for (auto c = header.channels().begin(); c != header.channels().end(); ++c)
    pixel_bytes += c.channel().type == Imf::HALF ? 2 : 4;
  uint64_t lines = 256;  // DWAB and anything newer
  switch (header.compression()) {
    case Imf::NO_COMPRESSION: case Imf::RLE_COMPRESSION: case Imf::ZIPS_COMPRESSION: lines = 1; break;
    case Imf::ZIP_COMPRESSION: case Imf::PXR24_COMPRESSION: lines = 16; break;
    case Imf::PIZ_COMPRESSION: case Imf::B44_COMPRESSION: case Imf::B44A_COMPRESSION:
    case Imf::DWAA_COMPRESSION: lines = 32; break;
    default: break;
  }
  uint64_t bytes = w * pixel_bytes * lines;
  if (header.hasTileDescription())
    bytes = uint64_t(header.tileDescription().xSize) * header.tileDescription().ySize * pixel_bytes;
  if (bytes <= kMaxExrChunkBytes) return "";
  return "a chunk needs " + std::to_string(bytes) + " bytes to decode (" + std::to_string(w) + " pixels wide, " +
         std::to_string(lines) + " lines a chunk), more than " + std::to_string(kMaxExrChunkBytes);
}

}  // namespace frameless
