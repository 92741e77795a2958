// glTF 2.0 input (.gltf with external or data: buffers, .glb by content) through Debian's
// tinygltf: the default scene's node tree and its transforms, triangle primitives (strips and
// fans converted), materials (gltf_material.cpp), perspective cameras and KHR_lights_punctual
// lights. tinygltf checks no index or byte range, so every accessor is bounds-checked here
// before it is read; gltf_check.cpp covers what tinygltf would misread or let through.
#include <cmath>
#include <cstring>

#include <glm/gtc/matrix_transform.hpp>
#include <glm/gtc/quaternion.hpp>
#include <glm/gtc/type_ptr.hpp>

#include "core/gltf_internal.h"
#include "core/scene_build.h"

namespace frameless {
namespace {

using gltf::fail;
using tinygltf::Model;

// Vertices and triangles per model after instancing: a small file cannot ask for unbounded memory.
constexpr size_t kMaxElements = size_t(1) << 27;

std::string str(long long i) { return std::to_string(i); }

// An accessor whose every element lies inside its buffer.
struct View {
  const unsigned char* data = nullptr;
  size_t stride = 0;
  size_t count = 0;
  int ctype = 0;
  int ncomp = 0;
  bool normalized = false;

  template <class T>
  T get(size_t i, int c) const {
    T v;
    std::memcpy(&v, data + i * stride + size_t(c) * sizeof(T), sizeof(T));
    return v;
  }
  // Component c of element i as a float: float, or unsigned byte/short scaled to [0, 1].
  float unit(size_t i, int c) const {
    if (ctype == TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE) return float(get<uint8_t>(i, c)) / 255.0f;
    if (ctype == TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT)
      return float(get<uint16_t>(i, c)) / 65535.0f;
    return get<float>(i, c);
  }
};

size_t component_size(int ctype) {
  switch (ctype) {
    case TINYGLTF_COMPONENT_TYPE_BYTE:
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE:
      return 1;
    case TINYGLTF_COMPONENT_TYPE_SHORT:
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT:
      return 2;
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT:
    case TINYGLTF_COMPONENT_TYPE_FLOAT:
      return 4;
    default:
      return 0;
  }
}

int component_count(int type) {
  switch (type) {
    case TINYGLTF_TYPE_SCALAR:
      return 1;
    case TINYGLTF_TYPE_VEC2:
      return 2;
    case TINYGLTF_TYPE_VEC3:
      return 3;
    case TINYGLTF_TYPE_VEC4:
      return 4;
    default:
      return 0;
  }
}

Result<View> accessor_view(const Model& m, int index, const std::string& path) {
  if (index < 0 || size_t(index) >= m.accessors.size())
    return fail(path, "accessor " + str(index) + " out of range (" + str(m.accessors.size()) +
                          " accessors)");
  const tinygltf::Accessor& a = m.accessors[size_t(index)];
  auto bad = [&](const std::string& what) {
    return fail(path, "accessor " + str(index) + ": " + what);
  };
  if (a.sparse.isSparse) return bad("sparse accessors are not supported");
  if (a.bufferView < 0) return bad("no bufferView (all-zero accessors are not supported)");
  if (size_t(a.bufferView) >= m.bufferViews.size())
    return bad("bufferView " + str(a.bufferView) + " out of range");
  const tinygltf::BufferView& bv = m.bufferViews[size_t(a.bufferView)];
  if (bv.buffer < 0 || size_t(bv.buffer) >= m.buffers.size())
    return bad("bufferView " + str(a.bufferView) + ": buffer " + str(bv.buffer) + " out of range");
  const size_t buffer_size = m.buffers[size_t(bv.buffer)].data.size();
  if (bv.byteOffset > buffer_size || bv.byteLength > buffer_size - bv.byteOffset)
    return bad("bufferView " + str(a.bufferView) + " runs past the end of buffer " +
               str(bv.buffer));
  View v;
  v.ctype = a.componentType;
  v.ncomp = component_count(a.type);
  v.count = a.count;
  v.normalized = a.normalized;
  const size_t elem = component_size(a.componentType) * size_t(v.ncomp);
  if (elem == 0) return bad("unsupported componentType or type");
  v.stride = bv.byteStride != 0 ? bv.byteStride : elem;
  if (v.stride < elem || v.stride > 252)
    return bad("byteStride " + str(bv.byteStride) + " does not fit " + str(elem) +
               "-byte elements");
  if (v.count == 0) return v;
  // byteOffset + stride * (count - 1) + elem <= byteLength, without overflow.
  if (a.byteOffset > bv.byteLength || bv.byteLength - a.byteOffset < elem ||
      v.count - 1 > (bv.byteLength - a.byteOffset - elem) / v.stride)
    return bad(str(v.count) + " elements run past the end of bufferView " + str(a.bufferView));
  v.data = m.buffers[size_t(bv.buffer)].data.data() + bv.byteOffset + a.byteOffset;
  return v;
}

bool finite_matrix(const glm::dmat4& m) {
  for (int c = 0; c < 4; ++c)
    for (int r = 0; r < 4; ++r)
      if (!std::isfinite(m[c][r]) || std::abs(m[c][r]) > 1e30) return false;
  return true;
}

Vec3 dir(const glm::dmat4& m, double x, double y, double z) {
  return Vec3(glm::normalize(glm::dmat3(m) * glm::dvec3(x, y, z)));
}

class Builder {
 public:
  Builder(const Model& m, const std::string& path, gltf::MaterialMap& materials, ModelData& out)
      : m_(m), path_(path), materials_(materials), out_(out), mesh_(out.mesh) {}

