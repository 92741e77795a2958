// Byte-level reading and writing of the cluster's messages (wire.cpp, wire_pieces.cpp):
// little-endian fixed-width fields, counts before arrays, every read bounds-checked.
#pragma once
#include <cmath>
#include <cstring>
#include <stdexcept>
#include <string>
#include <vector>

#include "cluster/wire.h"

namespace frameless::cluster::wire_io {

static_assert(sizeof(float) == 4 && sizeof(double) == 8);

class Writer {
 public:
  explicit Writer(size_t reserve = 64) { out_.reserve(reserve); head(); }
  template <class T>
  void put(const T& v) {
    const size_t n = out_.size();
    out_.resize(n + sizeof(T));
    std::memcpy(out_.data() + n, &v, sizeof(T));
  }
  void str(const std::string& s) {
    put(uint32_t(s.size()));
    out_.insert(out_.end(), s.begin(), s.end());
  }
  std::vector<uint8_t> take() { return std::move(out_); }

 private:
  void head() {
    put(kWireMagic);
    put(kWireVersion);
  }
  std::vector<uint8_t> out_;
};

class Reader {
 public:
  Reader(const uint8_t* data, size_t size, const char* what) : p_(data), n_(size), what_(what) {
    if (get<uint32_t>("magic") != kWireMagic) fail("magic", "not a frameless cluster message");
    if (const uint32_t v = get<uint32_t>("version"); v != kWireVersion)
      fail("version", "wire version " + std::to_string(v) + ", this build speaks " +
                          std::to_string(kWireVersion));
  }
  template <class T>
  T get(const char* field) {
    if (n_ - i_ < sizeof(T)) fail(field, "message truncated");
    T v;
    std::memcpy(&v, p_ + i_, sizeof(T));
    i_ += sizeof(T);
    return v;
  }
  float finite(const char* field) {
    const float v = get<float>(field);
    if (!std::isfinite(v)) fail(field, "not finite");
    return v;
  }
  // A count of items of at least `item_bytes` each: never more than the bytes left.
  uint32_t count(const char* field, size_t item_bytes) {
    const uint32_t c = get<uint32_t>(field);
    if (item_bytes && uint64_t(c) * item_bytes > n_ - i_) fail(field, "count beyond the message");
    return c;
  }
  std::string str(const char* field, size_t max) {
    const uint32_t len = count(field, 1);
    if (len > max) fail(field, "longer than " + std::to_string(max) + " bytes");
    std::string s(reinterpret_cast<const char*>(p_ + i_), len);
    i_ += len;
    return s;
  }
  void end() {
    if (i_ != n_) fail("end", std::to_string(n_ - i_) + " trailing bytes");
  }
  [[noreturn]] void fail(const char* field, const std::string& problem) const {
    throw std::invalid_argument(std::string(what_) + "." + field + ": " + problem);
  }

 private:
  const uint8_t* p_;
  size_t n_, i_ = 0;
  const char* what_;
};

inline void put_camera(Writer& w, const Camera& c) {
  for (const Vec3& v : {c.eye, c.look, c.up})
    for (int k = 0; k < 3; ++k) w.put(v[k]);
  w.put(c.fov_deg);
}

inline Camera get_camera(Reader& r) {
  Camera c;
  for (Vec3* v : {&c.eye, &c.look, &c.up})
    for (int k = 0; k < 3; ++k) (*v)[k] = r.finite("camera");
  c.fov_deg = r.finite("camera.fov");
  if (!camera_is_valid(c)) r.fail("camera", "degenerate camera");
  return c;
}

inline uint16_t to_bfloat16(float v) {
  uint32_t u;
  std::memcpy(&u, &v, 4);
  u += 0x7fffu + ((u >> 16) & 1u);  // round to nearest even (finite, non-negative inputs)
  return uint16_t(u >> 16);
}

inline float from_bfloat16(uint16_t h) {
  const uint32_t u = uint32_t(h) << 16;
  float v;
  std::memcpy(&v, &u, 4);
  return v;
}

}  // namespace frameless::cluster::wire_io
