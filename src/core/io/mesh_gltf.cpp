// glTF 2.0 input (.gltf with external or data: buffers, .glb by content) through Debian's
// tinygltf: triangle primitives (strips and fans converted) placed by the default scene's nodes
// (gltf_instances.cpp: transforms, instances, cameras, lights): a mesh one node places is copied
// into the model's flat mesh, a mesh several nodes place is stored once as a shared mesh;
// materials in gltf_material.cpp. tinygltf checks no index or byte range, so every accessor is
// bounds-checked here before it is read; gltf_check.cpp covers what tinygltf would misread or
// let through.
#include <cmath>
#include <cstring>

#include "core/io/file_util.h"
#include "core/io/gltf_internal.h"
#include "core/scene/scene_build.h"

namespace frameless {
namespace {

using gltf::fail;
using gltf::str;
using tinygltf::Model;

// Vertices and triangles stored per model (shared meshes once, however often they are placed):
// a small file cannot ask for unbounded memory.
constexpr size_t kMaxElements = size_t(1) << 27;


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

// A mesh being filled: the flattened model (model space) or one shared mesh (object space).
struct Part {
  MeshData& mesh;
  std::vector<uint8_t>& has_normal;  // per vertex: the file gave it a usable normal
};

// A glTF mesh stored once as MeshData::shared[index] (kInvalidId: it has no triangles).
struct SharedMesh {
  uint32_t index = kInvalidId;
  size_t skipped = 0;                  // its point/line primitives, counted at each placement
  Vec3 lo{kInfinity}, hi{-kInfinity};  // its object-space vertex box
};

class Builder {
 public:
  Builder(const Model& m, const std::string& path, gltf::MaterialMap& materials, ModelData& out)
      : m_(m), path_(path), materials_(materials), out_(out), flat_{out.mesh, flat_normal_} {}

  std::optional<Error> run();

 private:
  std::optional<Error> add_mesh(int index, const glm::dmat4& world, Part part);
  std::optional<Error> place_shared(const gltf::NodeVisit& v);
  std::optional<Error> add_primitive(const tinygltf::Primitive& p, const glm::dmat4& world,
                                     Part part);
  void finish_normals(Part part);
  Error err(const std::string& what) const { return fail(path_, what); }
  void warn_once(const std::string& w) {
    if (std::find(out_.warnings.begin(), out_.warnings.end(), w) == out_.warnings.end())
      out_.warnings.push_back(w);
  }

