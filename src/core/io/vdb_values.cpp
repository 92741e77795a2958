// OpenVDB's value encoding (io/Compression.h of OpenVDB 10, file versions 222 and later).
#include "core/io/vdb_values.h"

#include <Imath/half.h>
#include <blosc.h>
#include <zlib.h>

#include <bit>
#include <cmath>

namespace frameless::vdb {
namespace {

static_assert(std::endian::native == std::endian::little,
              "OpenVDB files are read in the machine's byte order");

[[noreturn]] void fail(const std::string& what) { throw VdbFailure{what}; }

size_t value_bytes(Stored s) { return s == Stored::kHalf ? 2 : s == Stored::kDouble ? 8 : 4; }

// One compressed chunk of exactly `bytes` bytes: int64 n, then -n raw bytes (n <= 0, OpenVDB's
// "compression did not pay") or n compressed ones.
void read_chunk(Cursor& c, uint32_t compression, size_t bytes, uint8_t* out) {
  if (!(compression & (kCompressZip | kCompressBlosc))) {
    if (bytes) std::memcpy(out, c.take(bytes, "node values"), bytes);
    return;
  }
  const int64_t n = c.get<int64_t>("the size of a compressed chunk");
  if (n <= 0) {
    if (n == INT64_MIN || uint64_t(-n) != bytes)
      fail("a stored chunk of " + std::to_string(n == INT64_MIN ? 0 : -n) + " bytes where " +
           std::to_string(bytes) + " are expected");
    if (bytes) std::memcpy(out, c.take(bytes, "node values"), bytes);
    return;
  }
  const uint8_t* src = c.take(uint64_t(n), "a compressed chunk");
  if (compression & kCompressBlosc) {
    size_t nbytes = 0;
    if (blosc_cbuffer_validate(src, size_t(n), &nbytes) != 0) fail("a corrupt Blosc chunk");
    if (nbytes != bytes)
      fail("a Blosc chunk of " + std::to_string(nbytes) + " bytes where " + std::to_string(bytes) +
           " are expected");
    if (blosc_decompress_ctx(src, out, bytes, 1) != int(bytes)) fail("a corrupt Blosc chunk");
  } else {
    uLongf got = uLongf(bytes);
    if (uncompress(out, &got, src, uLong(n)) != Z_OK || got != bytes) fail("a corrupt zlib chunk");
  }
}

}  // namespace

void Cursor::seek(uint64_t p, const char* what) {
  if (p > size_)
    fail(std::string(what) + " at byte " + std::to_string(p) + ", past the end (" +
         std::to_string(size_) + " bytes)");
  pos_ = size_t(p);
}

const uint8_t* Cursor::take(uint64_t n, const char* what) {
  if (n > size_ - pos_)
    fail(std::string("truncated in ") + what + " (byte " + std::to_string(pos_) + ")");
  const uint8_t* p = data_ + pos_;
  pos_ += size_t(n);
  return p;
}

std::string Cursor::string(const char* what) {
  const uint32_t n = get<uint32_t>(what);
  if (n > (1u << 20))
    fail(std::string(what) + ": a string of " + std::to_string(n) + " bytes (byte " +
         std::to_string(pos_) + ")");
  const uint8_t* p = take(n, what);
  return std::string(reinterpret_cast<const char*>(p), n);
}

size_t Mask::count() const {
  size_t n = 0;
  for (uint64_t w : words) n += size_t(std::popcount(w));
  return n;
}

Mask read_mask(Cursor& c, size_t bits, const char* what) {
  Mask m;
  m.words.resize(bits / 64);
  std::memcpy(m.words.data(), c.take(bits / 8, what), bits / 8);
  return m;
}

float read_full(Cursor& c, Stored full, const char* what) {
  return full == Stored::kDouble ? float(c.get<double>(what)) : c.get<float>(what);
}

void read_values(Cursor& c, uint32_t compression, Stored stored, Stored full, float background,
                 const Mask& mask, size_t count, float* out) {
  // OpenVDB's codes: 0 all inactive values are the background, 1 all are -background, 2 one other
  // value, 3 +-background chosen by a selection mask, 4 one value or the background by the mask,
  // 5 two values by the mask, 6 every value is stored.
  const int8_t code = c.get<int8_t>("a node's value code");
  if (code < 0 || code > 6)
    fail("unknown node value code " + std::to_string(code) + " (byte " +
         std::to_string(c.pos() - 1) + ")");
  float inactive1 = background, inactive0 = code == 0 ? background : -background;
  if (code == 2 || code == 4 || code == 5) {
    inactive0 = read_full(c, full, "an inactive value");
    if (code == 5) inactive1 = read_full(c, full, "an inactive value");
  }
  Mask selection;
  if (code >= 3 && code <= 5) selection = read_mask(c, count, "a selection mask");
  const bool active_only = (compression & kCompressActiveMask) && code != 6;
  const size_t stored_count = active_only ? mask.count() : count;
  std::vector<uint8_t> raw(stored_count * value_bytes(stored));
  if (stored_count > 0 || stored != Stored::kHalf) read_chunk(c, compression, raw.size(), raw.data());  // OpenVDB writes no empty half chunk
  const auto value = [&](size_t i) {
    const uint8_t* p = raw.data() + i * value_bytes(stored);
    if (stored == Stored::kHalf) {
      uint16_t h;
      std::memcpy(&h, p, 2);
      return imath_half_to_float(h);  // Imath (OpenEXR's): IEEE binary16
    }
    if (stored == Stored::kDouble) {
      double d;
      std::memcpy(&d, p, 8);
      return float(d);
    }
    float f;
    std::memcpy(&f, p, 4);
    return f;
  };
  if (stored_count == count) {
    for (size_t i = 0; i < count; ++i) out[i] = value(i);
    return;
  }
  for (size_t i = 0, k = 0; i < count; ++i)
    out[i] = mask.on(i)                                  ? value(k++)
             : code >= 3 && code <= 5 && selection.on(i) ? inactive1
                                                         : inactive0;
}

}  // namespace frameless::vdb
