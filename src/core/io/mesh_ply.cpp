// PLY input: ascii, binary little and big endian. Vertex x, y, z (+ optional nx, ny, nz and u v,
// s t or texture_u texture_v), face
// vertex_indices lists of any integer types, polygons triangulated as fans. Counts in the header
// are never trusted for allocation: every read is checked against the bytes actually present.
#include <bit>
#include <charconv>
#include <cmath>
#include <cstring>
#include <optional>
#include <string_view>

#include "core/io/mesh_readers.h"
#include "core/io/text_tokens.h"

namespace frameless {
namespace {

enum class Type : uint8_t { kInt8, kUint8, kInt16, kUint16, kInt32, kUint32, kFloat32, kFloat64 };

std::optional<Type> type_from_name(std::string_view s) {
  if (s == "char" || s == "int8") return Type::kInt8;
  if (s == "uchar" || s == "uint8") return Type::kUint8;
  if (s == "short" || s == "int16") return Type::kInt16;
  if (s == "ushort" || s == "uint16") return Type::kUint16;
  if (s == "int" || s == "int32") return Type::kInt32;
  if (s == "uint" || s == "uint32") return Type::kUint32;
  if (s == "float" || s == "float32") return Type::kFloat32;
  if (s == "double" || s == "float64") return Type::kFloat64;
  return std::nullopt;
}

size_t type_size(Type t) {
  switch (t) {
    case Type::kInt8: case Type::kUint8: return 1;
    case Type::kInt16: case Type::kUint16: return 2;
    case Type::kInt32: case Type::kUint32: case Type::kFloat32: return 4;
    case Type::kFloat64: return 8;
  }
  return 1;
}

bool is_integer(Type t) { return t != Type::kFloat32 && t != Type::kFloat64; }

struct Property {
  std::string name;
  Type type = Type::kFloat32;
  bool is_list = false;
  Type count_type = Type::kUint8;
};

struct Element {
  std::string name;
  uint64_t count = 0;
  size_t header_line = 0;
  std::vector<Property> props;
};

enum class Format : uint8_t { kAscii, kLittle, kBig };

std::string shown(std::string_view s) {
  // Built by append: GCC 12 warns falsely (-Wrestrict) on "'" + std::string.
  std::string out(1, '\'');
  out.append(s.substr(0, 32));
  out.push_back('\'');
  return out;
}

// Reads one value of type t from the body, ascii or binary, as a double. Every failure sets a
// message and returns false; the caller adds file and position.
class BodyReader {
 public:
  BodyReader(const std::string& bytes, size_t pos, Format format, size_t first_line)
      : bytes_(bytes), pos_(pos), format_(format), line_(first_line) {}

  // ascii: moves to the next non-empty line; binary: no-op.
  bool begin_record() {
    if (format_ != Format::kAscii) return true;
    while (pos_ < bytes_.size()) {
      size_t end = bytes_.find('\n', pos_);
      if (end == std::string::npos) end = bytes_.size();
      line_text_ = std::string_view(bytes_.data() + pos_, end - pos_);
      pos_ = end + 1;
      ++line_;
      std::string_view probe = line_text_;
      if (!next_token(probe).empty()) return true;
    }
    error_ = "unexpected end of file";
    return false;
  }
  bool end_record() {
    if (format_ != Format::kAscii) return true;
    if (!next_token(line_text_).empty()) {
      error_ = "extra values at end of line";
      return false;
    }
    return true;
  }

  bool read(Type t, double& out) {
    if (format_ == Format::kAscii) return read_ascii(t, out);
    const size_t n = type_size(t);
    if (bytes_.size() - pos_ < n) {
      error_ = "truncated binary data";
      return false;
    }
    unsigned char b[8];
    std::memcpy(b, bytes_.data() + pos_, n);
    pos_ += n;
    const bool swap = (format_ == Format::kBig) == (std::endian::native == std::endian::little);
    if (swap)
      for (size_t i = 0; i < n / 2; ++i) std::swap(b[i], b[n - 1 - i]);
    switch (t) {
      case Type::kInt8: { int8_t v; std::memcpy(&v, b, 1); out = v; break; }
      case Type::kUint8: out = b[0]; break;
      case Type::kInt16: { int16_t v; std::memcpy(&v, b, 2); out = v; break; }
      case Type::kUint16: { uint16_t v; std::memcpy(&v, b, 2); out = v; break; }
      case Type::kInt32: { int32_t v; std::memcpy(&v, b, 4); out = v; break; }
      case Type::kUint32: { uint32_t v; std::memcpy(&v, b, 4); out = v; break; }
      case Type::kFloat32: { float v; std::memcpy(&v, b, 4); out = v; break; }
      case Type::kFloat64: std::memcpy(&out, b, 8); break;
    }
    return true;
  }

