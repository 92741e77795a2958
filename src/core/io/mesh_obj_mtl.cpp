// OBJ with MTL materials: the MTL libraries are read by a parser of our own (every error names
// its file and line; names and texture paths may hold spaces; '\' separators and options such
// as -bm, -s, -o, -clamp) and mapped onto Parker's material classes.
//
// MTL -> Parker's classes, first rule that matches (Kd, Ks clamped to [0, 1]; Kd defaults to 1
// when only map_Kd is given, else 0.8; "Ks bright" is max(Ks) >= 0.1 or a map_Ks):
//   dielectric  illum 4, 6, 7 or 9; or Tf given with some component < 1 (Tf 0 0 0, which
//               exporters write for "no filter", is ignored); or d < 1 with Ni > 1 and no map_d.
//               ior = Ni when Ni > 1, else 1.5; extinction = -ln(Tf) per scene unit and channel
//               (Tf clamped to [1e-4, 1]; none without Tf); kh = Ks, kh_tex = map_Ks.
//   metal       Kd black (max < 0.01, no map_Kd) and Ks bright, illum not 0 or 1:
//               ks = kh = Ks, ks_tex = kh_tex = map_Ks.
//   polished    Ks non-black (max > 0.01 or map_Ks) and illum 3 or 5 (ray-traced reflection):
//               kd = Kd, r0 = Ks (the mirror term the illum model asks for), kh = Ks.
//   polished    Ks non-black and illum not 0 or 1: kd = Kd, kh = Ks, r0 = 0.08 * Ks (Ks 0.5,
//               the common exporter default, gives the 0.04 of an n = 1.5 coat).
//   diffuse     otherwise (illum 0 and 1 switch highlights off): kd = Kd.
// All classes: phong_exponent = Ns clamped to [1, 10000]; map_Kd -> kd_tex (sRGB; diffuse and
// polished only); map_d -> alpha_tex (linear; channel: the image's alpha when it has one, else
// its first channel; -imfchan r/g/b/m picks one); bump, map_bump, map_Bump -> bump_tex (linear,
// bump_scale = -bm); norm -> normal_tex (linear); Ke -> emission (>= 0, an error otherwise),
// map_Ke -> emission_tex (sRGB). Not dielectric: opacity = d (or 1 - Tr when d
// is absent; Tr 1 alone is read as opaque, the inverted convention some exporters use).
// Texture options: -s u v -> uv_scale, -o u v -> uv_offset, -clamp on -> clamp wrap; others
// (-blendu, -boost, -mm, -t, -texres, -type, -colorspace, -cc) are read and ignored.
// Ka, map_Ka, disp, decal, refl and PBR extensions are ignored.
// Files: mtllib relative to the OBJ's folder, textures relative to the MTL's folder; when the
// exact path is missing each component is matched case-insensitively, then the bare file name
// is tried in that folder (Windows absolute paths). Faces before any usemtl, or naming a material
// no library defines, get a default diffuse material.
#include <algorithm>
#include <charconv>
#include <cmath>
#include <filesystem>
#include <optional>
#include <string_view>
#include <unordered_map>

#include "core/io/file_util.h"
#include "core/io/mesh_obj.h"
#include "core/io/text_tokens.h"
#include "core/scene/scene_build.h"

