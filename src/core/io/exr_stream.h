// OpenEXR input from bytes already in memory: the readers check sizes before the library
// allocates, and the fuzzer feeds bytes without files (loading thread).
#pragma once
#include <algorithm>
#include <cstdint>
#include <cstring>
#include <string>

#include <IexBaseExc.h>
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

}  // namespace frameless