  // Bytes left: a bound on how many more values can possibly follow.
  size_t remaining() const { return bytes_.size() - std::min(pos_, bytes_.size()); }
  // Most list items that can still follow in this record (each takes at least one byte).
  size_t list_bound() const { return format_ == Format::kAscii ? line_text_.size() : remaining(); }
  bool binary() const { return format_ != Format::kAscii; }
  size_t line() const { return line_; }
  size_t offset() const { return pos_; }
  const std::string& error() const { return error_; }

 private:
  bool read_ascii(Type t, double& out) {
    const std::string_view tok = next_token(line_text_);
    if (tok.empty()) {
      error_ = "too few values on the line";
      return false;
    }
    const char* end = tok.data() + tok.size();
    std::from_chars_result r;
    if (is_integer(t)) {
      long long v = 0;
      r = std::from_chars(tok.data(), end, v);
      out = double(v);
    } else {
      std::string_view s = tok;
      if (s[0] == '+') s.remove_prefix(1);
      r = std::from_chars(s.data(), end, out);
    }
    if (r.ec != std::errc() || r.ptr != end) {
      error_ = shown(tok) + " is not a valid " + (is_integer(t) ? "integer" : "number");
      return false;
    }
    return true;
  }

  const std::string& bytes_;
  size_t pos_;
  Format format_;
  size_t line_;
  std::string_view line_text_;
  std::string error_;
};

struct Header {
  Format format = Format::kAscii;
  std::vector<Element> elements;
  size_t body = 0;        // byte offset of the first body byte
  size_t body_line = 0;   // line number of end_header
};

Result<Header> parse_header(const std::string& bytes, const std::string& path) {
  Header h;
  size_t pos = 0, line_no = 0;
  bool have_format = false;
  auto fail = [&](const std::string& what) {
    return Error{path + ":" + std::to_string(line_no) + ": " + what};
  };
  constexpr size_t kMaxHeader = 1 << 20;  // a header longer than this is not a mesh header
  while (true) {
    if (pos >= bytes.size() || pos > kMaxHeader) {
      ++line_no;
      return fail("bad PLY header: no end_header");
    }
    size_t end = bytes.find('\n', pos);
    if (end == std::string::npos) end = bytes.size();
    std::string_view line(bytes.data() + pos, end - pos);
    pos = end + 1;
    ++line_no;
    if (!line.empty() && line.back() == '\r') line.remove_suffix(1);
    if (line_no == 1) {
      if (line != "ply") return fail("bad PLY header: file does not start with 'ply'");
      continue;
    }
    std::string_view rest = line;
    const std::string_view key = next_token(rest);
    if (key.empty() || key == "comment" || key == "obj_info") continue;
    if (key == "end_header") break;
    if (key == "format") {
      const std::string_view f = next_token(rest), v = next_token(rest);
      if (f == "ascii") h.format = Format::kAscii;
      else if (f == "binary_little_endian") h.format = Format::kLittle;
      else if (f == "binary_big_endian") h.format = Format::kBig;
      else return fail("bad PLY header: format: unknown format " + shown(f));
      if (v != "1.0") return fail("bad PLY header: format: unsupported version " + shown(v));
      have_format = true;
    } else if (key == "element") {
      Element e;
      e.name = std::string(next_token(rest));
      const std::string_view c = next_token(rest);
      const auto r = std::from_chars(c.data(), c.data() + c.size(), e.count);
      if (e.name.empty() || c.empty() || r.ec != std::errc() || r.ptr != c.data() + c.size())
        return fail("bad PLY header: element: expected 'element NAME COUNT'");
      e.header_line = line_no;
      h.elements.push_back(std::move(e));
    } else if (key == "property") {
      if (h.elements.empty()) return fail("bad PLY header: property before any element");
      Property p;
      std::string_view t = next_token(rest);
      if (t == "list") {
        p.is_list = true;
        const std::string_view ct = next_token(rest);
        const auto count_type = type_from_name(ct);
        if (!count_type || !is_integer(*count_type))
          return fail("bad PLY header: property: list count type " + shown(ct) +
                      " is not an integer type");
        p.count_type = *count_type;
        t = next_token(rest);
      }
      const auto type = type_from_name(t);
      if (!type) return fail("bad PLY header: property: unknown type " + shown(t));
      p.type = *type;
      p.name = std::string(next_token(rest));
      if (p.name.empty()) return fail("bad PLY header: property: missing name");
      h.elements.back().props.push_back(std::move(p));
    } else {
      return fail("bad PLY header: unknown keyword " + shown(key));
    }
  }
  if (!have_format) return fail("bad PLY header: no format line");
  h.body = pos;
  h.body_line = line_no;
  return h;
}

}  // namespace

Result<MeshData> parse_ply(const std::string& bytes, const std::string& path) {
  auto header = parse_header(bytes, path);
  if (!header) return header.error();
  const Header& h = *header;
  BodyReader in(bytes, std::min(h.body, bytes.size()), h.format, h.body_line);
  MeshData mesh;
  uint64_t vertex_count = 0;
  bool have_vertices = false, have_faces = false;
  for (const Element& e : h.elements)
    if (e.name == "vertex") vertex_count = e.count, have_vertices = true;
  if (vertex_count > 0xfffffff0u) return Error{path + ": too many vertices"};
  auto header_error = [&](const Element& e, const std::string& what) {
    return Error{path + ":" + std::to_string(e.header_line) + ": element " + e.name + ": " + what};
  };

  for (const Element& e : h.elements) {
    int xyz[3] = {-1, -1, -1}, nxyz[3] = {-1, -1, -1}, uv[2] = {-1, -1}, indices = -1;
    for (size_t i = 0; i < e.props.size(); ++i) {
      const Property& p = e.props[i];
      static const char* kAxes[3] = {"x", "y", "z"};
      static const char* kNormals[3] = {"nx", "ny", "nz"};
      for (int k = 0; k < 3; ++k) {
        if (p.name == kAxes[k]) xyz[k] = int(i);
        if (p.name == kNormals[k]) nxyz[k] = int(i);
      }
      if (p.name == "vertex_indices" || p.name == "vertex_index") indices = int(i);
      // Texture coordinates go by several names in the wild.
      if (p.name == "u" || p.name == "s" || p.name == "texture_u" || p.name == "texture_s") uv[0] = int(i);
      if (p.name == "v" || p.name == "t" || p.name == "texture_v" || p.name == "texture_t") uv[1] = int(i);
    }
    const bool is_vertex = e.name == "vertex", is_face = e.name == "face";
    if (is_vertex) {
      if (xyz[0] < 0 || xyz[1] < 0 || xyz[2] < 0)
        return header_error(e, "needs properties x, y and z");
      for (int k = 0; k < 3; ++k)
        if (e.props[size_t(xyz[k])].is_list) return header_error(e, "x, y, z must not be lists");
    }
    const bool with_normals = is_vertex && nxyz[0] >= 0 && nxyz[1] >= 0 && nxyz[2] >= 0;
    const bool with_uvs = is_vertex && uv[0] >= 0 && uv[1] >= 0 &&
                          !e.props[size_t(uv[0])].is_list && !e.props[size_t(uv[1])].is_list;
    if (is_face) {
      if (indices < 0) return header_error(e, "needs a list property vertex_indices");
      const Property& p = e.props[size_t(indices)];
      if (!p.is_list || !is_integer(p.type))
        return header_error(e, "vertex_indices must be a list of integers");
      have_faces = true;
    }
    // An element without properties has no data to read, whatever its count says.
    if (e.props.empty()) continue;
    // Every record takes at least one byte, so a count beyond the bytes left is a lie: fail
    // before allocating anything.
    if (e.count > in.remaining())
      return Error{path + ":" + std::to_string(e.header_line) + ": element " + e.name +
                   ": header claims " + std::to_string(e.count) + " records but only " +
                   std::to_string(in.remaining()) + " bytes follow (truncated file?)"};
    if (is_vertex) {
      mesh.positions.reserve(size_t(e.count));
      if (with_normals) mesh.normals.reserve(size_t(e.count));
      if (with_uvs) mesh.uvs.reserve(size_t(e.count));
    }
    std::vector<double> list;
    for (uint64_t r = 0; r < e.count; ++r) {
      auto body_error = [&](const std::string& what) {
        const std::string where = in.binary() ? std::to_string(e.header_line) + ": " + e.name +
                                                    " " + std::to_string(r) + " (byte " +
                                                    std::to_string(in.offset()) + ")"
                                              : std::to_string(in.line()) + ": " + e.name + " " +
                                                    std::to_string(r);
        return Error{path + ":" + where + ": " + what};
      };
      if (!in.begin_record()) return body_error(in.error());
      double vals[8] = {0, 0, 0, 0, 0, 0, 0, 0};
      for (size_t i = 0; i < e.props.size(); ++i) {
        const Property& p = e.props[i];
        if (!p.is_list) {
          double v;
          if (!in.read(p.type, v)) return body_error(in.error());
          for (int k = 0; k < 3; ++k) {
            if (int(i) == xyz[k]) vals[k] = v;
            if (int(i) == nxyz[k]) vals[3 + k] = v;
          }
          if (int(i) == uv[0]) vals[6] = v;
          if (int(i) == uv[1]) vals[7] = v;
          continue;
        }
        double count;
        if (!in.read(p.count_type, count)) return body_error(in.error());
        if (count < 0) return body_error(p.name + ": negative list length");
        // Each item needs at least one byte: bounds the loop on a lying count.
        if (count > double(in.list_bound()))
          return body_error(p.name + ": list length " + std::to_string(uint64_t(count)) +
                            " exceeds the data left (truncated file?)");
        const bool keep = is_face && int(i) == indices;
        list.clear();
        for (uint64_t k = 0; k < uint64_t(count); ++k) {
          double v;
          if (!in.read(p.type, v)) return body_error(in.error());
          if (keep) list.push_back(v);
        }
        if (!keep) continue;
        if (list.size() < 3)
          return body_error("a face needs at least 3 vertices, got " + std::to_string(list.size()));
        for (double v : list)
          if (v < 0 || v >= double(vertex_count))
            return body_error("vertex index " + std::to_string(int64_t(v)) +
                              " out of range (0.." +
                              std::to_string(int64_t(vertex_count) - 1) + ")");
        for (size_t k = 1; k + 1 < list.size(); ++k)
          mesh.triangles.push_back(UVec3(uint32_t(list[0]), uint32_t(list[k]), uint32_t(list[k + 1])));
      }
      if (!in.end_record()) return body_error(in.error());
      if (is_vertex) {
        for (int k = 0; k < (with_normals ? 6 : 3); ++k)
          if (!std::isfinite(vals[k]) || std::fabs(vals[k]) > 3.0e38)
            return body_error(std::string(k < 3 ? "position" : "normal") +
                              " is not a finite number");
        mesh.positions.push_back(Vec3(float(vals[0]), float(vals[1]), float(vals[2])));
        if (with_normals) mesh.normals.push_back(Vec3(float(vals[3]), float(vals[4]), float(vals[5])));
        if (with_uvs) {
          if (!std::isfinite(vals[6]) || !std::isfinite(vals[7]) || std::fabs(vals[6]) > 3.0e38 ||
              std::fabs(vals[7]) > 3.0e38)
            return body_error("texture coordinate is not a finite number");
          mesh.uvs.push_back(Vec2(float(vals[6]), float(vals[7])));
        }
      }
    }
  }
  if (!have_vertices || !have_faces || mesh.triangles.empty())
    return Error{path + ": empty mesh (no " + std::string(have_vertices ? "faces" : "vertices") +
                 ")"};
  // Zero-length normals cannot shade: drop them all rather than mix.
  for (const Vec3& n : mesh.normals)
    if (glm::dot(n, n) == 0.0f) {
      mesh.normals.clear();
      break;
    }
  return mesh;
}

}  // namespace frameless