namespace frameless {
namespace {

namespace fs = std::filesystem;

// One texture statement (map_Kd, bump, ...): file name as written and the options we honour.
struct MtlMap {
  bool present = false;
  size_t line = 0;
  std::string key;
  std::string file;
  TextureWrap wrap = TextureWrap::kRepeat;
  Vec2 scale{1.0f};
  Vec2 offset{0.0f};
  float bump = 1.0f;
  char channel = 0;  // -imfchan, 0 when absent
};

struct MtlMaterial {
  std::string name;
  std::string mtl_path;
  Vec3 kd{0.8f}, ks{0.0f}, tf{1.0f}, ke{0.0f};
  float ns = 0.0f, ni = 0.0f, d = 1.0f, tr = 0.0f;
  int illum = -1;
  bool has_kd = false, has_tf = false, has_ni = false, has_d = false, has_tr = false;
  bool has_ke = false;
  MtlMap map_kd, map_ks, map_d, bump, norm, map_ke;
};

std::string lower(std::string_view s) {
  std::string out(s);
  for (char& c : out) c = char(std::tolower(static_cast<unsigned char>(c)));
  return out;
}

// "'tok' is not ...", built by appending (g++ 12 warns falsely on "'" + std::string + "'").
std::string bad_token(std::string_view tok, const char* what) {
  std::string s(1, '\'');
  s.append(tok.substr(0, 32));
  s += "' is not ";
  s += what;
  return s;
}

// Reads up to `most` leading tokens that are finite numbers; stops before the first that is not.
int read_numbers(std::string_view& rest, float* out, int most) {
  int n = 0;
  while (n < most) {
    std::string_view probe = rest;
    float x;
    if (!parse_finite(next_token(probe), x)) break;
    out[n++] = x;
    rest = probe;
  }
  return n;
}

std::string folder_of(const std::string& path) {
  const size_t slash = path.find_last_of('/');
  if (slash == std::string::npos) return ".";
  return slash == 0 ? "/" : path.substr(0, slash);
}

// Walks rel below base, taking each component exactly when it exists, else the first entry of
// that folder whose name matches it case-insensitively.
std::optional<std::string> walk(fs::path cur, std::string_view rel) {
  std::error_code ec;
  while (!rel.empty()) {
    const size_t slash = rel.find('/');
    const std::string part(rel.substr(0, slash));
    rel = slash == std::string_view::npos ? std::string_view() : rel.substr(slash + 1);
    if (part.empty() || part == ".") continue;
    if (part == ".." || fs::exists(cur / part, ec)) {
      cur /= part;
      continue;
    }
    const std::string want = lower(part);
    bool found = false;
    for (fs::directory_iterator it(cur, ec), end; !ec && it != end; it.increment(ec))
      if (lower(it->path().filename().string()) == want) {
        cur = it->path();
        found = true;
        break;
      }
    if (!found) return std::nullopt;
  }
  if (!fs::is_regular_file(cur, ec)) return std::nullopt;
  return cur.string();
}

// Finds a file named in an OBJ/MTL: relative to dir unless absolute, '\' read as '/'; exact,
// then case-insensitive, then the bare file name in dir.
std::optional<std::string> find_file(const std::string& dir, std::string name) {
  std::replace(name.begin(), name.end(), '\\', '/');
  if (name.empty()) return std::nullopt;
  std::error_code ec;
  const bool absolute = name[0] == '/';
  const std::string direct = absolute ? name : dir + "/" + name;
  if (fs::is_regular_file(direct, ec)) return direct;
  if (auto found = absolute ? walk("/", name) : walk(dir, name)) return found;
  const size_t slash = name.find_last_of('/');
  if (slash != std::string::npos) return walk(dir, std::string_view(name).substr(slash + 1));
  return std::nullopt;
}

// Reads "Kd r [g b]", "Kd xyz x y z" (taken as RGB); "spectral" curves are ignored.
std::optional<std::string> read_color(std::string_view rest, Vec3& out, bool& has) {
  std::string_view probe = rest;
  const std::string_view first = next_token(probe);
  if (first == "spectral") return std::nullopt;
  if (first == "xyz") rest = probe;
  float c[3];
  const int n = read_numbers(rest, c, 3);
  const std::string_view bad = next_token(rest);
  if (!bad.empty()) return bad_token(bad, "a finite number");
  if (n != 1 && n != 3) return std::string("expected 1 or 3 numbers");
  out = n == 1 ? Vec3(c[0]) : Vec3(c[0], c[1], c[2]);
  has = true;
  return std::nullopt;
}

std::optional<std::string> read_scalar(std::string_view rest, float& out, bool& has) {
  std::string_view probe = rest;
  if (next_token(probe) == "-halo") rest = probe;  // d -halo f: read as plain d
  const std::string_view tok = next_token(rest);
  if (tok.empty()) return std::string("expected a number");
  if (!parse_finite(tok, out)) return bad_token(tok, "a finite number");
  has = true;
  return std::nullopt;
}

// Options, then the file name: the rest of the line, so names may hold spaces.
std::optional<std::string> read_map(std::string_view rest, MtlMap& map) {
  for (;;) {
    std::string_view probe = rest;
    const std::string_view opt = next_token(probe);
    float v[3];
    int most = 0;  // numeric arguments the option takes (1..most); 0: one word
    if (opt == "-bm" || opt == "-boost" || opt == "-texres") most = 1;
    else if (opt == "-mm") most = 2;
    else if (opt == "-s" || opt == "-o" || opt == "-t") most = 3;
    else if (opt != "-blendu" && opt != "-blendv" && opt != "-cc" && opt != "-clamp" &&
             opt != "-imfchan" && opt != "-type" && opt != "-colorspace")
      break;  // not an option: the file name starts here
    rest = probe;
    if (most == 0) {
      const std::string_view word = next_token(rest);
      if (word.empty()) return std::string(opt) + ": missing value";
      if (opt == "-clamp") map.wrap = word == "on" ? TextureWrap::kClamp : TextureWrap::kRepeat;
      if (opt == "-imfchan") map.channel = char(std::tolower(static_cast<unsigned char>(word[0])));
      continue;
    }
    const int n = read_numbers(rest, v, most);
    if (n == 0) return std::string(opt) + ": expected a number";
    if (opt == "-bm") map.bump = v[0];
    if (opt == "-s") map.scale = Vec2(v[0], n > 1 ? v[1] : 1.0f);
    if (opt == "-o") map.offset = Vec2(v[0], n > 1 ? v[1] : 0.0f);
  }
  map.file = std::string(trim(rest));
  if (map.file.empty()) return std::string("missing file name");
  map.present = true;
  return std::nullopt;
}

Result<std::vector<MtlMaterial>> parse_mtl(const std::string& text, const std::string& path) {
  std::vector<MtlMaterial> out;
  size_t line_no = 0;
  for (size_t pos = 0; pos < text.size();) {
    size_t end = text.find('\n', pos);
    if (end == std::string::npos) end = text.size();
    ++line_no;
    std::string_view line(text.data() + pos, end - pos);
    pos = end + 1;
    const std::string where = path + ":" + std::to_string(line_no) + ": ";
    if (line.find('\0') != std::string_view::npos) return Error{where + "NUL byte in a text file"};
    const std::string_view key_tok = next_token(line);
    const std::string key = lower(key_tok);
    if (key == "newmtl") {
      out.emplace_back();
      out.back().name = std::string(trim(line));
      out.back().mtl_path = path;
      continue;
    }
    if (out.empty()) continue;  // statements before the first newmtl describe nothing
    MtlMaterial& m = out.back();
    std::optional<std::string> err;
    MtlMap* map = nullptr;
    bool dummy = false;
    if (key == "kd") err = read_color(line, m.kd, m.has_kd);
    else if (key == "ks") err = read_color(line, m.ks, dummy);
    else if (key == "tf") err = read_color(line, m.tf, m.has_tf);
    else if (key == "ke") {
      err = read_color(line, m.ke, m.has_ke);
      if (!err && std::min({m.ke.x, m.ke.y, m.ke.z}) < 0.0f)
        err = std::string("emission must be >= 0");
    }
    else if (key == "ns") err = read_scalar(line, m.ns, dummy);
    else if (key == "ni") err = read_scalar(line, m.ni, m.has_ni);
    else if (key == "d") err = read_scalar(line, m.d, m.has_d);
    else if (key == "tr") err = read_scalar(line, m.tr, m.has_tr);
    else if (key == "illum") {
      const std::string_view tok = next_token(line);
      const auto r = std::from_chars(tok.data(), tok.data() + tok.size(), m.illum);
      if (tok.empty() || r.ec != std::errc() || r.ptr != tok.data() + tok.size())
        err = bad_token(tok, "an integer");
    } else if (key == "map_kd") map = &m.map_kd;
    else if (key == "map_ks") map = &m.map_ks;
    else if (key == "map_d") map = &m.map_d;
    else if (key == "bump" || key == "map_bump") map = &m.bump;
    else if (key == "norm") map = &m.norm;
    else if (key == "map_ke") map = &m.map_ke;
    if (map) {
      *map = MtlMap{};
      map->line = line_no;
      map->key = std::string(key_tok);
      err = read_map(line, *map);
    }
    if (err) return Error{where + std::string(key_tok) + ": " + *err};
  }
  return out;
}

Vec3 clamp01(const Vec3& v) { return glm::clamp(v, Vec3(0.0f), Vec3(1.0f)); }

// Loads one texture statement's image (shared through the cache); returns its slot in
// mesh.textures, reusing an identical texture.
Result<uint32_t> add_texture(MeshData& mesh, ImageCache& images, const MtlMaterial& m,
                             const MtlMap& map, bool srgb) {
  const std::string where = m.mtl_path + ":" + std::to_string(map.line) + ": " + map.key + ": ";
  const auto file = find_file(folder_of(m.mtl_path), map.file);
  if (!file) return Error{where + "cannot open '" + map.file + "'"};
  auto image = images.get(*file);
  if (!image) return Error{where + image.error().message};
  Texture t;
  t.kind = TextureKind::kImage;
  t.image = *image;
  t.wrap = map.wrap;
  t.srgb = srgb;
  t.uv_scale = map.scale;
  t.uv_offset = map.offset;
  for (size_t i = 0; i < mesh.textures.size(); ++i) {
    const Texture& o = mesh.textures[i];
    if (o.image == t.image && o.srgb == srgb && o.wrap == t.wrap && o.uv_scale == t.uv_scale &&
        o.uv_offset == t.uv_offset)
      return uint32_t(i);
  }
  mesh.textures.push_back(std::move(t));
  return uint32_t(mesh.textures.size() - 1);
}

// Applies the mapping in the comment at the top of this file.
Result<Material> to_material(const MtlMaterial& m, MeshData& mesh, ImageCache& images) {
  Material out;
  out.name = m.name;
  const Vec3 kd = clamp01(m.has_kd ? m.kd : m.map_kd.present ? Vec3(1.0f) : Vec3(0.8f));
  const Vec3 ks = clamp01(m.ks);
  const float d_raw = m.has_d ? m.d : m.has_tr && m.tr < 1.0f ? 1.0f - m.tr : 1.0f;
  const float d = std::clamp(d_raw, 0.0f, 1.0f);
  const float tf_min = std::min({m.tf.x, m.tf.y, m.tf.z});
  const bool filter = m.has_tf && tf_min < 1.0f && max_component(m.tf) > 0.0f;
  const bool highlights = m.illum != 0 && m.illum != 1;
  const bool ks_on = max_component(ks) > 0.01f || m.map_ks.present;
  const bool ks_bright = max_component(ks) >= 0.1f || m.map_ks.present;
  const bool kd_black = max_component(kd) < 0.01f && !m.map_kd.present;
  const int il = m.illum;
  out.phong_exponent = std::clamp(m.ns, 1.0f, 10000.0f);
  out.kh = ks;
  if (il == 4 || il == 6 || il == 7 || il == 9 || filter ||
      (d < 1.0f && m.has_ni && m.ni > 1.0f && !m.map_d.present)) {
    out.cls = MaterialClass::kDielectric;
    out.ior = m.has_ni && m.ni > 1.0f ? m.ni : 1.5f;
    if (filter) out.extinction = -glm::log(glm::clamp(m.tf, Vec3(1e-4f), Vec3(1.0f)));
  } else if (kd_black && ks_bright && highlights) {
    out.cls = MaterialClass::kMetal;
    out.ks = ks;
  } else if (ks_on && (il == 3 || il == 5)) {
    out.cls = MaterialClass::kPolished;
    out.kd = kd;
    out.r0 = ks;
  } else if (ks_on && highlights) {
    out.cls = MaterialClass::kPolished;
    out.kd = kd;
    out.r0 = 0.08f * ks;
  } else {
    out.cls = MaterialClass::kDiffuse;
    out.kd = kd;
    out.kh = Vec3(0.0f);
  }
  if (out.cls != MaterialClass::kDielectric) out.opacity = d;
  const bool uses_kd = out.cls == MaterialClass::kDiffuse || out.cls == MaterialClass::kPolished;
  const bool uses_kh = out.cls != MaterialClass::kDiffuse;
  auto slot = [&](const MtlMap& map, bool srgb, uint32_t& dst) -> std::optional<Error> {
    if (!map.present) return std::nullopt;
    auto t = add_texture(mesh, images, m, map, srgb);
    if (!t) return t.error();
    dst = *t;
    return std::nullopt;
  };
  if (uses_kd)
    if (auto e = slot(m.map_kd, true, out.kd_tex)) return *e;
  if (uses_kh)
    if (auto e = slot(m.map_ks, true, out.kh_tex)) return *e;
  if (out.cls == MaterialClass::kMetal) out.ks_tex = out.kh_tex;
  if (auto e = slot(m.map_d, false, out.alpha_tex)) return *e;
  if (out.alpha_tex != kNoTexture) {
    const bool alpha = mesh.textures[out.alpha_tex].image->has_alpha();
    const char c = m.map_d.channel;
    out.alpha_channel = c == 'g' ? 1 : c == 'b' ? 2 : (c == 'm' || c == 0) && alpha ? 3 : 0;
  }
  if (auto e = slot(m.bump, false, out.bump_tex)) return *e;
  out.bump_scale = m.bump.bump;
  if (auto e = slot(m.norm, false, out.normal_tex)) return *e;
  // Ke: emitted radiance, any class (1 under a map_Ke without Ke, as Kd under map_Kd).
  out.emission = m.has_ke ? m.ke : m.map_ke.present ? Vec3(1.0f) : Vec3(0.0f);
  if (auto e = slot(m.map_ke, true, out.emission_tex)) return *e;
  return out;
}

Material default_material(const std::string& name) {
  Material m;
  m.name = name;
  m.cls = MaterialClass::kDiffuse;
  m.kd = Vec3(0.75f, 0.72f, 0.68f);
  return m;
}

// The MTL files one mtllib line names: the whole rest of the line when it is one file (names
// with spaces), else its space-separated names. Errors name the whole line until one resolves.
Result<std::vector<std::string>> library_files(const ObjScan::Library& lib, const std::string& dir,
                                               const std::string& path) {
  if (auto whole = find_file(dir, lib.names)) return std::vector<std::string>{*whole};
  std::vector<std::string> files;
  std::string_view rest = lib.names;
  for (std::string_view tok = next_token(rest); !tok.empty(); tok = next_token(rest)) {
    auto file = find_file(dir, std::string(tok));
    if (!file)
      return Error{path + ":" + std::to_string(lib.line) + ": mtllib: cannot open '" +
                   (files.empty() ? lib.names : std::string(tok)) + "'"};
    files.push_back(*file);
  }
  return files;
}

}  // namespace

Result<MeshData> parse_obj_with_materials(const std::string& text, const std::string& path,
                                          ImageCache& images) {
  auto scan = scan_obj(text, path);
  if (!scan) return scan.error();
  if (scan->libraries.empty()) return build_obj_mesh(*scan, path, false);
  // Every library is read, even one no face uses: a missing file is an error either way.
  std::vector<MtlMaterial> defs;
  std::vector<std::string> read;
  const std::string dir = folder_of(path);
  for (const ObjScan::Library& lib : scan->libraries) {
    auto files = library_files(lib, dir, path);
    if (!files) return files.error();
    for (const std::string& file : *files) {
      if (std::find(read.begin(), read.end(), file) != read.end()) continue;
      read.push_back(file);
      auto bytes = read_file_bytes(file);
      if (!bytes) return bytes.error();
      auto mtl = parse_mtl(*bytes, file);
      if (!mtl) return mtl.error();
      defs.insert(defs.end(), mtl->begin(), mtl->end());
    }
  }
  std::unordered_map<std::string, size_t> def_of;  // the first definition of a name wins
  for (size_t i = 0; i < defs.size(); ++i) def_of.emplace(defs[i].name, i);

  auto mesh = build_obj_mesh(*scan, path, true);
  if (!mesh) return mesh.error();
  // Materials in order of first use by a face; usemtl names no face uses are left out.
  const size_t none = scan->materials.size();
  std::vector<uint16_t> remap(none + 1, kNoObjMaterial);
  for (uint16_t& fm : mesh->face_material) {
    const size_t k = fm == kNoObjMaterial ? none : size_t(fm);
    if (remap[k] == kNoObjMaterial) {
      remap[k] = uint16_t(mesh->materials.size());
      const std::string name = k == none ? "default" : scan->materials[k];
      const auto it = k == none ? def_of.end() : def_of.find(name);
      if (it == def_of.end()) {
        mesh->materials.push_back(default_material(name));
      } else {
        auto mat = to_material(defs[it->second], *mesh, images);
        if (!mat) return mat.error();
        mesh->materials.push_back(std::move(*mat));
      }
    }
    fm = remap[k];
  }
  return mesh;
}

Result<MeshData> load_obj_with_materials(const std::string& path, ImageCache& images) {
  auto bytes = read_file_bytes(path);
  if (!bytes) return Error{one_line(bytes.error().message)};
  // File names from the OBJ and MTL appear in errors: keep them on one line.
  return one_line(parse_obj_with_materials(*bytes, path, images));
}

}  // namespace frameless
