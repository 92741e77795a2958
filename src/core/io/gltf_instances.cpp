// glTF nodes: the world transform of every node the default scene reaches, which mesh references
// become instances (a mesh two or more nodes place is stored once, core/accel/instance.h), and the
// cameras and KHR_lights_punctual lights nodes carry.
#include <cmath>

#include <glm/gtc/matrix_transform.hpp>
#include <glm/gtc/quaternion.hpp>
#include <glm/gtc/type_ptr.hpp>

#include "core/accel/instance.h"
#include "core/io/gltf_internal.h"
#include "core/scene/scene_build.h"

namespace frameless::gltf {
namespace {

using tinygltf::Model;

// Placements by instances per model: each costs an Instance and a box in the top-level BVH.
constexpr size_t kMaxInstances = size_t(1) << 20;

Result<glm::dmat4> local_matrix(const Model& m, int n, const std::string& path) {
  const tinygltf::Node& node = m.nodes[size_t(n)];
  const std::string where = "node " + str(n) + ": ";
  if (!node.matrix.empty()) {
    if (node.matrix.size() != 16) return fail(path, where + "matrix needs 16 numbers");
    return glm::make_mat4(node.matrix.data());  // column-major in glTF and GLM
  }
  glm::dmat4 t(1.0);
  if (!node.translation.empty()) {
    if (node.translation.size() != 3) return fail(path, where + "translation needs 3 numbers");
    t = glm::translate(t, glm::make_vec3(node.translation.data()));
  }
  if (!node.rotation.empty()) {
    if (node.rotation.size() != 4) return fail(path, where + "rotation needs 4 numbers");
    const auto& r = node.rotation;  // x, y, z, w
    glm::dquat q(r[3], r[0], r[1], r[2]);
    const double len = glm::length(q);
    if (!(len > 1e-12) || !std::isfinite(len))
      return fail(path, where + "rotation is not a unit quaternion");
    t *= glm::mat4_cast(q / len);
  }
  if (!node.scale.empty()) {
    if (node.scale.size() != 3) return fail(path, where + "scale needs 3 numbers");
    t = glm::scale(t, glm::make_vec3(node.scale.data()));
  }
  return t;
}

bool finite_matrix(const glm::dmat4& m) {
  for (int c = 0; c < 4; ++c)
    for (int r = 0; r < 4; ++r)
      if (!std::isfinite(m[c][r]) || std::abs(m[c][r]) > 1e30) return false;
  return true;
}

// Whether an Instance can be made with this transform (the float matrix placements carry).
bool invertible(const glm::dmat4& world) {
  const glm::mat4 w(world);
  Affine a, inverse;
  a.m = glm::mat3(w);
  a.t = Vec3(w[3]);
  return invert(a, inverse);
}

// The default scene, else scene 0, else (no scenes at all) every node that is no node's child.
Result<std::vector<int>> root_nodes(const Model& m, const std::string& path) {
  if (m.defaultScene >= 0 && !m.scenes.empty()) {
    if (size_t(m.defaultScene) >= m.scenes.size())
      return fail(path, "scene " + str(m.defaultScene) + " out of range (" + str(m.scenes.size()) +
                            " scenes)");
    return m.scenes[size_t(m.defaultScene)].nodes;
  }
  if (!m.scenes.empty()) return m.scenes[0].nodes;
  std::vector<uint8_t> is_child(m.nodes.size(), 0);
  for (const tinygltf::Node& node : m.nodes)
    for (int c : node.children)
      if (c >= 0 && size_t(c) < m.nodes.size()) is_child[size_t(c)] = 1;
  std::vector<int> roots;
  for (size_t i = 0; i < m.nodes.size(); ++i)
    if (!is_child[i]) roots.push_back(int(i));
  return roots;
}

// Marks the visits whose mesh two or more visits with invertible transforms place.
std::optional<Error> mark_instances(const Model& m, std::vector<NodeVisit>& visits,
                                    const std::string& path) {
  std::vector<uint32_t> uses(m.meshes.size(), 0);
  for (const NodeVisit& v : visits) {
    const int mesh = m.nodes[size_t(v.node)].mesh;
    if (mesh >= 0 && v.invertible) ++uses[size_t(mesh)];
  }
  size_t instances = 0;
  for (NodeVisit& v : visits) {
    const int mesh = m.nodes[size_t(v.node)].mesh;
    v.instance = mesh >= 0 && v.invertible && uses[size_t(mesh)] >= 2;
    instances += v.instance ? 1 : 0;
  }
  if (instances > kMaxInstances)
    return fail(path, "more than " + str(kMaxInstances) + " mesh instances");
  return std::nullopt;
}

Vec3 dir(const glm::dmat4& m, double x, double y, double z) {
  return Vec3(glm::normalize(glm::dmat3(m) * glm::dvec3(x, y, z)));
}

}  // namespace

Result<std::vector<NodeVisit>> walk_nodes(const Model& m, const std::string& path) {
  auto roots = root_nodes(m, path);
  if (!roots) return roots.error();
  // Depth-first with an explicit stack (no recursion to overflow); a node met twice means a cycle
  // or a node with two parents, which glTF forbids.
  std::vector<NodeVisit> visits;
  std::vector<uint8_t> seen(m.nodes.size(), 0);
  std::vector<std::pair<int, glm::dmat4>> stack;
  for (auto it = roots->rbegin(); it != roots->rend(); ++it)
    stack.emplace_back(*it, glm::dmat4(1.0));
  while (!stack.empty()) {
    const auto [n, parent] = stack.back();
    stack.pop_back();
    if (n < 0 || size_t(n) >= m.nodes.size())
      return fail(path, "node " + str(n) + " out of range (" + str(m.nodes.size()) + " nodes)");
    if (seen[size_t(n)])
      return fail(path, "node " + str(n) +
                            ": reached twice (a cycle in the node hierarchy, or two parents)");
    seen[size_t(n)] = 1;
    const tinygltf::Node& node = m.nodes[size_t(n)];
    auto local = local_matrix(m, n, path);
    if (!local) return local.error();
    const glm::dmat4 world = parent * *local;
    if (!finite_matrix(world)) return fail(path, "node " + str(n) + ": transform is not finite");
    if (node.mesh >= 0 && size_t(node.mesh) >= m.meshes.size())
      return fail(path,
                  "mesh " + str(node.mesh) + " out of range (" + str(m.meshes.size()) + " meshes)");
    visits.push_back({n, world, node.mesh >= 0 && invertible(world), false});
    for (auto it = node.children.rbegin(); it != node.children.rend(); ++it)
      stack.emplace_back(*it, world);
  }
  if (auto e = mark_instances(m, visits, path)) return *e;
  return visits;
}

std::optional<Error> add_camera(const Model& m, const std::string& path, int n, int index,
                                const glm::dmat4& world, ModelData& out) {
  if (size_t(index) >= m.cameras.size())
    return fail(path, "node " + str(n) + ": camera " + str(index) + " out of range (" +
                          str(m.cameras.size()) + " cameras)");
  const tinygltf::Camera& c = m.cameras[size_t(index)];
  if (c.type != "perspective") {
    out.warnings.push_back("camera " + str(index) + ": " + (c.type.empty() ? "untyped" : c.type) +
                           " cameras are not supported (skipped)");
    return std::nullopt;
  }
  // The camera looks down its node's -Z with +Y up.
  Camera cam;
  cam.eye = Vec3(world * glm::dvec4(0.0, 0.0, 0.0, 1.0));
  cam.look = cam.eye + dir(world, 0.0, 0.0, -1.0);
  cam.up = dir(world, 0.0, 1.0, 0.0);
  cam.fov_deg = float(glm::degrees(c.perspective.yfov));
  if (!camera_is_valid(cam)) {
    out.warnings.push_back("camera " + str(index) + ": invalid yfov or transform (skipped)");
    return std::nullopt;
  }
  out.cameras.push_back(cam);
  return std::nullopt;
}

// KHR_lights_punctual carries physical units: point and spot intensity in candela (lm/sr, falling
// off as 1/d^2), directional in lux. Parker's lights have no falloff, so each light's illuminance
// is taken at the model's bounding-box centre (point: I/d^2, directional: I) and all lights are
// scaled together so the brightest gets illuminance 1: colour = glTF colour * E / E_max. Relative
// brightness is kept; lights of intensity 0 are dropped; spot cones and range are ignored.
void add_lights(const Model& m, const std::vector<std::pair<int, glm::dmat4>>& lights,
                ModelData& out) {
  Vec3 lo, hi;
  mesh_bounds(out.mesh, glm::mat4(1.0f), lo, hi);  // flat triangles and placed shared meshes
  const Vec3 centre = 0.5f * (lo + hi);
  const double min_dist = std::max(1e-3 * double(glm::length(hi - lo)), 1e-6);
  std::vector<std::pair<Light, double>> lit;
  double e_max = 0.0;
  for (const auto& [index, world] : lights) {
    const tinygltf::Light& g = m.lights[size_t(index)];
    const std::string where = "light " + str(index) + ": ";
    Light l;
    if (g.color.size() == 3)
      l.color =
          glm::clamp(Vec3(float(g.color[0]), float(g.color[1]), float(g.color[2])), 0.0f, 1.0f);
    else if (!g.color.empty())
      out.warnings.push_back(where + "color needs 3 numbers (white used)");
    double e = std::isfinite(g.intensity) ? std::max(g.intensity, 0.0) : 0.0;
    if (g.type == "directional") {
      l.kind = LightKind::kDirectional;
      l.direction = dir(world, 0.0, 0.0, -1.0);
    } else if (g.type == "point" || g.type == "spot") {
      l.position = Vec3(world * glm::dvec4(0.0, 0.0, 0.0, 1.0));
      e /= std::pow(std::max(double(glm::length(l.position - centre)), min_dist), 2.0);
      if (g.type == "spot")
        out.warnings.push_back("spot light " + str(index) + " treated as a point light");
    } else {
      out.warnings.push_back(where + "type '" + g.type + "' is not supported (skipped)");
      continue;
    }
    if (!(e > 0.0) || !std::isfinite(e) || !is_finite(l.position) || !is_finite(l.direction))
      continue;
    e_max = std::max(e_max, e);
    lit.emplace_back(l, e);
  }
  for (auto& [l, e] : lit) {
    l.color *= float(e / e_max);
    out.lights.push_back(l);
  }
}

}  // namespace frameless::gltf
