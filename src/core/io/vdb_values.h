// The byte level of OpenVDB files (issue 27): a bounds-checked cursor over the file's bytes, and
// the node values as OpenVDB's readCompressedValues stores them (an inactive-value code, optional
// selection mask, then the active or all values, raw, zlib- or Blosc-compressed, in float, double
// or half). Everything that is wrong throws VdbFailure with what and where.
#pragma once
#include <cstdint>
#include <cstring>
#include <string>
#include <vector>

namespace frameless::vdb {

struct VdbFailure {
  std::string what;
};

// Little-endian reads from [data, data + size); `pos` is the next byte.
class Cursor {
 public:
  Cursor(const uint8_t* data, size_t size) : data_(data), size_(size) {}
  size_t pos() const { return pos_; }
  size_t size() const { return size_; }
  size_t left() const { return size_ - pos_; }
  void seek(uint64_t p, const char* what);
  const uint8_t* take(uint64_t n, const char* what);  // n bytes, or a failure naming `what`
  template <class T>
  T get(const char* what) {
    T v;
    std::memcpy(&v, take(sizeof(T), what), sizeof(T));
    return v;
  }
  std::string string(const char* what);  // uint32 length, then the bytes (at most 1 MiB)

 private:
  const uint8_t* data_;
  size_t size_, pos_ = 0;
};

enum : uint32_t { kCompressZip = 0x1, kCompressActiveMask = 0x2, kCompressBlosc = 0x4 };
enum class Stored : uint8_t { kFloat, kDouble, kHalf };  // how a grid's values are written

// A node mask: 512 bits for leaves, 4096 and 32768 for the internal nodes.
struct Mask {
  std::vector<uint64_t> words;
  bool on(size_t i) const { return (words[i >> 6] >> (i & 63)) & 1u; }
  size_t count() const;
};
Mask read_mask(Cursor& c, size_t bits, const char* what);

// `count` values of a node with value mask `mask`, as floats. `stored` is how the values are
// written; the background and inactive values are always at full precision (`full`).
void read_values(Cursor& c, uint32_t compression, Stored stored, Stored full, float background,
                 const Mask& mask, size_t count, float* out);

// A value of the grid's full type (float or double) as float.
float read_full(Cursor& c, Stored full, const char* what);

}  // namespace frameless::vdb
