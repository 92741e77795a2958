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

namespace exr_detail {

inline uint32_t le32(const std::string& bytes, size_t at) {
  return uint32_t(uint8_t(bytes[at])) | uint32_t(uint8_t(bytes[at + 1])) << 8 | uint32_t(uint8_t(bytes[at + 2])) << 16 |
         uint32_t(uint8_t(bytes[at + 3])) << 24;
}

// Moves `p` past a null-terminated name of at most 255 characters ending before `end`.
inline bool skip_name(const std::string& bytes, size_t& p, size_t end) {
  const size_t zero = bytes.find('\0', p);
  if (zero == std::string::npos || zero >= end || zero - p > 255) return false;
  p = zero + 1;
  return true;
}

// Whether an attribute of type `type` reads exactly its `size` bytes at `at`. OpenEXR's readers
// of known types read what their type says, not what the size says: a channel list runs to its
// terminating name, a preview reads width x height pixels, a string vector its strings' lengths,
// a fixed type its own bytes; a value that disagrees with its size shifts everything after it,
// and the next "size" OpenEXR reads is arbitrary bytes (a 1.3 GB allocation, found by the fuzzer).
inline bool value_fits(const std::string& bytes, const std::string& type, size_t at, uint32_t size) {
  const size_t end = at + size;
  if (type == "chlist") {  // (name, int type, u8 linear, 3 reserved, int x and y sampling)..., ""
    size_t p = at;
    while (p < end && bytes[p] != '\0')
      if (!skip_name(bytes, p, end) || end - p < 16) return false;
      else p += 16;
    return p + 1 == end;
  }
  if (type == "preview")  // width, height, then 4 bytes a pixel
    return size >= 8 && (size - 8) % 4 == 0 && uint64_t(le32(bytes, at)) * le32(bytes, at + 4) == (size - 8) / 4;
  if (type == "stringvector") {  // (int length, characters)...
    size_t p = at;
    while (p < end) {
      if (end - p < 4 || le32(bytes, p) > end - p - 4) return false;
      p += 4 + le32(bytes, p);
    }
    return true;
  }
  if (type == "floatvector") return size % 4 == 0;
  if (type == "idmanifest") return size >= 4;
  static const struct {
    const char* name;
    uint32_t bytes;
  } kFixed[] = {{"box2i", 16}, {"box2f", 16}, {"chromaticities", 32}, {"compression", 1}, {"deepImageState", 1},
                {"double", 8}, {"envmap", 1}, {"float", 4}, {"int", 4}, {"keycode", 28}, {"lineOrder", 1},
                {"m33d", 72}, {"m33f", 36}, {"m44d", 128}, {"m44f", 64}, {"rational", 8}, {"tiledesc", 9},
                {"timecode", 8}, {"v2d", 16}, {"v2f", 8}, {"v2i", 8}, {"v3d", 24}, {"v3f", 12}, {"v3i", 12}};
  for (const auto& f : kFixed)
    if (type == f.name) return size == f.bytes;
  return true;  // a string or an unknown type: exactly `size` bytes
}

}  // namespace exr_detail

// Walks the headers' attribute lists (name, type, size, value; every part's of a multi-part file)
// and checks each size against the bytes that follow and each known type's value against its size,
// before OpenEXR allocates what a size claims: "" or what is wrong.
inline std::string exr_header_problem(const std::string& bytes) {
  using namespace exr_detail;
  if (bytes.size() < 8) return "header is truncated";
  const bool multipart = le32(bytes, 4) & 0x1000;
  size_t at = 8;  // past the magic and the version field
  for (int part = 0; part < 1024; ++part) {
    for (int attributes = 0;; ++attributes) {
      if (attributes == 4096) return "header has more than 4096 attributes";
      if (at >= bytes.size()) return "header is truncated";
      if (bytes[at] == '\0') break;  // the header's end
      const bool named = skip_name(bytes, at, bytes.size());
      const size_t type_at = at;
      if (!named || !skip_name(bytes, at, bytes.size()))
        return "header attribute " + std::to_string(attributes) + " has no valid name or type";
      const std::string type = bytes.substr(type_at, at - 1 - type_at);
      if (bytes.size() - at < 4) return "header is truncated";
      const uint32_t size = le32(bytes, at);
      at += 4;
      if (size > bytes.size() - at) return "header attribute " + std::to_string(attributes) + " claims more bytes than the file holds";
      if (!value_fits(bytes, type, at, size))
        return "header attribute " + std::to_string(attributes) + " (" + type + ") does not fill its " + std::to_string(size) + " bytes";
      at += size;
    }
    ++at;  // past the header's end
    if (!multipart || (at < bytes.size() && bytes[at] == '\0')) return "";  // one header, or the parts' end
  }
  return "file has more than 1024 parts";
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
