// Wavefront OBJ input: tinyobjloader parses and triangulates; a line scan of our own first
// checks what tinyobjloader lets through silently (NaN/Inf numbers, out-of-range indices) so
// that every error names its line.
#include <charconv>
#include <cmath>
#include <cstring>
#include <string_view>

#include <tiny_obj_loader.h>

#include "core/scene_io.h"
#include "core/text_tokens.h"

namespace frameless {
namespace {

Error line_error(const std::string& path, size_t line, const std::string& what) {
  return Error{path + ":" + std::to_string(line) + ": " + what};
}

// Checks one numeric token of a v/vn line. A leading '+' is accepted as in C's strtod.
bool parse_finite(std::string_view tok, float& out) {
  if (!tok.empty() && tok[0] == '+') tok.remove_prefix(1);
  const auto r = std::from_chars(tok.data(), tok.data() + tok.size(), out);
  return r.ec == std::errc() && r.ptr == tok.data() + tok.size() && std::isfinite(out);
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

// The checks tinyobjloader does not make, with line numbers.
std::optional<Error> scan_obj(const std::string& text, const std::string& path) {
  long long total_v = 0, total_vn = 0;
  for (size_t pos = 0; pos < text.size();) {
    size_t end = text.find('\n', pos);
    if (end == std::string::npos) end = text.size();
    std::string_view line(text.data() + pos, end - pos);
    std::string_view key = next_token(line);
    if (key == "v") ++total_v;
    if (key == "vn") ++total_vn;
    pos = end + 1;
  }
  long long v_count = 0, vn_count = 0, faces = 0;
  size_t line_no = 0;
  for (size_t pos = 0; pos < text.size();) {
    size_t end = text.find('\n', pos);
    if (end == std::string::npos) end = text.size();
    ++line_no;
    std::string_view line(text.data() + pos, end - pos);
    pos = end + 1;
    if (line.find('\0') != std::string_view::npos)
      return line_error(path, line_no, "NUL byte in a text file");
    if (!line.empty() && line.back() == '\\')
      return line_error(path, line_no, "line continuation is not supported");
    std::string_view key = next_token(line);
    if (key == "v" || key == "vn") {
      for (int k = 0; k < 3; ++k) {
        std::string_view tok = next_token(line);
        float x;
        if (tok.empty())
          return line_error(path, line_no, std::string(key) + ": expected 3 numbers");
        if (!parse_finite(tok, x))
          return line_error(path, line_no,
                            std::string(key) + ": '" + std::string(tok.substr(0, 32)) +
                                "' is not a finite number");
      }
      (key == "v" ? v_count : vn_count)++;
    } else if (key == "f") {
      int corners = 0;
      for (std::string_view tok = next_token(line); !tok.empty(); tok = next_token(line)) {
        ++corners;
        // v, v/vt, v//vn or v/vt/vn: check the position and normal parts.
        const size_t s1 = tok.find('/');
        const std::string_view vi = tok.substr(0, s1);
        if (!check_index(vi, v_count, total_v))
          return line_error(path, line_no,
                            "f: vertex index '" + std::string(vi.substr(0, 32)) +
                                "' out of range (1.." + std::to_string(total_v) + ")");
        if (s1 != std::string_view::npos) {
          const size_t s2 = tok.find('/', s1 + 1);
          if (s2 != std::string_view::npos) {
            const std::string_view ni = tok.substr(s2 + 1);
            if (!ni.empty() && !check_index(ni, vn_count, total_vn))
              return line_error(path, line_no,
                                "f: normal index '" + std::string(ni.substr(0, 32)) +
                                    "' out of range (1.." + std::to_string(total_vn) + ")");
          }
        }
      }
      if (corners < 3) return line_error(path, line_no, "f: a face needs at least 3 vertices");
      ++faces;
    }
  }
  if (faces == 0) return Error{path + ": empty mesh (no faces)"};
  return std::nullopt;
}

}  // namespace

Result<MeshData> parse_obj(const std::string& text, const std::string& path) {
  if (auto err = scan_obj(text, path)) return *err;
  tinyobj::ObjReaderConfig config;
  config.triangulate = true;
  config.vertex_color = false;
  tinyobj::ObjReader reader;
  // Materials are ignored: the scene assigns one material per mesh.
  if (!reader.ParseFromString(text, "", config)) {
    std::string msg = reader.Error();
    while (!msg.empty() && (msg.back() == '\n' || msg.back() == '\r')) msg.pop_back();
    for (char& c : msg)
      if (c == '\n' || c == '\r') c = ' ';
    return Error{path + ": " + (msg.empty() ? "cannot parse OBJ" : msg)};
  }
  const tinyobj::attrib_t& attrib = reader.GetAttrib();
  const size_t nv = attrib.vertices.size() / 3;
  const size_t nn = attrib.normals.size() / 3;
  MeshData mesh;
  mesh.positions.resize(nv);
  for (size_t i = 0; i < nv; ++i)
    mesh.positions[i] = Vec3(attrib.vertices[3 * i], attrib.vertices[3 * i + 1],
                             attrib.vertices[3 * i + 2]);
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
          const size_t n = size_t(c.normal_index);
          normals[tri[k]] = Vec3(attrib.normals[3 * n], attrib.normals[3 * n + 1],
                                 attrib.normals[3 * n + 2]);
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

}  // namespace frameless
