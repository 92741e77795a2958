#include "display/camera_path.h"

#include <algorithm>
#include <cmath>
#include <fstream>
#include <sstream>

#include <glm/gtc/matrix_transform.hpp>
#include <glm/gtc/quaternion.hpp>
#include <nlohmann/json.hpp>

namespace frameless {
namespace {

// A keyframe split into the quantities that are interpolated.
struct Pose {
  Vec3 eye;
  glm::quat orientation;  // maps camera axes (x right, y up, -z forward) to world
  float distance;         // eye to look-at point
  float fov;
};

Pose to_pose(const Camera& c) {
  const CameraBasis b = make_camera_basis(c, 1, 1);
  Pose p;
  p.eye = c.eye;
  p.orientation = glm::normalize(glm::quat_cast(glm::mat3(b.u, b.v, -b.w)));
  p.distance = glm::length(c.look - c.eye);
  p.fov = c.fov_deg;
  return p;
}

Camera to_camera(const Pose& p) {
  Camera c;
  c.eye = p.eye;
  c.look = p.eye + p.orientation * Vec3(0.0f, 0.0f, -1.0f) * p.distance;
  c.up = p.orientation * Vec3(0.0f, 1.0f, 0.0f);
  c.fov_deg = p.fov;
  return c;
}

// Cubic Hermite between p1 (at s=0) and p2 (s=1) with velocities m1, m2 over a segment of length h.
Vec3 hermite(const Vec3& p1, const Vec3& p2, const Vec3& m1, const Vec3& m2, float h, float s) {
  const float s2 = s * s, s3 = s2 * s;
  return (2 * s3 - 3 * s2 + 1) * p1 + (s3 - 2 * s2 + s) * h * m1 + (-2 * s3 + 3 * s2) * p2 +
         (s3 - s2) * h * m2;
}

Camera rotate_about_up(const Camera& c, double degrees) {
  const Vec3 up = glm::normalize(c.up);
  const float a = float(degrees * kPi / 180.0);
  const Vec3 v = c.eye - c.look;
  const Vec3 r = v * std::cos(a) + glm::cross(up, v) * std::sin(a) +
                 up * glm::dot(up, v) * (1.0f - std::cos(a));
  Camera out = c;
  out.eye = c.look + r;
  return out;
}

bool read_vec3(const nlohmann::json& j, Vec3& out) {
  if (!j.is_array() || j.size() != 3) return false;
  for (int i = 0; i < 3; ++i) {
    if (!j[i].is_number()) return false;
    out[i] = j[i].get<float>();
  }
  return is_finite(out);
}

}  // namespace

Camera evaluate_camera_path(const CameraPath& path, double t, const Camera& fallback) {
  const auto& k = path.keyframes;
  if (k.empty()) return fallback;
  if (!(t > k.front().time)) return k.front().camera;
  if (t >= k.back().time) return k.back().camera;
  // Segment i: the last keyframe at or before t.
  const auto it = std::upper_bound(k.begin(), k.end(), t,
                                   [](double v, const CameraKeyframe& f) { return v < f.time; });
  const size_t i = size_t(it - k.begin()) - 1;
  const CameraKeyframe& a = k[i];
  const CameraKeyframe& b = k[i + 1];
  if (b.cut) return a.camera;  // hold until the jump
  const double h = b.time - a.time;
  if (!(h > 0.0)) return b.camera;
  const float s = float((t - a.time) / h);
  const Pose pa = to_pose(a.camera), pb = to_pose(b.camera);
  // Velocities from the neighbours (Catmull-Rom); the path starts, ends or cuts where one is missing.
  const bool has_prev = i > 0 && !a.cut && a.time > k[i - 1].time;
  const bool has_next = i + 2 < k.size() && !k[i + 2].cut && k[i + 2].time > b.time;
  const Vec3 chord = (pb.eye - pa.eye) / float(h);
  Vec3 m1 = has_prev ? (pb.eye - k[i - 1].camera.eye) / float(b.time - k[i - 1].time) : chord;
  Vec3 m2 = has_next ? (k[i + 2].camera.eye - pa.eye) / float(k[i + 2].time - a.time) : chord;
  // At an open end, the parabola through the segment that matches the inner velocity.
  if (!has_prev && has_next) m1 = 2.0f * chord - m2;
  if (has_prev && !has_next) m2 = 2.0f * chord - m1;
  Pose p;
  p.eye = hermite(pa.eye, pb.eye, m1, m2, float(h), s);
  glm::quat qb = pb.orientation;
  if (glm::dot(pa.orientation, qb) < 0.0f) qb = -qb;  // shortest arc
  p.orientation = glm::normalize(glm::slerp(pa.orientation, qb, s));
  p.distance = pa.distance + (pb.distance - pa.distance) * s;
  p.fov = pa.fov + (pb.fov - pa.fov) * s;
  return to_camera(p);
}

CameraPath make_shorthand_path(const Camera& start, const PathShorthand& sh, double duration) {
  CameraPath path;
  duration = std::max(duration, 0.0);
  auto pose_at = [&](double t, bool after_cut) {
    const double f = duration > 0.0 ? t / duration : 0.0;
    Camera c = start;
    const Vec3 offset = c.eye - c.look;
    c.eye = c.look + offset * float(std::pow(sh.dolly_factor, f));
    return rotate_about_up(c, sh.orbit_deg * f + (after_cut ? sh.cut_orbit_deg : 0.0));
  };
  // Keyframes every 10 degrees of orbit keep the spline within 0.02% of the circle.
  const int n = std::max(1, int(std::ceil(std::abs(sh.orbit_deg) / 10.0)));
  const bool has_cut = sh.cut_at >= 0.0 && sh.cut_at <= duration;
  bool cut_done = false;
  for (int s = 0; s <= n; ++s) {
    const double t = duration * s / n;
    if (has_cut && !cut_done && sh.cut_at <= t) {
      // The view just before the jump, then the jump itself at the same instant.
      if (sh.cut_at > 0.0) path.keyframes.push_back({sh.cut_at, pose_at(sh.cut_at, false)});
      path.keyframes.push_back({sh.cut_at, pose_at(sh.cut_at, true), true});
      cut_done = true;
      if (t == sh.cut_at) continue;
    }
    path.keyframes.push_back({t, pose_at(t, cut_done)});
  }
  return path;
}

Result<CameraPath> parse_camera_path(const std::string& text, const std::string& file) {
  nlohmann::json j;
  try {
    j = nlohmann::json::parse(text);
  } catch (const nlohmann::json::parse_error& e) {
    return Error{file + ": " + e.what()};
  }
  if (!j.is_object() || !j.contains("keyframes") || !j["keyframes"].is_array())
    return Error{file + ": keyframes: missing (expected an array of keyframes)"};
  CameraPath path;
  const auto& arr = j["keyframes"];
  for (size_t i = 0; i < arr.size(); ++i) {
    const auto& k = arr[i];
    const std::string where = file + ": keyframes[" + std::to_string(i) + "].";
    if (!k.is_object()) return Error{where.substr(0, where.size() - 1) + ": expected an object"};
    CameraKeyframe f;
    if (!k.contains("t") || !k["t"].is_number() || !std::isfinite(k["t"].get<double>()) ||
        k["t"].get<double>() < 0.0)
      return Error{where + "t: expected a time in seconds >= 0"};
    f.time = k["t"].get<double>();
    if (!path.keyframes.empty() && f.time < path.keyframes.back().time)
      return Error{where + "t: times must not decrease"};
    if (!k.contains("eye") || !read_vec3(k["eye"], f.camera.eye))
      return Error{where + "eye: expected [x, y, z] (finite numbers)"};
    if (!k.contains("look") || !read_vec3(k["look"], f.camera.look))
      return Error{where + "look: expected [x, y, z] (finite numbers)"};
    if (k.contains("up") && !read_vec3(k["up"], f.camera.up))
      return Error{where + "up: expected [x, y, z] (finite numbers)"};
    if (k.contains("fov")) {
      if (!k["fov"].is_number()) return Error{where + "fov: expected degrees in (0, 180)"};
      f.camera.fov_deg = k["fov"].get<float>();
    }
    if (k.contains("cut")) {
      if (!k["cut"].is_boolean()) return Error{where + "cut: expected true or false"};
      f.cut = k["cut"].get<bool>();
    }
    if (!camera_is_valid(f.camera))
      return Error{where.substr(0, where.size() - 1) +
                   ": invalid camera (eye == look, up parallel to the view, or fov outside (0, 180))"};
    path.keyframes.push_back(f);
  }
  if (path.keyframes.empty()) return Error{file + ": keyframes: empty (need at least one)"};
  return path;
}

Result<CameraPath> load_camera_path(const std::string& file) {
  std::ifstream in(file, std::ios::binary);
  if (!in) return Error{file + ": cannot open camera path file"};
  std::stringstream ss;
  ss << in.rdbuf();
  return parse_camera_path(ss.str(), file);
}

std::string camera_path_to_json(const CameraPath& path, const std::string& source) {
  nlohmann::json arr = nlohmann::json::array();
  for (const CameraKeyframe& k : path.keyframes) {
    const Camera& c = k.camera;
    nlohmann::json j = {{"t", k.time},
                        {"eye", {c.eye.x, c.eye.y, c.eye.z}},
                        {"look", {c.look.x, c.look.y, c.look.z}},
                        {"up", {c.up.x, c.up.y, c.up.z}},
                        {"fov", c.fov_deg}};
    if (k.cut) j["cut"] = true;
    arr.push_back(j);
  }
  nlohmann::json doc = {{"source", source}, {"keyframes", arr}};
  return doc.dump(1) + "\n";
}

std::vector<float> world_to_camera_matrix(const Camera& camera) {
  const glm::mat4 view = glm::lookAt(camera.eye, camera.look, camera.up);
  std::vector<float> m(16);
  // glm stores columns; row-vector convention wants the transpose, i.e. glm's [col][row] read as [row][col].
  for (int r = 0; r < 4; ++r)
    for (int c = 0; c < 4; ++c) m[size_t(r * 4 + c)] = view[r][c];
  return m;
}

}  // namespace frameless
