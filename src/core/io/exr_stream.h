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

}  // namespace frameless
