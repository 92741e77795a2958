// Shared helpers of the JSON scene reader (scene_json*.cpp): typed field access whose errors
// name the JSON field path. Loading thread only; a Failure never leaves the reader.
#pragma once
#include <cmath>
#include <cstdint>
#include <string>

#include <glm/mat4x4.hpp>
#include <nlohmann/json.hpp>

#include "core/base/types.h"
#include "core/geometry/geometry.h"

namespace frameless::scene_json {

// ordered_json keeps materials (and so material ids) in file order.
using json = nlohmann::ordered_json;

constexpr int kMaxImageSide = 16384;

// Thrown inside this file only, caught by parse_scene_json and turned into an Error.
struct Failure {
  std::string field;
  std::string what;
};

[[noreturn]] inline void fail(const std::string& field, const std::string& what) { throw Failure{field, what}; }

inline std::string type_name(const json& j) { return j.type_name(); }

inline const json& require_object(const json& j, const std::string& field) {
  if (!j.is_object()) fail(field, "expected an object, got " + type_name(j));
  return j;
}

// Rejects keys not in `allowed`: catches typos such as "radus".
inline void check_keys(const json& j, const std::string& field, std::initializer_list<const char*> allowed) {
  for (auto it = j.begin(); it != j.end(); ++it) {
    bool ok = false;
    for (const char* a : allowed) ok |= it.key() == a;
    if (!ok) {
      std::string list;
      for (const char* a : allowed) list += std::string(list.empty() ? "" : ", ") + a;
      fail(field.empty() ? it.key() : field + "." + it.key(), "unknown key (expected one of: " + list + ")");
    }
  }
}

inline std::string sub(const std::string& field, const char* key) {
  return field.empty() ? std::string(key) : field + "." + key;
}

inline double get_number(const json& j, const std::string& field) {
  if (!j.is_number()) fail(field, "expected a number, got " + type_name(j));
  const double v = j.get<double>();
  if (!std::isfinite(v) || std::fabs(v) > 3.0e38) fail(field, "number is not finite");
  return v;
}

inline float get_float(const json& j, const std::string& field, double lo, double hi, const char* range) {
  const double v = get_number(j, field);
  if (v < lo || v > hi) fail(field, std::string("must be ") + range + " (got " + j.dump() + ")");
  return float(v);
}

inline int64_t get_int(const json& j, const std::string& field, int64_t lo, int64_t hi) {
  if (!j.is_number_integer()) fail(field, "expected an integer, got " + (j.is_number() ? j.dump() : type_name(j)));
  if (j.is_number_unsigned() && j.get<uint64_t>() > uint64_t(INT64_MAX))
    fail(field, "must be in " + std::to_string(lo) + ".." + std::to_string(hi) + " (got " + j.dump() + ")");
  const int64_t v = j.get<int64_t>();
  if (v < lo || v > hi)
    fail(field, "must be in " + std::to_string(lo) + ".." + std::to_string(hi) + " (got " + j.dump() + ")");
  return v;
}

inline Vec3 get_vec3(const json& j, const std::string& field) {
  if (!j.is_array() || j.size() != 3) fail(field, "expected an array of 3 numbers");
  return Vec3(float(get_number(j[0], field + "[0]")), float(get_number(j[1], field + "[1]")),
              float(get_number(j[2], field + "[2]")));
}

// A colour: [r, g, b] or one grey number; each component >= 0.
inline Vec3 get_color(const json& j, const std::string& field) {
  const Vec3 c = j.is_number() ? Vec3(float(get_number(j, field))) : get_vec3(j, field);
  if (c.x < 0.0f || c.y < 0.0f || c.z < 0.0f) fail(field, "colour components must be >= 0");
  return c;
}

inline Vec3 get_unit(const json& j, const std::string& field) {
  const Vec3 v = get_vec3(j, field);
  const float len = glm::length(v);
  if (!(len > 1e-20f) || !std::isfinite(len)) fail(field, "must be a non-zero vector");
  return v / len;
}

inline std::string get_string(const json& j, const std::string& field) {
  if (!j.is_string()) fail(field, "expected a string, got " + type_name(j));
  return j.get<std::string>();
}

inline const json& need(const json& o, const std::string& f, const char* key) {
  if (!o.contains(key)) fail(sub(f, key), "missing");
  return o[key];
}


inline bool get_bool(const json& j, const std::string& field) {
  if (!j.is_boolean()) fail(field, "expected true or false, got " + type_name(j));
  return j.get<bool>();
}

// An affine transform: 16 numbers row-major, or {translate, rotate, scale} (M = T R S).
glm::mat4 parse_transform(const json& j, const std::string& f);
inline Affine to_affine(const glm::mat4& m) { return Affine{glm::mat3(m), Vec3(m[3])}; }

}  // namespace frameless::scene_json