  const Model& m_;
  const std::string& path_;
  gltf::MaterialMap& materials_;
  ModelData& out_;
  std::vector<uint8_t> flat_normal_;
  Part flat_;
  std::vector<std::vector<uint8_t>> shared_normal_;  // has_normal of each shared mesh
  std::map<int, SharedMesh> shared_meshes_;          // glTF mesh -> its shared copy
  size_t vertices_ = 0, triangles_ = 0;              // stored (shared meshes once)
  bool any_normal_ = false, any_uv_ = false;
  size_t skipped_primitives_ = 0;
  std::vector<std::pair<int, glm::dmat4>> lights_;      // KHR_lights_punctual index, node transform
  std::map<std::tuple<int, int, int>, size_t> shared_;  // vertex accessors -> first vertex
};

std::optional<Error> Builder::run() {
  auto visits = gltf::walk_nodes(m_, path_);
  if (!visits) return visits.error();
  for (const gltf::NodeVisit& v : *visits) {
    const tinygltf::Node& node = m_.nodes[size_t(v.node)];
    if (node.skin >= 0) warn_once("skins are ignored (meshes are shown in their bind pose)");
    if (node.mesh >= 0)
      if (auto e = v.instance ? place_shared(v) : add_mesh(node.mesh, v.world, flat_)) return e;
    if (node.camera >= 0)
      if (auto e = gltf::add_camera(m_, path_, v.node, node.camera, v.world, out_)) return e;
    const auto ext = node.extensions.find("KHR_lights_punctual");
    if (ext != node.extensions.end() && ext->second.Has("light")) {
      const tinygltf::Value& l = ext->second.Get("light");
      if (!l.IsInt() || l.GetNumberAsInt() < 0 || size_t(l.GetNumberAsInt()) >= m_.lights.size())
        return err("node " + str(v.node) + ": light out of range (" + str(m_.lights.size()) +
                   " lights)");
      lights_.emplace_back(l.GetNumberAsInt(), v.world);
    }
  }
  if (skipped_primitives_ > 0)
    out_.warnings.push_back(str(skipped_primitives_) +
                            " point/line primitive(s) skipped: only triangles are rendered");
  MeshData& model = out_.mesh;
  if (model.triangles.empty() && model.placements.empty()) return err("no triangles in the scene");
  finish_normals(flat_);
  for (size_t i = 0; i < model.shared.size(); ++i)
    finish_normals({model.shared[i], shared_normal_[i]});
  if (!any_uv_) {
    model.uvs.clear();
    for (MeshData& s : model.shared) s.uvs.clear();
  }
  gltf::add_lights(m_, lights_, out_);
  return std::nullopt;
}

std::optional<Error> Builder::add_mesh(int index, const glm::dmat4& world, Part part) {
  shared_.clear();
  for (const tinygltf::Primitive& p : m_.meshes[size_t(index)].primitives)
    if (auto e = add_primitive(p, world, part)) return e;
  return std::nullopt;
}

// A placement of a shared mesh: the mesh is built in object space on its first placement, then
// every placement adds its node's world matrix.
std::optional<Error> Builder::place_shared(const gltf::NodeVisit& v) {
  const int index = m_.nodes[size_t(v.node)].mesh;
  MeshData& model = out_.mesh;
  auto [it, fresh] = shared_meshes_.try_emplace(index);
  SharedMesh& sm = it->second;
  if (fresh) {
    model.shared.emplace_back();
    shared_normal_.emplace_back();
    const size_t skipped = skipped_primitives_;
    if (auto e = add_mesh(index, glm::dmat4(1.0), {model.shared.back(), shared_normal_.back()}))
      return e;
    sm.skipped = skipped_primitives_ - skipped;
    if (model.shared.back().triangles.empty()) {
      model.shared.pop_back();  // nothing to place
      shared_normal_.pop_back();
      return std::nullopt;
    }
    sm.index = uint32_t(model.shared.size() - 1);
    for (const Vec3& p : model.shared.back().positions) {
      sm.lo = glm::min(sm.lo, p);
      sm.hi = glm::max(sm.hi, p);
    }
  } else {
    skipped_primitives_ += sm.skipped;
  }
  if (sm.index == kInvalidId) return std::nullopt;
  // The placed box holds every placed vertex: its corners stand for them in the check that
  // flattened vertices get.
  const glm::mat4 to_model(v.world);
  for (int k = 0; k < 8; ++k) {
    const Vec3 c(k & 1 ? sm.hi.x : sm.lo.x, k & 2 ? sm.hi.y : sm.lo.y, k & 4 ? sm.hi.z : sm.lo.z);
    if (!is_finite(Vec3(to_model * Vec4(c, 1.0f))))
      return err("node " + str(v.node) + ": position is not finite after the node transform");
  }
  model.placements.push_back({sm.index, to_model});
  return std::nullopt;
}

std::optional<Error> Builder::add_primitive(const tinygltf::Primitive& p, const glm::dmat4& world,
                                            Part part) {
  MeshData& mesh = part.mesh;
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

  // Vertices after the node transform (model space; identity for a shared mesh's object space);
  // normals by the inverse transpose.
  const glm::mat4 mp(world);
  const glm::mat3 mn(glm::transpose(glm::inverse(glm::dmat3(world))));
  const bool flip = glm::determinant(glm::dmat3(world)) < 0.0;
  // Primitives of one mesh instance that name the same vertex accessors share their vertices.
  auto attribute = [&](const char* name) {
    const auto it = p.attributes.find(name);
    return it == p.attributes.end() ? -1 : it->second;
  };
  const auto [slot, fresh] = shared_.try_emplace(
      {pos_it->second, attribute("NORMAL"), attribute("TEXCOORD_0")}, mesh.positions.size());
  const size_t base = slot->second;
  if (fresh && vertices_ + nv > kMaxElements)
    return err("more than " + str(kMaxElements) + " vertices");
  if (fresh) vertices_ += nv;
  for (size_t i = 0; fresh && i < nv; ++i) {
    const Vec3 x(pos->get<float>(i, 0), pos->get<float>(i, 1), pos->get<float>(i, 2));
    if (!is_finite(x)) return err(where + "non-finite value");
    const Vec3 y(mp * Vec4(x, 1.0f));
    if (!is_finite(y)) return err(where + "position is not finite after the node transform");
    mesh.positions.push_back(y);
    Vec3 n(0.0f);
    if (nrm) {
      n = Vec3(nrm->get<float>(i, 0), nrm->get<float>(i, 1), nrm->get<float>(i, 2));
      if (!is_finite(n)) return err("accessor " + str(attribute("NORMAL")) + ": non-finite value");
      n = mn * n;
      const float len = glm::length(n);
      n = len > 0.0f && std::isfinite(len) ? n / len : Vec3(0.0f);
    }
    mesh.normals.push_back(n);
    part.has_normal.push_back(n != Vec3(0.0f));
    any_normal_ = any_normal_ || n != Vec3(0.0f);
    Vec2 t(0.0f);
    if (uv) {
      t = Vec2(uv->unit(i, 0), uv->unit(i, 1));
      if (!std::isfinite(t.x) || !std::isfinite(t.y))
        return err("accessor " + str(attribute("TEXCOORD_0")) + ": non-finite value");
      t.y = 1.0f - t.y;  // glTF's v runs down the image; ours (sample_texture) runs up
      any_uv_ = true;
    }
    mesh.uvs.push_back(t);
  }

  // Triangles; strips alternate winding, fans pivot on their first vertex.
  const size_t n = p.indices >= 0 ? indices.size() : nv;
  if (triangles_ + n > kMaxElements) return err("more than " + str(kMaxElements) + " triangles");
  auto at = [&](size_t i) { return p.indices >= 0 ? indices[i] : uint32_t(i); };
  auto emit = [&](uint32_t a, uint32_t b, uint32_t c) {
    if (a == b || b == c || a == c) return;  // strip restarts and degenerate input
    if (flip) std::swap(b, c);               // a mirroring transform reverses the winding
    mesh.triangles.emplace_back(uint32_t(base) + a, uint32_t(base) + b, uint32_t(base) + c);
    mesh.face_material.push_back(*material);
    ++triangles_;
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

// Vertices without a usable normal: none anywhere in the model keeps the geometric normal
// everywhere; a mix gives the triangles that touch such a vertex their own vertices with the face
// normal (flat, as glTF asks for primitives without normals). Each part on its own.
void Builder::finish_normals(Part part) {
  MeshData& mesh = part.mesh;
  if (!any_normal_) {
    mesh.normals.clear();
    return;
  }
  const size_t nv = mesh.positions.size();
  for (UVec3& t : mesh.triangles) {
    if (part.has_normal[t[0]] && part.has_normal[t[1]] && part.has_normal[t[2]]) continue;
    const Vec3 c = glm::cross(mesh.positions[t[1]] - mesh.positions[t[0]],
                              mesh.positions[t[2]] - mesh.positions[t[0]]);
    const float len = glm::length(c);
    const Vec3 fn = len > 0.0f && std::isfinite(len) ? c / len : Vec3(0.0f, 0.0f, 1.0f);
    for (int k = 0; k < 3; ++k) {
      mesh.positions.push_back(mesh.positions[t[k]]);
      mesh.uvs.push_back(mesh.uvs[t[k]]);
      mesh.normals.push_back(fn);
      t[k] = uint32_t(mesh.positions.size() - 1);
    }
  }
  // Vertices left without a normal are no longer used; give them a harmless unit one.
  for (size_t i = 0; i < nv; ++i)
    if (!part.has_normal[i]) mesh.normals[i] = Vec3(0.0f, 0.0f, 1.0f);
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
