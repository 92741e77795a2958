// glTF input, what is settled before tinygltf sees the bytes: tinygltf 2.7 reads up to 8 bytes
// past a GLB whose BIN chunk header overruns the file, recurses once per JSON nesting level
// (extras) and silently ignores members of the wrong type, so each of those becomes a one-line
// error here; and its file access is narrowed to the model's buffer files.
#include <cerrno>
#include <cstdio>
#include <cstring>
#include <string_view>

#include <nlohmann/json.hpp>

#include "core/io/file_util.h"
#include "core/io/gltf_internal.h"
#include "core/scene/scene_build.h"

namespace frameless::gltf {
namespace {

using json = nlohmann::json;

constexpr int kMaxJsonDepth = 64;  // glTF itself needs about 8 levels

uint32_t read_u32(const std::string& b, size_t at) {
  return uint32_t(uint8_t(b[at])) | uint32_t(uint8_t(b[at + 1])) << 8 |
         uint32_t(uint8_t(b[at + 2])) << 16 | uint32_t(uint8_t(b[at + 3])) << 24;
}

// Deepest [ / { nesting outside strings: a byte scan, before any parser recurses.
int json_depth(std::string_view text) {
  int depth = 0, deepest = 0;
  bool in_string = false;
  for (size_t i = 0; i < text.size(); ++i) {
    const char c = text[i];
    if (in_string) {
      if (c == '\\')
        ++i;
      else if (c == '"')
        in_string = false;
    } else if (c == '"') {
      in_string = true;
    } else if (c == '[' || c == '{') {
      deepest = std::max(deepest, ++depth);
    } else if (c == ']' || c == '}') {
      --depth;
    }
  }
  return deepest;
}

// What a member must hold. Members we never read are not checked.
enum class Want : uint8_t {
  kSkip,
  kString,
  kIndex,
  kNumber,
  kBool,
  kObject,
  kNumbers,
  kIndices,
  kStrings,
  kObjects,
  kNumberOrNumbers,
  kAttributes,
  kExtensions
};

bool one_of(std::string_view key, std::initializer_list<std::string_view> names) {
  for (std::string_view n : names)
    if (key == n) return true;
  return false;
}

Want want_for(std::string_view key, int level) {
  if (key == "nodes") return level == 0 ? Want::kObjects : Want::kIndices;
  if (one_of(key, {"scenes", "meshes", "accessors", "bufferViews", "buffers", "materials",
                   "textures", "images", "samplers", "cameras", "primitives", "lights"}))
    return Want::kObjects;
  if (one_of(key, {"name", "uri", "mimeType", "alphaMode", "type", "version", "generator"}))
    return Want::kString;
  if (one_of(key, {"scene", "mesh",       "camera",     "skin",       "material",  "indices",
                   "index", "source",     "sampler",    "bufferView", "buffer",    "texCoord",
                   "light", "byteOffset", "byteLength", "byteStride", "count",     "componentType",
                   "mode",  "wrapS",      "wrapT",      "magFilter",  "minFilter", "target"}))
    return Want::kIndex;
  if (one_of(key, {"metallicFactor", "roughnessFactor", "alphaCutoff", "yfov", "znear", "zfar",
                   "aspectRatio", "xmag", "ymag", "intensity", "range", "ior", "transmissionFactor",
                   "strength", "innerConeAngle", "outerConeAngle", "attenuationDistance",
                   "thicknessFactor"}))
    return Want::kNumber;
  if (one_of(key, {"normalized", "doubleSided"})) return Want::kBool;
  if (one_of(key, {"asset", "pbrMetallicRoughness", "baseColorTexture", "metallicRoughnessTexture",
                   "normalTexture", "occlusionTexture", "emissiveTexture", "perspective",
                   "orthographic", "spot", "transmissionTexture", "sparse"}))
    return Want::kObject;
  if (one_of(key, {"matrix", "translation", "baseColorFactor", "emissiveFactor", "color", "offset",
                   "min", "max", "weights", "attenuationColor"}))
    return Want::kNumbers;
  if (one_of(key, {"scale", "rotation"})) return Want::kNumberOrNumbers;
  if (one_of(key, {"children"})) return Want::kIndices;
  if (one_of(key, {"extensionsUsed", "extensionsRequired"})) return Want::kStrings;
  if (key == "attributes") return Want::kAttributes;
  if (key == "extensions") return Want::kExtensions;
  return Want::kSkip;  // extras, animations, skins, unknown members
}

// Extensions whose members we read (and so check); others are left alone.
bool known_extension(std::string_view name) {
  return one_of(name, {"KHR_texture_transform", "KHR_materials_transmission", "KHR_materials_ior",
                       "KHR_materials_volume", "KHR_lights_punctual"});
}

bool is_index(const json& v) {
  return (v.is_number_unsigned() || (v.is_number_integer() && v.get<int64_t>() >= 0)) &&
         v.get<uint64_t>() <= uint64_t(INT32_MAX);
}

const char* want_name(Want w) {
  switch (w) {
    case Want::kString:
      return "a string";
    case Want::kIndex:
      return "a non-negative integer";
    case Want::kNumber:
      return "a number";
    case Want::kBool:
      return "true or false";
    case Want::kObject:
    case Want::kAttributes:
    case Want::kExtensions:
      return "an object";
    case Want::kNumbers:
      return "an array of numbers";
    case Want::kIndices:
      return "an array of non-negative integers";
    case Want::kStrings:
      return "an array of strings";
    case Want::kObjects:
      return "an array of objects";
    case Want::kNumberOrNumbers:
      return "a number or an array of numbers";
    case Want::kSkip:
      break;
  }
  return "something else";
}

class TypeCheck {
 public:
  std::string error;

