// Wavefront OBJ input: tinyobjloader parses and triangulates; a line scan of our own first
// checks what tinyobjloader lets through silently (NaN/Inf numbers, out-of-range indices) so
// that every error names its line, and hands it a sanitised copy holding only what we use.
#include "core/io/mesh_obj.h"

#include <charconv>
#include <cmath>
#include <cstring>
#include <optional>
#include <string_view>
#include <unordered_map>

#include <tiny_obj_loader.h>

#include "core/io/text_tokens.h"

namespace frameless {
namespace {

Error line_error(const std::string& path, size_t line, const std::string& what) {
  return Error{path + ":" + std::to_string(line) + ": " + what};
}

// Resolves an OBJ index (1-based, or negative = relative to the count so far).
bool check_index(std::string_view tok, long long defined, long long total) {
  if (tok.empty()) return false;
  long long v = 0;
  const auto r = std::from_chars(tok.data(), tok.data() + tok.size(), v);
  if (r.ec != std::errc()) return false;
  if (v > 0) return v <= total;
  if (v < 0) return -v <= defined;
  return false;
}

// Appends the shortest text that reads back as x, so tinyobjloader parses only short numbers.
void append_number(std::string& out, float x) {
  char buf[32];
  const auto r = std::to_chars(buf, buf + sizeof buf, x);
  out += ' ';
  out.append(buf, r.ptr);
}

std::optional<Error> check_face_part(std::string_view tok, const char* what, long long defined,
                                     long long total, const std::string& path, size_t line) {
  if (tok.empty() || check_index(tok, defined, total)) return std::nullopt;
  return line_error(path, line,
                    std::string("f: ") + what + " index '" + std::string(tok.substr(0, 32)) +
                        "' out of range (1.." + std::to_string(total) + ")");
}

}  // namespace

Result<ObjScan> scan_obj(const std::string& text, const std::string& path) {
  long long total_v = 0, total_vn = 0, total_vt = 0;
  for (size_t pos = 0; pos < text.size();) {
    size_t end = text.find('\n', pos);
    if (end == std::string::npos) end = text.size();
    std::string_view line(text.data() + pos, end - pos);
    std::string_view key = next_token(line);
    if (key == "v") ++total_v;
    if (key == "vn") ++total_vn;
    if (key == "vt") ++total_vt;
    pos = end + 1;
  }
  ObjScan scan;
  scan.text.reserve(text.size());
  std::unordered_map<std::string, size_t> material_ids;
  long long v_count = 0, vn_count = 0, vt_count = 0, faces = 0;
  size_t line_no = 0;
  for (size_t pos = 0; pos < text.size(); scan.text += '\n') {
    size_t end = text.find('\n', pos);
    if (end == std::string::npos) end = text.size();
    ++line_no;
    std::string_view line(text.data() + pos, end - pos);
    pos = end + 1;
    if (line.find('\0') != std::string_view::npos)
      return line_error(path, line_no, "NUL byte in a text file");
    std::string_view key = next_token(line);
    const bool used = key == "v" || key == "vn" || key == "vt" || key == "f" ||
                      key == "usemtl" || key == "mtllib";
    if (!used) continue;  // comments, groups and statements we do not use never reach tinyobj
    if (!line.empty() && line.back() == '\\')
      return line_error(path, line_no, "line continuation is not supported");
    if (key == "v" || key == "vn" || key == "vt") {
      // v and vn need 3 numbers (extra v numbers, w or colours, are dropped); vt 2 or 3 (u v [w]).
      const int need = key == "vt" ? 2 : 3;
      const int most = key == "vt" ? 3 : 1 << 30;
      scan.text += key;
      int k = 0;
      for (std::string_view tok = next_token(line); !tok.empty(); tok = next_token(line), ++k) {
        float x;
        if (k == most)
          return line_error(path, line_no, std::string(key) + ": expected 2 or 3 numbers");
        if (k >= 3) continue;
        if (!parse_finite(tok, x))
          return line_error(path, line_no,
                            std::string(key) + ": '" + std::string(tok.substr(0, 32)) +
                                "' is not a finite number");
        if (k < need) append_number(scan.text, x);
      }
      if (k < need)
        return line_error(path, line_no,
                          std::string(key) + (need == 2 ? ": expected 2 or 3 numbers"
                                                        : ": expected 3 numbers"));
      (key == "v" ? v_count : key == "vn" ? vn_count : vt_count)++;
    } else if (key == "f") {
      int corners = 0;
      scan.text += 'f';
      for (std::string_view tok = next_token(line); !tok.empty(); tok = next_token(line)) {
        ++corners;
        // v, v/vt, v//vn or v/vt/vn: check every part that is there.
        const size_t s1 = tok.find('/');
        const std::string_view vi = tok.substr(0, s1);
        if (!check_index(vi, v_count, total_v))
          return line_error(path, line_no,
                            "f: vertex index '" + std::string(vi.substr(0, 32)) +
                                "' out of range (1.." + std::to_string(total_v) + ")");
        if (s1 != std::string_view::npos) {
          const size_t s2 = tok.find('/', s1 + 1);
          const size_t tn = s2 == std::string_view::npos ? std::string_view::npos : s2 - s1 - 1;
          if (auto err = check_face_part(tok.substr(s1 + 1, tn), "texture", vt_count, total_vt,
                                         path, line_no))
            return *err;
          if (s2 != std::string_view::npos)
            if (auto err = check_face_part(tok.substr(s2 + 1), "normal", vn_count, total_vn, path,
                                           line_no))
              return *err;
        }
        scan.text += ' ';
        scan.text += tok;
      }
      if (corners < 3) return line_error(path, line_no, "f: a face needs at least 3 vertices");
      ++faces;
    } else if (key == "usemtl") {
      // Names may hold spaces; tinyobjloader would cut them, so it sees "o m<K>" instead.
      const std::string name(trim(line));
      auto it = material_ids.find(name);
      if (it == material_ids.end()) {
        if (scan.materials.size() >= kNoObjMaterial)
          return line_error(path, line_no, "usemtl: too many materials");
        it = material_ids.emplace(name, scan.materials.size()).first;
        scan.materials.push_back(name);
      }
      scan.text += "o m" + std::to_string(it->second);
    } else {
      const std::string_view names = trim(line);
      if (!names.empty()) scan.libraries.push_back({line_no, std::string(names)});
    }
  }
  if (faces == 0) return Error{path + ": empty mesh (no faces)"};
  return scan;
}

namespace {

// One output vertex per distinct (position, texcoord, normal) triple of a face corner.
struct CornerKey {
  int v, t, n;
  bool operator==(const CornerKey&) const = default;
};
struct CornerHash {
  size_t operator()(const CornerKey& k) const {
    uint64_t h = uint64_t(uint32_t(k.v)) * 0x9E3779B97F4A7C15ull;
    h ^= (uint64_t(uint32_t(k.t)) + 0x7F4A7C15ull + (h << 6) + (h >> 2)) * 0xBF58476D1CE4E5B9ull;
    h ^= (uint64_t(uint32_t(k.n)) + 0x94D049BBull + (h << 6) + (h >> 2)) * 0x94D049BB133111EBull;
    return size_t(h ^ (h >> 31));
  }
};

Vec3 attrib3(const std::vector<tinyobj::real_t>& a, int i) {
  return Vec3(a[3 * size_t(i)], a[3 * size_t(i) + 1], a[3 * size_t(i) + 2]);
}

// The usemtl index K of a shape named "m<K>" by scan_obj, else none.
uint16_t shape_material(const std::string& name, size_t count) {
  if (name.size() < 2 || name[0] != 'm') return kNoObjMaterial;
  unsigned k = 0;
  const auto r = std::from_chars(name.data() + 1, name.data() + name.size(), k);
  const bool whole = r.ec == std::errc() && r.ptr == name.data() + name.size();
  return whole && k < count ? uint16_t(k) : kNoObjMaterial;
}

// Per-corner vertices for the OBJ+MTL path: uvs where faces give vt, normals when all corners
// give one, one vertex per distinct triple.
Result<MeshData> split_vertices(const tinyobj::attrib_t& attrib,
                                const std::vector<tinyobj::shape_t>& shapes, const ObjScan& scan,
                                const std::string& path) {
  const int nv = int(attrib.vertices.size() / 3), nn = int(attrib.normals.size() / 3);
  const int nt = int(attrib.texcoords.size() / 2);
  bool use_normals = nn > 0, use_uvs = false;
  for (const tinyobj::shape_t& shape : shapes)
    for (const tinyobj::index_t& c : shape.mesh.indices) {
      if (c.vertex_index < 0 || c.vertex_index >= nv)
        return Error{path + ": vertex index out of range"};
      use_normals = use_normals && c.normal_index >= 0 && c.normal_index < nn;
      use_uvs = use_uvs || (c.texcoord_index >= 0 && c.texcoord_index < nt);
    }
  MeshData mesh;
  std::unordered_map<CornerKey, uint32_t, CornerHash> vertex_of;
  for (const tinyobj::shape_t& shape : shapes) {
    const uint16_t material = shape_material(shape.name, scan.materials.size());
    const std::vector<tinyobj::index_t>& idx = shape.mesh.indices;
    for (size_t f = 0; f + 2 < idx.size(); f += 3) {
      UVec3 tri;
      for (int k = 0; k < 3; ++k) {
        const tinyobj::index_t& c = idx[f + size_t(k)];
        const bool has_t = use_uvs && c.texcoord_index >= 0 && c.texcoord_index < nt;
        const int t = has_t ? c.texcoord_index : -1;
        const CornerKey key{c.vertex_index, t, use_normals ? c.normal_index : -1};
        auto [it, added] = vertex_of.emplace(key, uint32_t(mesh.positions.size()));
        if (added) {
          mesh.positions.push_back(attrib3(attrib.vertices, key.v));
          if (use_normals) mesh.normals.push_back(attrib3(attrib.normals, key.n));
          if (use_uvs)
            mesh.uvs.push_back(t < 0 ? Vec2(0.0f)
                                     : Vec2(attrib.texcoords[2 * size_t(t)],
                                            attrib.texcoords[2 * size_t(t) + 1]));
        }
        tri[k] = it->second;
      }
      mesh.triangles.push_back(tri);
      mesh.face_material.push_back(material);
    }
  }
  // Zero-length normals cannot shade: fall back to flat shading for the whole mesh.
  for (const Vec3& n : mesh.normals)
    if (!(glm::dot(n, n) > 0.0f)) {
      mesh.normals.clear();
      break;
    }
  return mesh;
}

}  // namespace

Result<MeshData> build_obj_mesh(const ObjScan& scan, const std::string& path, bool with_materials) {
  tinyobj::ObjReaderConfig config;
  config.triangulate = true;
  config.vertex_color = false;
  tinyobj::ObjReader reader;
  // Materials never come from tinyobjloader: the scan turned usemtl into object names.
  if (!reader.ParseFromString(scan.text, "", config)) {
    std::string msg = reader.Error();
    while (!msg.empty() && (msg.back() == '\n' || msg.back() == '\r')) msg.pop_back();
    for (char& c : msg)
      if (c == '\n' || c == '\r') c = ' ';
    return Error{path + ": " + (msg.empty() ? "cannot parse OBJ" : msg)};
  }
  const tinyobj::attrib_t& attrib = reader.GetAttrib();
  if (with_materials) {
    auto mesh = split_vertices(attrib, reader.GetShapes(), scan, path);
    if (mesh && mesh->triangles.empty()) return Error{path + ": empty mesh (no faces)"};
    return mesh;
  }
  const size_t nv = attrib.vertices.size() / 3;
  const size_t nn = attrib.normals.size() / 3;
  MeshData mesh;
  mesh.positions.resize(nv);
  for (size_t i = 0; i < nv; ++i) mesh.positions[i] = attrib3(attrib.vertices, int(i));
  // OBJ indexes normals separately from positions; we keep one normal per position, taken from
  // the first face corner that names one. Mixed or missing normals fall back to none.
  std::vector<Vec3> normals;
  bool use_normals = nn > 0;
  if (use_normals) normals.assign(nv, Vec3(0.0f));
  std::vector<uint8_t> have(use_normals ? nv : 0, 0);
  for (const tinyobj::shape_t& shape : reader.GetShapes()) {
    const std::vector<tinyobj::index_t>& idx = shape.mesh.indices;
    for (size_t f = 0; f + 2 < idx.size(); f += 3) {
      UVec3 tri;
      for (int k = 0; k < 3; ++k) {
        const tinyobj::index_t& c = idx[f + size_t(k)];
        if (c.vertex_index < 0 || size_t(c.vertex_index) >= nv)
          return Error{path + ": vertex index out of range"};
        tri[k] = uint32_t(c.vertex_index);
        if (!use_normals) continue;
        if (c.normal_index < 0 || size_t(c.normal_index) >= nn) {
          use_normals = false;
          continue;
        }
        if (!have[tri[k]]) {
          normals[tri[k]] = attrib3(attrib.normals, c.normal_index);
          have[tri[k]] = 1;
        }
      }
      mesh.triangles.push_back(tri);
    }
  }
  if (mesh.triangles.empty()) return Error{path + ": empty mesh (no faces)"};
  if (use_normals) {
    // Positions no face uses keep a harmless normal; zero-length normals disable shading normals.
    for (size_t i = 0; i < nv && use_normals; ++i) {
      if (!have[i]) normals[i] = Vec3(0.0f, 1.0f, 0.0f);
      use_normals = glm::dot(normals[i], normals[i]) > 0.0f;
    }
    if (use_normals) mesh.normals = std::move(normals);
  }
  return mesh;
}

Result<MeshData> parse_obj(const std::string& text, const std::string& path) {
  auto scan = scan_obj(text, path);
  if (!scan) return scan.error();
  return build_obj_mesh(*scan, path, false);
}

}  // namespace frameless
