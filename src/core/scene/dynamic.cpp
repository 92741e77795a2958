// Dynamic objects: frames at an instant and the flat world state of the motion channel.
#include "core/scene/dynamic.h"

#include <cmath>

#include "core/scene/scene.h"
#include "core/scene/scene_analysis.h"

namespace frameless {

WorldState initial_world(const Scene& scene) {
  WorldState w;
  w.object_position.reserve(scene.dynamic.size());
  for (const DynamicObject& o : scene.dynamic) w.object_position.push_back(o.sphere.center);
  w.lights = scene.lights;
  w.materials.assign(scene.materials.begin(), scene.materials.end());
  return w;
}

size_t world_floats(const Scene& scene) {
  return scene.dynamic.size() * kObjectFloats + scene.lights.size() * kLightFloats +
         scene.materials.size() * kMaterialFloats;
}

void pack_world(const WorldState& w, std::vector<float>& out) {
  out.clear();
  auto put = [&](const Vec3& v) { out.insert(out.end(), {v.x, v.y, v.z}); };
  for (const Vec3& p : w.object_position) put(p);
  for (const Light& l : w.lights) {
    put(l.position);
    put(l.color);
    out.push_back(l.radius);
  }
  for (const MaterialParams& m : w.materials) {
    put(m.kd);
    put(m.ks);
    put(m.kh);
    out.push_back(m.phong_exponent);
    put(m.emission);
  }
}

std::string world_problem(const WorldState& w, const WorldState& shape) {
  if (w.object_position.size() != shape.object_position.size() || w.lights.size() != shape.lights.size() ||
      w.materials.size() != shape.materials.size())
    return "the world does not match the scene (its objects, lights and materials)";
  const auto ok = [](const Vec3& v, bool non_negative) {
    return is_finite(v) && (!non_negative || (v.x >= 0.0f && v.y >= 0.0f && v.z >= 0.0f));
  };
  for (size_t i = 0; i < w.object_position.size(); ++i)
    if (!ok(w.object_position[i], false)) return "object " + std::to_string(i) + ": position must be finite";
  for (size_t i = 0; i < w.lights.size(); ++i) {
    const Light& l = w.lights[i];
    if (!ok(l.position, false) || !ok(l.direction, false)) return "light " + std::to_string(i) + ": position and direction must be finite";
    if (!ok(l.color, true)) return "light " + std::to_string(i) + ": colour must be finite and >= 0";
    if (!(l.radius >= 0.0f) || !std::isfinite(l.radius)) return "light " + std::to_string(i) + ": radius must be finite and >= 0";
  }
  for (size_t i = 0; i < w.materials.size(); ++i) {
    const MaterialParams& m = w.materials[i];
    if (!ok(m.kd, true) || !ok(m.ks, true) || !ok(m.kh, true) || !ok(m.emission, true))
      return "material " + std::to_string(i) + ": colours and emission must be finite and >= 0";
    if (!(m.phong_exponent >= 0.0f) || !std::isfinite(m.phong_exponent))
      return "material " + std::to_string(i) + ": the Phong exponent must be finite and >= 0";
  }
  return "";
}

bool unpack_world(const float* data, size_t n, WorldState& w) {
  const size_t want = w.object_position.size() * kObjectFloats + w.lights.size() * kLightFloats +
                      w.materials.size() * kMaterialFloats;
  if (n != want || (n > 0 && !data)) return false;
  for (size_t i = 0; i < n; ++i)
    if (!std::isfinite(data[i])) return false;
  // Radii and exponents must stay in range too: a negative radius would flip shadow cones.
  const float* d = data + w.object_position.size() * kObjectFloats;
  for (size_t i = 0; i < w.lights.size(); ++i, d += kLightFloats)
    if (d[6] < 0.0f) return false;
  for (size_t i = 0; i < w.materials.size(); ++i, d += kMaterialFloats)
    if (d[9] < 0.0f || d[10] < 0.0f || d[11] < 0.0f || d[12] < 0.0f) return false;  // exponent, emission
  d = data;
  auto get = [&]() {
    const Vec3 v(d[0], d[1], d[2]);
    d += 3;
    return v;
  };
  for (Vec3& p : w.object_position) p = get();
  for (Light& l : w.lights) {
    l.position = get();
    l.color = get();
    l.radius = *d++;
  }
  for (MaterialParams& m : w.materials) {
    m.kd = get();
    m.ks = get();
    m.kh = get();
    m.phong_exponent = *d++;
    m.emission = get();  // a lamp turned up or down while you look
  }
  return true;
}

void advance_frame(const Scene& scene, const WorldState& w, double t, DynamicFrame& frame) {
  const size_t n = std::min(scene.dynamic.size(), frame.spheres.size());
  for (size_t i = 0; i < n; ++i) {
    const DynamicObject& o = scene.dynamic[i];
    const Vec3 base = i < w.object_position.size() ? w.object_position[i] : o.sphere.center;
    frame.spheres[i].center = base + motion_offset(o.motion, t);
  }
  frame.time = t;
}

void evaluate_frame(const Scene& scene, const WorldState& w, double t, DynamicFrame& frame) {
  const size_t n = scene.dynamic.size();
  frame.spheres.resize(n);
  frame.sphere_material.resize(n);
  for (size_t i = 0; i < n; ++i) {
    frame.spheres[i].radius = scene.dynamic[i].sphere.radius;
    frame.sphere_material[i] = scene.dynamic[i].material;
  }
  frame.lights = w.lights.size() == scene.lights.size() ? w.lights : scene.lights;
  if (w.materials.size() == scene.materials.size())
    frame.materials = w.materials;
  else
    frame.materials.assign(scene.materials.begin(), scene.materials.end());
  frame.shade_path = frame_shade_path(scene, frame);
  advance_frame(scene, w, t, frame);
}

}  // namespace frameless