  std::optional<Error> run();

 private:
  Result<glm::dmat4> local_matrix(int n);
  std::optional<Error> add_mesh(int index, const glm::dmat4& world);
  std::optional<Error> add_primitive(const tinygltf::Primitive& p, const glm::dmat4& world);
  std::optional<Error> add_camera(int n, int index, const glm::dmat4& world);
  void finish_normals();
  void add_lights();
  Error err(const std::string& what) const { return fail(path_, what); }
  void warn_once(const std::string& w) {
    if (std::find(out_.warnings.begin(), out_.warnings.end(), w) == out_.warnings.end())
      out_.warnings.push_back(w);
  }

  const Model& m_;
  const std::string& path_;
  gltf::MaterialMap& materials_;
  ModelData& out_;
  MeshData& mesh_;
  std::vector<uint8_t> has_normal_;
  bool any_normal_ = false, any_uv_ = false;
  size_t skipped_primitives_ = 0;
  std::vector<std::pair<int, glm::dmat4>> lights_;      // KHR_lights_punctual index, node transform
  std::map<std::tuple<int, int, int>, size_t> shared_;  // vertex accessors -> first vertex
};

Result<glm::dmat4> Builder::local_matrix(int n) {
  const tinygltf::Node& node = m_.nodes[size_t(n)];
  const std::string where = "node " + str(n) + ": ";
  if (!node.matrix.empty()) {
    if (node.matrix.size() != 16) return err(where + "matrix needs 16 numbers");
    return glm::make_mat4(node.matrix.data());  // column-major in glTF and GLM
  }
  glm::dmat4 t(1.0);
  if (!node.translation.empty()) {
    if (node.translation.size() != 3) return err(where + "translation needs 3 numbers");
    t = glm::translate(t, glm::make_vec3(node.translation.data()));
  }
  if (!node.rotation.empty()) {
    if (node.rotation.size() != 4) return err(where + "rotation needs 4 numbers");
    const auto& r = node.rotation;  // x, y, z, w
    glm::dquat q(r[3], r[0], r[1], r[2]);
    const double len = glm::length(q);
    if (!(len > 1e-12) || !std::isfinite(len))
      return err(where + "rotation is not a unit quaternion");
    t *= glm::mat4_cast(q / len);
  }
  if (!node.scale.empty()) {
    if (node.scale.size() != 3) return err(where + "scale needs 3 numbers");
    t = glm::scale(t, glm::make_vec3(node.scale.data()));
  }
  return t;
}

std::optional<Error> Builder::run() {
  // The default scene, else scene 0, else (no scenes at all) every node that is no node's child.
  std::vector<int> roots;
  if (m_.defaultScene >= 0 && !m_.scenes.empty()) {
    if (size_t(m_.defaultScene) >= m_.scenes.size())
      return err("scene " + str(m_.defaultScene) + " out of range (" + str(m_.scenes.size()) +
                 " scenes)");
    roots = m_.scenes[size_t(m_.defaultScene)].nodes;
  } else if (!m_.scenes.empty()) {
    roots = m_.scenes[0].nodes;
  } else {
    std::vector<uint8_t> is_child(m_.nodes.size(), 0);
    for (const tinygltf::Node& node : m_.nodes)
      for (int c : node.children)
        if (c >= 0 && size_t(c) < m_.nodes.size()) is_child[size_t(c)] = 1;
    for (size_t i = 0; i < m_.nodes.size(); ++i)
      if (!is_child[i]) roots.push_back(int(i));
  }
  // Depth-first with an explicit stack (no recursion to overflow); a node met twice means a cycle
  // or a node with two parents, which glTF forbids.
  std::vector<uint8_t> seen(m_.nodes.size(), 0);
  std::vector<std::pair<int, glm::dmat4>> stack;
  for (auto it = roots.rbegin(); it != roots.rend(); ++it) stack.emplace_back(*it, glm::dmat4(1.0));
  while (!stack.empty()) {
    const auto [n, parent] = stack.back();
    stack.pop_back();
    if (n < 0 || size_t(n) >= m_.nodes.size())
      return err("node " + str(n) + " out of range (" + str(m_.nodes.size()) + " nodes)");
    if (seen[size_t(n)])
      return err("node " + str(n) +
                 ": reached twice (a cycle in the node hierarchy, or two parents)");
    seen[size_t(n)] = 1;
    const tinygltf::Node& node = m_.nodes[size_t(n)];
    auto local = local_matrix(n);
    if (!local) return local.error();
    const glm::dmat4 world = parent * *local;
    if (!finite_matrix(world)) return err("node " + str(n) + ": transform is not finite");
    if (node.skin >= 0) warn_once("skins are ignored (meshes are shown in their bind pose)");
    if (node.mesh >= 0)
      if (auto e = add_mesh(node.mesh, world)) return e;
    if (node.camera >= 0)
      if (auto e = add_camera(n, node.camera, world)) return e;
    const auto ext = node.extensions.find("KHR_lights_punctual");
    if (ext != node.extensions.end() && ext->second.Has("light")) {
      const tinygltf::Value& l = ext->second.Get("light");
      if (!l.IsInt() || l.GetNumberAsInt() < 0 || size_t(l.GetNumberAsInt()) >= m_.lights.size())
        return err("node " + str(n) + ": light out of range (" + str(m_.lights.size()) +
                   " lights)");
      lights_.emplace_back(l.GetNumberAsInt(), world);
    }
    for (auto it = node.children.rbegin(); it != node.children.rend(); ++it)
      stack.emplace_back(*it, world);
  }
  if (skipped_primitives_ > 0)
    out_.warnings.push_back(str(skipped_primitives_) +
                            " point/line primitive(s) skipped: only triangles are rendered");
  if (mesh_.triangles.empty()) return err("no triangles in the scene");
  finish_normals();
  if (!any_uv_) mesh_.uvs.clear();
  add_lights();
  return std::nullopt;
}

std::optional<Error> Builder::add_mesh(int index, const glm::dmat4& world) {
  if (size_t(index) >= m_.meshes.size())
    return err("mesh " + str(index) + " out of range (" + str(m_.meshes.size()) + " meshes)");
  shared_.clear();
  for (const tinygltf::Primitive& p : m_.meshes[size_t(index)].primitives)
    if (auto e = add_primitive(p, world)) return e;
  return std::nullopt;
}

std::optional<Error> Builder::add_primitive(const tinygltf::Primitive& p, const glm::dmat4& world) {
  const int mode = p.mode < 0 ? TINYGLTF_MODE_TRIANGLES : p.mode;
  if (mode < TINYGLTF_MODE_TRIANGLES) {
    ++skipped_primitives_;
    return std::nullopt;
  }
  if (mode > TINYGLTF_MODE_TRIANGLE_FAN) return err("primitive mode " + str(mode) + " is unknown");
  if (!p.targets.empty()) warn_once("morph targets are ignored");
  const auto pos_it = p.attributes.find("POSITION");
  if (pos_it == p.attributes.end()) return err("a primitive has no POSITION attribute");
  auto pos = accessor_view(m_, pos_it->second, path_);
  if (!pos) return pos.error();
  const std::string where = "accessor " + str(pos_it->second) + ": ";
  if (pos->ctype != TINYGLTF_COMPONENT_TYPE_FLOAT || pos->ncomp != 3)
    return err(where + "POSITION must be float VEC3");
  const size_t nv = pos->count;
  if (nv == 0) return std::nullopt;

  // Optional attributes, with the same count as POSITION.
  auto optional_view = [&](const char* name, std::optional<View>& v) -> std::optional<Error> {
    const auto it = p.attributes.find(name);
    if (it == p.attributes.end()) return std::nullopt;
    auto r = accessor_view(m_, it->second, path_);
    if (!r) return r.error();
    if (r->count != nv)
      return err("accessor " + str(it->second) + ": " + name + " has " + str(r->count) +
                 " elements, POSITION " + str(nv));
    const bool fl = r->ctype == TINYGLTF_COMPONENT_TYPE_FLOAT;
    const bool unorm = r->normalized && (r->ctype == TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE ||
                                         r->ctype == TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT);
    if (std::strcmp(name, "NORMAL") == 0 ? !fl || r->ncomp != 3 : !(fl || unorm) || r->ncomp != 2)
      return err("accessor " + str(it->second) + ": " + name + " has an unsupported type");
    v = *r;
    return std::nullopt;
  };
  std::optional<View> nrm, uv;
  if (auto e = optional_view("NORMAL", nrm)) return e;
  if (auto e = optional_view("TEXCOORD_0", uv)) return e;

  std::vector<uint32_t> indices;
  if (p.indices >= 0) {
    auto iv = accessor_view(m_, p.indices, path_);
    if (!iv) return iv.error();
    const std::string iwhere = "accessor " + str(p.indices) + ": ";
    if (iv->ncomp != 1 || (iv->ctype != TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE &&
                           iv->ctype != TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT &&
                           iv->ctype != TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT))
      return err(iwhere + "indices must be unsigned byte, short or int scalars");
    indices.resize(iv->count);
    for (size_t i = 0; i < iv->count; ++i) {
      const uint32_t k = iv->ctype == TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE ? iv->get<uint8_t>(i, 0)
                         : iv->ctype == TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT
                             ? iv->get<uint16_t>(i, 0)
                             : iv->get<uint32_t>(i, 0);
      if (k >= nv)
        return err(iwhere + "index " + str(k) + " out of range (" + str(nv) + " vertices)");
      indices[i] = k;
    }
  }
  auto material = materials_.get(p.material);
  if (!material) return material.error();

  // Vertices, in model space after the node transform; normals by the inverse transpose.
  const glm::mat4 mp(world);
  const glm::mat3 mn(glm::transpose(glm::inverse(glm::dmat3(world))));
  const bool flip = glm::determinant(glm::dmat3(world)) < 0.0;
  // Primitives of one mesh instance that name the same vertex accessors share their vertices.
  auto attribute = [&](const char* name) {
    const auto it = p.attributes.find(name);
    return it == p.attributes.end() ? -1 : it->second;
  };
  const auto [slot, fresh] = shared_.try_emplace(
      {pos_it->second, attribute("NORMAL"), attribute("TEXCOORD_0")}, mesh_.positions.size());
  const size_t base = slot->second;
  if (fresh && mesh_.positions.size() + nv > kMaxElements)
    return err("more than " + str(kMaxElements) + " vertices");
  for (size_t i = 0; fresh && i < nv; ++i) {
    const Vec3 x(pos->get<float>(i, 0), pos->get<float>(i, 1), pos->get<float>(i, 2));
    if (!is_finite(x)) return err(where + "non-finite value");
    const Vec3 y(mp * Vec4(x, 1.0f));
    if (!is_finite(y)) return err(where + "position is not finite after the node transform");
    mesh_.positions.push_back(y);
    Vec3 n(0.0f);
    if (nrm) {
      n = Vec3(nrm->get<float>(i, 0), nrm->get<float>(i, 1), nrm->get<float>(i, 2));
      if (!is_finite(n)) return err("accessor " + str(attribute("NORMAL")) + ": non-finite value");
      n = mn * n;
      const float len = glm::length(n);
      n = len > 0.0f && std::isfinite(len) ? n / len : Vec3(0.0f);
    }
    mesh_.normals.push_back(n);
    has_normal_.push_back(n != Vec3(0.0f));
    any_normal_ = any_normal_ || n != Vec3(0.0f);
    Vec2 t(0.0f);
    if (uv) {
      t = Vec2(uv->unit(i, 0), uv->unit(i, 1));
      if (!std::isfinite(t.x) || !std::isfinite(t.y))
        return err("accessor " + str(attribute("TEXCOORD_0")) + ": non-finite value");
      t.y = 1.0f - t.y;  // glTF's v runs down the image; ours (sample_texture) runs up
      any_uv_ = true;
    }
    mesh_.uvs.push_back(t);
  }

  // Triangles; strips alternate winding, fans pivot on their first vertex.
  const size_t n = p.indices >= 0 ? indices.size() : nv;
  if (mesh_.triangles.size() + n > kMaxElements)
    return err("more than " + str(kMaxElements) + " triangles");
  auto at = [&](size_t i) { return p.indices >= 0 ? indices[i] : uint32_t(i); };
  auto emit = [&](uint32_t a, uint32_t b, uint32_t c) {
    if (a == b || b == c || a == c) return;  // strip restarts and degenerate input
    if (flip) std::swap(b, c);               // a mirroring transform reverses the winding
    mesh_.triangles.emplace_back(uint32_t(base) + a, uint32_t(base) + b, uint32_t(base) + c);
    mesh_.face_material.push_back(*material);
  };
  if (mode == TINYGLTF_MODE_TRIANGLES) {
    for (size_t i = 0; i + 2 < n; i += 3) emit(at(i), at(i + 1), at(i + 2));
  } else if (mode == TINYGLTF_MODE_TRIANGLE_STRIP) {
    for (size_t i = 0; i + 2 < n; ++i)
      i % 2 == 0 ? emit(at(i), at(i + 1), at(i + 2)) : emit(at(i + 1), at(i), at(i + 2));
  } else {
    for (size_t i = 1; i + 1 < n; ++i) emit(at(0), at(i), at(i + 1));
  }
  return std::nullopt;
}

std::optional<Error> Builder::add_camera(int n, int index, const glm::dmat4& world) {
  if (size_t(index) >= m_.cameras.size())
    return err("node " + str(n) + ": camera " + str(index) + " out of range (" +
               str(m_.cameras.size()) + " cameras)");
  const tinygltf::Camera& c = m_.cameras[size_t(index)];
  if (c.type != "perspective") {
    out_.warnings.push_back("camera " + str(index) + ": " + (c.type.empty() ? "untyped" : c.type) +
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
    out_.warnings.push_back("camera " + str(index) + ": invalid yfov or transform (skipped)");
    return std::nullopt;
  }
  out_.cameras.push_back(cam);
  return std::nullopt;
}

// Vertices without a usable normal: none anywhere keeps the geometric normal everywhere; a mix
// gives the triangles that touch such a vertex their own vertices with the face normal (flat,
// as glTF asks for primitives without normals).
void Builder::finish_normals() {
  if (!any_normal_) {
    mesh_.normals.clear();
    return;
  }
  const size_t nv = mesh_.positions.size();
  for (UVec3& t : mesh_.triangles) {
    if (has_normal_[t[0]] && has_normal_[t[1]] && has_normal_[t[2]]) continue;
    const Vec3 c = glm::cross(mesh_.positions[t[1]] - mesh_.positions[t[0]],
                              mesh_.positions[t[2]] - mesh_.positions[t[0]]);
    const float len = glm::length(c);
    const Vec3 fn = len > 0.0f && std::isfinite(len) ? c / len : Vec3(0.0f, 0.0f, 1.0f);
    for (int k = 0; k < 3; ++k) {
      mesh_.positions.push_back(mesh_.positions[t[k]]);
      mesh_.uvs.push_back(mesh_.uvs[t[k]]);
      mesh_.normals.push_back(fn);
      t[k] = uint32_t(mesh_.positions.size() - 1);
    }
  }
  // Vertices left without a normal are no longer used; give them a harmless unit one.
  for (size_t i = 0; i < nv; ++i)
    if (!has_normal_[i]) mesh_.normals[i] = Vec3(0.0f, 0.0f, 1.0f);
}

// KHR_lights_punctual carries physical units: point and spot intensity in candela (lm/sr, falling
// off as 1/d^2), directional in lux. Parker's lights have no falloff, so each light's illuminance
// is taken at the model's bounding-box centre (point: I/d^2, directional: I) and all lights are
// scaled together so the brightest gets illuminance 1: colour = glTF colour * E / E_max. Relative
// brightness is kept; lights of intensity 0 are dropped; spot cones and range are ignored.
void Builder::add_lights() {
  Vec3 lo(kInfinity), hi(-kInfinity);
  for (const Vec3& p : mesh_.positions) {
    lo = glm::min(lo, p);
    hi = glm::max(hi, p);
  }
  const Vec3 centre = 0.5f * (lo + hi);
  const double min_dist = std::max(1e-3 * double(glm::length(hi - lo)), 1e-6);
  std::vector<std::pair<Light, double>> lit;
  double e_max = 0.0;
  for (const auto& [index, world] : lights_) {
    const tinygltf::Light& g = m_.lights[size_t(index)];
    const std::string where = "light " + str(index) + ": ";
    Light l;
    if (g.color.size() == 3)
      l.color =
          glm::clamp(Vec3(float(g.color[0]), float(g.color[1]), float(g.color[2])), 0.0f, 1.0f);
    else if (!g.color.empty())
      out_.warnings.push_back(where + "color needs 3 numbers (white used)");
    double e = std::isfinite(g.intensity) ? std::max(g.intensity, 0.0) : 0.0;
    if (g.type == "directional") {
      l.kind = LightKind::kDirectional;
      l.direction = dir(world, 0.0, 0.0, -1.0);
    } else if (g.type == "point" || g.type == "spot") {
      l.position = Vec3(world * glm::dvec4(0.0, 0.0, 0.0, 1.0));
      e /= std::pow(std::max(double(glm::length(l.position - centre)), min_dist), 2.0);
      if (g.type == "spot")
        out_.warnings.push_back("spot light " + str(index) + " treated as a point light");
    } else {
      out_.warnings.push_back(where + "type '" + g.type + "' is not supported (skipped)");
      continue;
    }
    if (!(e > 0.0) || !std::isfinite(e) || !is_finite(l.position) || !is_finite(l.direction))
      continue;
    e_max = std::max(e_max, e);
    lit.emplace_back(l, e);
  }
  for (auto& [l, e] : lit) {
    l.color *= float(e / e_max);
    out_.lights.push_back(l);
  }
}

}  // namespace

namespace {

Result<ModelData> parse_gltf_any_text(const std::string& bytes, const std::string& path,
                                      const std::string& base_dir, ImageCache& images) {
  auto checked = gltf::check_gltf(bytes, path, base_dir);
  if (!checked) return checked.error();
  try {
    tinygltf::Model model;
    tinygltf::TinyGLTF loader;
    std::map<int, std::string> embedded;
    gltf::restrict_loader(loader, *checked, embedded);
    std::string error, warning;
    const auto* data = reinterpret_cast<const unsigned char*>(bytes.data());
    const bool ok = checked->binary
                        ? loader.LoadBinaryFromMemory(&model, &error, &warning, data,
                                                      unsigned(bytes.size()), base_dir)
                        : loader.LoadASCIIFromString(&model, &error, &warning, bytes.data(),
                                                     unsigned(bytes.size()), base_dir);
    if (!ok) return fail(path, gltf::one_line(error));
    ModelData out;
    gltf::MaterialMap materials(model, path, base_dir, images, embedded, out.mesh, out.warnings);
    Builder builder(model, path, materials, out);
    if (auto e = builder.run()) return *e;
    return out;
  } catch (const std::exception& e) {
    return fail(path,
                gltf::one_line(e.what()));  // bad_alloc, or a JSON type tinygltf did not expect
  }
}

}  // namespace

// Names and URIs from the file appear in errors and warnings: keep each on one line.
Result<ModelData> parse_gltf(const std::string& bytes, const std::string& path,
                             const std::string& base_dir, ImageCache& images) {
  auto r = parse_gltf_any_text(bytes, path, base_dir, images);
  if (r.ok())
    for (std::string& w : r->warnings) w = one_line(w);
  return one_line(std::move(r));
}

Result<ModelData> load_gltf(const std::string& path, ImageCache& images) {
  auto bytes = read_file_bytes(path);
  if (!bytes) return Error{one_line(bytes.error().message)};
  const size_t slash = path.find_last_of('/');
  const std::string base_dir = slash == std::string::npos ? "." : path.substr(0, slash);
  return parse_gltf(*bytes, path, base_dir.empty() ? "/" : base_dir, images);
}

}  // namespace frameless
