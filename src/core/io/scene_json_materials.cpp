// Textures and materials of JSON scene files (docs/scene-format.md).
#include <algorithm>
#include <vector>

#include <glm/gtc/matrix_inverse.hpp>

#include "core/io/scene_json_materials.h"

#include <cstdio>

#include "core/io/shader_library.h"
#include "core/shading/parker_shaders.h"

namespace frameless::scene_json {
namespace {

// Keys every material class accepts besides its own: texture slots, cut-out settings, emission.
std::vector<const char*> with_shared_keys(std::initializer_list<const char*> own) {
  std::vector<const char*> keys(own);
  for (const char* k : {"kd_texture", "kh_texture", "ks_texture", "alpha_texture", "alpha_channel",
                        "alpha_cutoff", "opacity", "normal_texture", "bump_texture", "bump_scale",
                        "emission", "emission_texture"})
    keys.push_back(k);
  return keys;
}

void check_keys(const json& j, const std::string& field, const std::vector<const char*>& allowed) {
  for (auto it = j.begin(); it != j.end(); ++it) {
    if (std::find_if(allowed.begin(), allowed.end(), [&](const char* a) { return it.key() == a; }) !=
        allowed.end())
      continue;
    std::string list;
    for (const char* a : allowed) list += std::string(list.empty() ? "" : ", ") + a;
    fail(sub(field, it.key().c_str()), "unknown key (expected one of: " + list + ")");
  }
}

uint32_t texture_ref(const json& j, const std::string& f, const TextureNames& textures) {
  const std::string name = get_string(j, f);
  const auto it = textures.find(name);
  if (it == textures.end()) fail(f, "unknown texture '" + name + "'");
  return it->second;
}

void parse_texture_slots(const json& j, const std::string& f, const TextureNames& textures,
                         const Scene& scene, Material& m) {
  if (j.contains("kd_texture")) m.kd_tex = texture_ref(j["kd_texture"], f + ".kd_texture", textures);
  if (j.contains("kh_texture")) m.kh_tex = texture_ref(j["kh_texture"], f + ".kh_texture", textures);
  if (j.contains("ks_texture")) m.ks_tex = texture_ref(j["ks_texture"], f + ".ks_texture", textures);
  if (j.contains("alpha_texture"))
    m.alpha_tex = texture_ref(j["alpha_texture"], f + ".alpha_texture", textures);
  if (j.contains("normal_texture"))
    m.normal_tex = texture_ref(j["normal_texture"], f + ".normal_texture", textures);
  if (j.contains("bump_texture"))
    m.bump_tex = texture_ref(j["bump_texture"], f + ".bump_texture", textures);
  if (j.contains("emission_texture"))
    m.emission_tex = texture_ref(j["emission_texture"], f + ".emission_texture", textures);
  if (j.contains("alpha_channel")) {
    const std::string c = get_string(j["alpha_channel"], f + ".alpha_channel");
    if (c == "alpha") m.alpha_channel = 3;
    else if (c == "red") m.alpha_channel = 0;
    else fail(f + ".alpha_channel", "must be \"alpha\" or \"red\" (got '" + c + "')");
  }
  if (j.contains("alpha_cutoff"))
    m.alpha_cutoff = get_float(j["alpha_cutoff"], f + ".alpha_cutoff", 0.0, 1.0, "in [0, 1]");
  if (j.contains("opacity")) m.opacity = get_float(j["opacity"], f + ".opacity", 0.0, 1.0, "in [0, 1]");
  if (j.contains("bump_scale"))
    m.bump_scale = get_float(j["bump_scale"], f + ".bump_scale", -1e6, 1e6, "in [-1e6, 1e6]");
  // Normal and bump maps are looked up by UV: a solid texture there would perturb nothing.
  for (const auto& [slot, key] : {std::pair{m.normal_tex, "normal_texture"}, std::pair{m.bump_tex, "bump_texture"}})
    if (slot != kNoTexture && scene.textures[slot].kind != TextureKind::kImage)
      fail(sub(f, key), "must name an image texture (a solid texture has no UV slope)");
  // Maps of data (alpha, normals, heights) are read as stored, not as sRGB colour.
  for (uint32_t t : {m.alpha_tex, m.normal_tex, m.bump_tex})
    if (t != kNoTexture && scene.textures[t].kind == TextureKind::kImage && scene.textures[t].srgb)
      fail(f, "texture used as data (alpha, normal or bump) must set \"srgb\": false");
}

}  // namespace

void parse_textures(const json& j, Scene& s, const std::string& base_dir, ImageCache& images,
                    TextureNames& names, std::set<uint32_t>& object_space) {
  require_object(j, "textures");
  for (auto it = j.begin(); it != j.end(); ++it) {
    const std::string f = "textures." + it.key();
    const json& t = require_object(it.value(), f);
    const std::string type = get_string(need(t, f, "type"), f + ".type");
    Texture tex;
    if (type == "image") {
      check_keys(t, f, {"type", "file", "wrap", "srgb", "uv_scale", "uv_offset"});
      const std::string file = get_string(need(t, f, "file"), f + ".file");
      const std::string full = !file.empty() && file[0] == '/' ? file : base_dir + "/" + file;
      auto image = images.get(full);
      if (!image) fail(f + ".file", image.error().message);
      tex.kind = TextureKind::kImage;
      tex.image = *image;
      if (t.contains("wrap")) {
        const std::string w = get_string(t["wrap"], f + ".wrap");
        if (w == "repeat") tex.wrap = TextureWrap::kRepeat;
        else if (w == "clamp") tex.wrap = TextureWrap::kClamp;
        else fail(f + ".wrap", "must be \"repeat\" or \"clamp\" (got '" + w + "')");
      }
      if (t.contains("srgb")) tex.srgb = get_bool(t["srgb"], f + ".srgb");
      auto get_vec2 = [&](const char* key) {
        const std::string kf = sub(f, key);
        const json& v = t[key];
        if (!v.is_array() || v.size() != 2) fail(kf, "expected an array of 2 numbers");
        return Vec2(float(get_number(v[0], kf + "[0]")), float(get_number(v[1], kf + "[1]")));
      };
      if (t.contains("uv_scale")) tex.uv_scale = get_vec2("uv_scale");
      if (t.contains("uv_offset")) tex.uv_offset = get_vec2("uv_offset");
    } else {
      if (type == "checker") tex.kind = TextureKind::kChecker;
      else if (type == "noise") tex.kind = TextureKind::kNoise;
      else if (type == "turbulence") tex.kind = TextureKind::kTurbulence;
      else if (type == "marble") tex.kind = TextureKind::kMarble;
      else if (type == "wood") tex.kind = TextureKind::kWood;
      else
        fail(f + ".type", "unknown texture '" + type +
                              "' (image, checker, noise, turbulence, marble or wood)");
      check_keys(t, f, {"type", "color_a", "color_b", "frequency", "octaves", "amplitude",
                        "transform", "space"});
      if (t.contains("space")) {
        const std::string space = get_string(t["space"], f + ".space");
        if (space == "object") object_space.insert(uint32_t(s.textures.size()));
        else if (space != "world")
          fail(f + ".space", "must be \"world\" or \"object\" (got '" + space + "')");
      }
      if (t.contains("color_a")) tex.color_a = get_color(t["color_a"], f + ".color_a");
      if (t.contains("color_b")) tex.color_b = get_color(t["color_b"], f + ".color_b");
      if (t.contains("frequency"))
        tex.frequency = get_float(t["frequency"], f + ".frequency", 1e-6, 1e6, "in (0, 1e6]");
      if (t.contains("octaves")) tex.octaves = int(get_int(t["octaves"], f + ".octaves", 1, 16));
      if (t.contains("amplitude"))
        tex.amplitude = get_float(t["amplitude"], f + ".amplitude", 0.0, 1e3, "in [0, 1e3]");
      // The texture's frame in the world: points map through the inverse of its transform.
      if (t.contains("transform"))
        tex.to_texture = glm::inverse(parse_transform(t["transform"], f + ".transform"));
    }
    if (s.textures.size() >= kNoTexture - 1) fail(f, "too many textures");
    names[it.key()] = uint32_t(s.textures.size());
    s.textures.push_back(std::move(tex));
  }
}

Material parse_material(const std::string& name, const json& j, const std::string& f,
                        const TextureNames& textures, const Scene& scene) {
  require_object(j, f);
  if (!j.contains("class")) fail(f + ".class", "missing (diffuse, metal, dielectric or polished; or a \"shader\")");
  const std::string cls = get_string(j["class"], f + ".class");
  Material m;
  m.name = name;
  if (cls == "diffuse") {
    m.cls = MaterialClass::kDiffuse;
    check_keys(j, f, with_shared_keys({"class", "kd"}));
  } else if (cls == "metal") {
    m.cls = MaterialClass::kMetal;
    check_keys(j, f, with_shared_keys({"class", "ks", "phong_exponent"}));
    m.kd = Vec3(0.0f);
    m.ks = Vec3(0.9f);
  } else if (cls == "dielectric") {
    m.cls = MaterialClass::kDielectric;
    check_keys(j, f, with_shared_keys({"class", "ior", "extinction", "kh", "phong_exponent"}));
    m.kd = Vec3(0.0f);
    m.kh = Vec3(1.0f);
  } else if (cls == "polished") {
    m.cls = MaterialClass::kPolished;
    check_keys(j, f, with_shared_keys({"class", "kd", "r0", "kh", "phong_exponent"}));
    m.kh = Vec3(1.0f);
  } else {
    fail(f + ".class", "unknown class '" + cls + "' (diffuse, metal, dielectric or polished)");
  }
  if (j.contains("kd")) m.kd = get_color(j["kd"], f + ".kd");
  if (j.contains("ks")) m.ks = get_color(j["ks"], f + ".ks");
  if (j.contains("kh")) m.kh = get_color(j["kh"], f + ".kh");
  if (j.contains("phong_exponent"))
    m.phong_exponent = get_float(j["phong_exponent"], f + ".phong_exponent", 0.0, 1e6, "in [0, 1e6]");
  if (j.contains("ior")) m.ior = get_float(j["ior"], f + ".ior", 1e-3, 100.0, "in (0, 100]");
  if (j.contains("extinction")) m.extinction = get_color(j["extinction"], f + ".extinction");
  if (j.contains("r0")) {
    m.r0 = get_color(j["r0"], f + ".r0");
    if (m.r0.x > 1.0f || m.r0.y > 1.0f || m.r0.z > 1.0f) fail(f + ".r0", "must be in [0, 1]");
  }
  if (j.contains("emission")) {
    m.emission = get_color(j["emission"], f + ".emission");
    if (max_component(m.emission) > 1e6f) fail(f + ".emission", "must be at most 1e6");
  } else if (j.contains("emission_texture")) {
    m.emission = Vec3(1.0f);  // the texture alone gives the emitted radiance
  }
  if (m.cls == MaterialClass::kMetal) m.kh = m.ks;  // metal: k_h = k_s (section 3.1)
  parse_texture_slots(j, f, textures, scene, m);
  return m;
}


Material parse_shader_material(const std::string& name, const json& j, const std::string& f, Scene& scene,
                               const std::string& base_dir, const TextureNames& textures) {
  require_object(j, f);
  check_keys(j, f, {"shader", "params", "emission"});
  // Parker's classes are built in (never loaded): declared like plug-ins, run as compiled.
  const std::string shader_name = get_string(j["shader"], f + ".shader");
  LoadedShader loaded{parker_shader(shader_name), "built in"};
  if (!loaded.shader) {
    auto found = load_shader(shader_name, base_dir);
    if (!found) fail(f + ".shader", found.error().message);
    loaded = *found;
  }
  const fl_shader& sh = *loaded.shader;
  ShaderMaterial bound{&sh, shader_defaults(sh), loaded.library};
  if (j.contains("params")) {
    const json& params = require_object(j["params"], f + ".params");
    for (auto it = params.begin(); it != params.end(); ++it) {
      const std::string pf = f + ".params." + it.key();
      int at = 0;
      const fl_param* decl = find_shader_param(sh, it.key(), at);
      if (!decl) {
        std::string declared;
        for (uint32_t i = 0; i < sh.param_count; ++i) declared += (i ? ", " : "") + std::string(sh.params[i].name);
        fail(pf, "unknown parameter of shader '" + std::string(sh.name) + "' (" +
                     (declared.empty() ? std::string("it declares none") : "it declares " + declared) + ")");
      }
      char range[96];
      std::snprintf(range, sizeof range, "in [%g, %g]", double(decl->min), double(decl->max));
      if (decl->type == FL_PARAM_TEXTURE) {  // a name from "textures", its slot
        bound.params[size_t(at)] = float(texture_ref(it.value(), pf, textures));
      } else if (decl->type == FL_PARAM_FLOAT) {
        bound.params[size_t(at)] = get_float(it.value(), pf, decl->min, decl->max, range);
      } else if (it.value().is_number()) {  // a grey: one number for all three
        const float g = get_float(it.value(), pf, decl->min, decl->max, range);
        for (int k = 0; k < 3; ++k) bound.params[size_t(at + k)] = g;
      } else {
        if (!it.value().is_array() || it.value().size() != 3) fail(pf, "expected [r, g, b] or one number");
        for (int k = 0; k < 3; ++k)
          bound.params[size_t(at + k)] = get_float(it.value()[size_t(k)], pf + "[" + std::to_string(k) + "]", decl->min, decl->max, range);
      }
    }
  }
  Material m;
  if (parker_shader(shader_name)) {
    m = parker_material(sh, bound.params.data());
    m.name = name;
    if (j.contains("emission")) m.emission = get_color(j["emission"], f + ".emission");
    if (max_component(m.emission) > 1e6f) fail(f + ".emission", "must be at most 1e6");
    return m;
  }
  if (scene.shaders.size() >= 65535) fail(f, "too many shader materials (at most 65535)");
  m.name = name;
  m.cls = MaterialClass::kShader;
  m.shader = uint16_t(scene.shaders.size());
  m.kd = Vec3(0.5f);
  if (sh.albedo) {
    const fl_vec3 a = sh.albedo(bound.params.data());
    m.kd = Vec3(a.x, a.y, a.z);
    if (!is_finite(m.kd)) fail(f + ".shader", loaded.library + ": albedo() returned a non-finite colour");
    m.kd = glm::clamp(m.kd, Vec3(0.0f), Vec3(1.0f));
  }
  if (j.contains("emission")) {
    m.emission = get_color(j["emission"], f + ".emission");
    if (max_component(m.emission) > 1e6f) fail(f + ".emission", "must be at most 1e6");
  }
  scene.shaders.push_back(std::move(bound));
  return m;
}

}  // namespace frameless::scene_json