  // Checks the members of object o (level: 0 for the root).
  bool object(const json& o, int level) {
    for (const auto& [key, value] : o.items()) {
      const Want w = want_for(key, level);
      if (w == Want::kSkip) continue;
      const size_t mark = where_.size();
      where_ += (where_.empty() ? "" : ".") + key;
      if (!member(value, w, level)) return false;
      where_.resize(mark);
    }
    return true;
  }

 private:
  std::string where_;

  bool mismatch(Want w) {
    error = where_ + ": expected " + want_name(w);
    return false;
  }

  bool member(const json& v, Want w, int level) {
    switch (w) {
      case Want::kString:
        return v.is_string() || mismatch(w);
      case Want::kIndex:
        return is_index(v) || mismatch(w);
      case Want::kNumber:
        return v.is_number() || mismatch(w);
      case Want::kBool:
        return v.is_boolean() || mismatch(w);
      case Want::kObject:
        if (!v.is_object()) return mismatch(w);
        return where_.ends_with("sparse") || object(v, level + 1);
      case Want::kNumberOrNumbers:
        if (v.is_number()) return true;
        [[fallthrough]];
      case Want::kNumbers:
      case Want::kIndices:
      case Want::kStrings:
      case Want::kObjects: {
        if (!v.is_array()) return mismatch(w);
        for (const json& e : v) {
          const bool ok = w == Want::kIndices   ? is_index(e)
                          : w == Want::kStrings ? e.is_string()
                          : w == Want::kObjects ? e.is_object()
                                                : e.is_number();
          if (!ok) return mismatch(w);
        }
        if (w != Want::kObjects) return true;
        const size_t mark = where_.size();
        for (size_t i = 0; i < v.size(); ++i) {
          where_ += "[" + std::to_string(i) + "]";
          if (!object(v[i], level + 1)) return false;
          where_.resize(mark);
        }
        return true;
      }
      case Want::kAttributes:
        if (!v.is_object()) return mismatch(w);
        for (const auto& [name, index] : v.items())
          if (!is_index(index)) {
            where_ += "." + name;
            return mismatch(Want::kIndex);
          }
        return true;
      case Want::kExtensions:
        if (!v.is_object()) return mismatch(w);
        for (const auto& [name, ext] : v.items()) {
          if (!known_extension(name)) continue;
          where_ += "." + name;
          if (!ext.is_object()) return mismatch(Want::kObject);
          if (!object(ext, level + 1)) return false;
          where_.resize(where_.size() - name.size() - 1);
        }
        return true;
      case Want::kSkip:
        break;
    }
    return true;
  }
};

// tinygltf's own decoding of buffer URIs ('+' also becomes a space), to recognise its requests.
std::string tinygltf_urldecode(const std::string& s) {
  auto hex = [](char c) -> int {
    if (c >= '0' && c <= '9') return c - '0';
    if (c >= 'a' && c <= 'f') return c - 'a' + 10;
    if (c >= 'A' && c <= 'F') return c - 'A' + 10;
    return 0;
  };
  std::string out;
  for (size_t i = 0; i < s.size(); ++i) {
    if (s[i] == '+') {
      out += ' ';
    } else if (s[i] == '%' && s.size() > i + 2) {
      out += char(hex(s[i + 1]) << 4 | hex(s[i + 2]));
      i += 2;
    } else {
      out += s[i];
    }
  }
  return out;
}

// tinygltf's file access: only the buffer files gltf_check found (never images, never the
// current directory it would also search), and no writing.
bool fs_exists(const std::string& file, void* user) {
  for (const auto& [asked, actual] : static_cast<const Checked*>(user)->buffer_files)
    if (asked == file) return true;
  return false;
}
std::string fs_expand(const std::string& file, void*) { return file; }
bool fs_read(std::vector<unsigned char>* out, std::string* error, const std::string& file,
             void* user) {
  for (const auto& [asked, actual] : static_cast<const Checked*>(user)->buffer_files) {
    if (asked != file) continue;
    auto bytes = read_file_bytes(actual);
    if (!bytes) {
      *error = bytes.error().message;
      return false;
    }
    out->assign(bytes->begin(), bytes->end());
    return true;
  }
  *error = "not a buffer of this file";
  return false;
}
bool fs_write(std::string* error, const std::string&, const std::vector<unsigned char>&, void*) {
  *error = "writing is disabled";
  return false;
}

// tinygltf's image callback decodes nothing: gltf_material loads the images that textures use.
// data: URI images arrive here already base64-decoded and are kept (tinygltf drops their URI);
// bufferView images are read later with their bounds checked, files through the ImageCache.
bool keep_data_uri_image(tinygltf::Image* image, const int index, std::string*, std::string*, int,
                         int, const unsigned char* bytes, int size, void* user) {
  if (image->bufferView < 0 && image->uri.empty() && bytes != nullptr && size > 0)
    (*static_cast<std::map<int, std::string>*>(user))[index].assign(
        reinterpret_cast<const char*>(bytes), size_t(size));
  return true;
}

}  // namespace

void restrict_loader(tinygltf::TinyGLTF& loader, Checked& checked,
                     std::map<int, std::string>& embedded) {
  loader.SetImageLoader(&keep_data_uri_image, &embedded);
  loader.SetFsCallbacks({&fs_exists, &fs_expand, &fs_read, &fs_write, &checked});
}

std::string percent_decode(const std::string& uri) {
  auto hex = [](char c) -> int {
    if (c >= '0' && c <= '9') return c - '0';
    if (c >= 'a' && c <= 'f') return c - 'a' + 10;
    if (c >= 'A' && c <= 'F') return c - 'A' + 10;
    return -1;
  };
  std::string out;
  for (size_t i = 0; i < uri.size(); ++i) {
    if (uri[i] == '%' && i + 2 < uri.size() && hex(uri[i + 1]) >= 0 && hex(uri[i + 2]) >= 0) {
      out += char(hex(uri[i + 1]) << 4 | hex(uri[i + 2]));
      i += 2;
    } else {
      out += uri[i];
    }
  }
  return out;
}

std::string join_path(const std::string& dir, const std::string& rel) {
  if (dir.empty()) return rel;
  return dir.back() == '/' ? dir + rel : dir + "/" + rel;
}

std::string one_line(const std::string& text) {
  std::string out;
  for (char c : text) {
    if (c == '\n' || c == '\r') {
      if (!out.empty() && out.back() != ' ') out += "; ";
    } else {
      out += c;
    }
  }
  while (!out.empty() && (out.back() == ' ' || out.back() == ';')) out.pop_back();
  if (out.size() > 300) out = out.substr(0, 300) + "...";  // data: URIs are quoted whole
  return out.empty() ? "cannot load glTF" : out;
}

Result<Checked> check_gltf(const std::string& bytes, const std::string& path,
                           const std::string& base_dir) {
  Checked out;
  if (bytes.size() > UINT32_MAX) return fail(path, "larger than 4 GiB");
  std::string_view text(bytes);
  if (bytes.size() >= 4 && std::memcmp(bytes.data(), "glTF", 4) == 0) {
    out.binary = true;
    if (bytes.size() < 20) return fail(path, "GLB: truncated header");
    if (read_u32(bytes, 4) != 2)
      return fail(path, "GLB: version " + std::to_string(read_u32(bytes, 4)) + " is not supported");
    const uint64_t length = read_u32(bytes, 8);
    if (length > bytes.size() || length < 20)
      return fail(path, "GLB: header length " + std::to_string(length) + " does not match the " +
                            std::to_string(bytes.size()) + "-byte file");
    const uint64_t json_end = 20 + uint64_t(read_u32(bytes, 12));
    if (read_u32(bytes, 16) != 0x4E4F534Au) return fail(path, "GLB: first chunk is not JSON");
    if (json_end > length) return fail(path, "GLB: JSON chunk runs past the end of the file");
    if (json_end < length) {
      if (json_end + 8 > length) return fail(path, "GLB: truncated BIN chunk header");
      if (json_end + 8 + read_u32(bytes, size_t(json_end)) > length)
        return fail(path, "GLB: BIN chunk runs past the end of the file");
    }
    text = text.substr(20, size_t(json_end - 20));
  }
  if (json_depth(text) > kMaxJsonDepth)
    return fail(path, "JSON nested deeper than " + std::to_string(kMaxJsonDepth) + " levels");
  json root;
  try {
    root = json::parse(text);
  } catch (const json::exception& e) {
    // nlohmann's message: "[json.exception.parse_error.101] parse error at line L, column C: ..."
    std::string what = e.what();
    const size_t bracket = what.find("] ");
    if (bracket != std::string::npos) what = what.substr(bracket + 2);
    return fail(path, "JSON: " + one_line(what));
  }
  if (!root.is_object()) return fail(path, "JSON: the top level is not an object");
  TypeCheck types;
  if (!types.object(root, 0)) return fail(path, types.error);

  if (root.contains("extensionsRequired"))
    for (const json& name : root["extensionsRequired"])
      if (!one_of(name.get<std::string>(),
                  {"KHR_texture_transform", "KHR_materials_transmission", "KHR_materials_ior",
                   "KHR_materials_volume", "KHR_lights_punctual"}))
        return fail(path, "extensionsRequired: '" + name.get<std::string>() + "' is not supported");

  // External buffers: the only files tinygltf may open (images are loaded by gltf_material).
  if (root.contains("buffers")) {
    const json& buffers = root["buffers"];
    for (size_t i = 0; i < buffers.size(); ++i) {
      const std::string where = "buffer " + std::to_string(i) + ": ";
      if (!buffers[i].contains("uri")) {
        if (!out.binary || i > 0) return fail(path, where + "no uri");
        continue;
      }
      const std::string uri = buffers[i]["uri"].get<std::string>();
      if (uri.starts_with("data:")) continue;
      const size_t colon = uri.find(':'), slash = uri.find('/');
      if (colon != std::string::npos && (slash == std::string::npos || colon < slash))
        return fail(path, where + "URI scheme '" + uri.substr(0, colon) + "' is not supported");
      const std::string file = join_path(base_dir, percent_decode(uri));
      std::FILE* f = std::fopen(file.c_str(), "rb");
      if (!f) return fail(path, where + "cannot read '" + uri + "': " + std::strerror(errno));
      std::fclose(f);
      // tinygltf asks for base_dir joined with its decoding of the URI (its JoinPath).
      out.buffer_files.emplace_back(join_path(base_dir, tinygltf_urldecode(uri)), file);
    }
  }
  return out;
}

}  // namespace frameless::gltf
