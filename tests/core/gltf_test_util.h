// Helpers shared by the glTF tests (gltf, gltf_assimp, gltf_instances, gltf_instances_assimp).
#pragma once
#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <string>

#include <gtest/gtest.h>

#include "core/base/error.h"
#include "core/io/mesh_readers.h"

namespace frameless {
namespace test_util {

// Debian's glTF 2 sample models (apt-get install assimp-testmodels).
inline const std::string kModels = "/usr/share/assimp/models/glTF2";

#define REQUIRE_ASSIMP_MODELS()                                  \
  if (!std::filesystem::exists(::frameless::test_util::kModels)) \
  GTEST_SKIP() << "assimp-testmodels is not installed (apt-get install assimp-testmodels)"

// A one-line error naming the file.
inline void expect_one_line_error(const Result<ModelData>& r, const std::string& name) {
  ASSERT_FALSE(r.ok()) << name << " loaded";
  const std::string& msg = r.error().message;
  EXPECT_EQ(msg.find('\n'), std::string::npos) << msg;
  EXPECT_NE(msg.find(name), std::string::npos) << msg;
}

inline std::string base64(const std::string& in) {
  static const char* k = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
  std::string out;
  for (size_t i = 0; i < in.size(); i += 3) {
    uint32_t v = uint32_t(uint8_t(in[i])) << 16;
    if (i + 1 < in.size()) v |= uint32_t(uint8_t(in[i + 1])) << 8;
    if (i + 2 < in.size()) v |= uint32_t(uint8_t(in[i + 2]));
    out += k[v >> 18 & 63];
    out += k[v >> 12 & 63];
    out += i + 1 < in.size() ? k[v >> 6 & 63] : '=';
    out += i + 2 < in.size() ? k[v & 63] : '=';
  }
  return out;
}

template <class T>
inline void put(std::string& b, T v) {
  b.append(reinterpret_cast<const char*>(&v), sizeof v);
}

// A 2x1 RGBA PNG: opaque red, transparent blue (gltf_instances_test.cpp's leaves: with MASK, half
// of the leaf is cut out).
inline const std::string kPng64 =
    "iVBORw0KGgoAAAANSUhEUgAAAAIAAAABCAYAAAD0In+KAAAADUlEQVR4nGP4z8AARgAO+gL+"
    "9R5MqQAAAABJRU5ErkJggg==";

inline void expect_near(const Vec3& a, const Vec3& b) {
  EXPECT_NEAR(a.x, b.x, 1e-5f);
  EXPECT_NEAR(a.y, b.y, 1e-5f);
  EXPECT_NEAR(a.z, b.z, 1e-5f);
}

}  // namespace test_util
}  // namespace frameless
