// glTF materials mapped onto Parker's four classes, and their textures and images.
//
// glTF pbrMetallicRoughness -> Parker class; the first rule that applies (roughness r, metallic m,
// base colour b = baseColorFactor, times baseColorTexture where a slot is named):
//  dielectric  KHR_materials_transmission.transmissionFactor > 0, or alphaMode BLEND with
//              b.a < 0.5: ior = KHR_materials_ior.ior (1.5), extinction from KHR_materials_volume
//              (-ln(attenuationColor) / attenuationDistance, else none), kh = 1 - r.
//  metal       m >= 0.5: ks = b.rgb, ks_tex = base colour texture.
//  polished    r < 0.5: kd = b.rgb, kd_tex = base colour texture, r0 = 0.04 (dielectric coat),
//              kh = 1 - r.
//  diffuse     otherwise: kd = b.rgb, kd_tex = base colour texture.
// The path tracer reads metals as GGX of roughness r (f0 = ks) and both non-metal classes as a
// GGX coat (f0 = 0.04, roughness r) over the coupled diffuse base (core/shading/bsdf.h).
// Every highlight exponent is N = 2 / r^4 - 2 (Blinn-Phong matching a microfacet alpha = r^2),
// clamped to [1, 10000]. A primitive without a material gets a grey (0.8) diffuse one, not glTF's
// white rough metal default.
// Alpha: MASK cuts out where base colour alpha (texture alpha times b.a) < alphaCutoff (0.5);
// BLEND that is not a dielectric is treated as MASK with cutoff 0.5; OPAQUE ignores alpha.
// normalTexture -> normal_tex (linear data; its scale is ignored). Colour textures are sRGB.
// Emission, any class: emissiveFactor (in [0, 1]) times KHR_materials_emissive_strength's
// emissiveStrength (in [0, 1e6]; 1 when absent), times emissiveTexture where one is named.
// Samplers: wrapS and wrapT both CLAMP_TO_EDGE -> clamp, otherwise repeat (mirrored repeat too).
// KHR_texture_transform offset and scale are applied (rotation is not: a warning); only
// TEXCOORD_0 is read. Ignored: metallicRoughnessTexture, occlusion.
#include <algorithm>
#include <cmath>

#include "core/io/gltf_internal.h"

namespace frameless::gltf {
namespace {

float phong_exponent(double roughness) {
  const double r = std::max(roughness, 1e-3);
  return float(std::clamp(2.0 / (r * r * r * r) - 2.0, 1.0, 10000.0));
}

// Number member `key` of extension `name`, or fallback.
double ext_number(const tinygltf::ExtensionMap& ext, const char* name, const char* key,
                  double fallback) {
  const auto it = ext.find(name);
  if (it == ext.end() || !it->second.IsObject() || !it->second.Has(key)) return fallback;
  const tinygltf::Value& v = it->second.Get(key);
  return v.IsNumber() && std::isfinite(v.GetNumberAsDouble()) ? v.GetNumberAsDouble() : fallback;
}

// Array member `key` of extension `name` into out[0..n) when it holds n finite numbers.
bool ext_numbers(const tinygltf::ExtensionMap& ext, const char* name, const char* key, int n,
                 double* out) {
  const auto it = ext.find(name);
  if (it == ext.end() || !it->second.IsObject() || !it->second.Has(key)) return false;
  const tinygltf::Value& v = it->second.Get(key);
  if (!v.IsArray() || v.ArrayLen() != size_t(n)) return false;
  for (int i = 0; i < n; ++i)
    if (!v.Get(i).IsNumber() || !std::isfinite(v.Get(i).GetNumberAsDouble())) return false;
  for (int i = 0; i < n; ++i) out[i] = v.Get(i).GetNumberAsDouble();
  return true;
}

}  // namespace

void MaterialMap::warn_once(const std::string& w) {
  if (std::find(warnings_.begin(), warnings_.end(), w) == warnings_.end()) warnings_.push_back(w);
}

Result<uint16_t> MaterialMap::get(int index) {
  if (const auto it = materials_.find(index); it != materials_.end()) return it->second;
  if (index < -1 || index >= int(model_.materials.size()))
    return fail(path_, "material " + str(index) + " out of range (" + str(model_.materials.size()) +
                           " materials)");
  if (mesh_.materials.size() >= 0xffff) return fail(path_, "more than 65535 materials");
  auto m = convert(index);
  if (!m) return m.error();
  mesh_.materials.push_back(*m);
  const uint16_t id = uint16_t(mesh_.materials.size() - 1);
  materials_[index] = id;
  return id;
}

Result<Material> MaterialMap::convert(int index) {
  Material m;
  if (index < 0) {
    m.name = "default";
    return m;
  }
  const tinygltf::Material& g = model_.materials[size_t(index)];
  const std::string where = "material " + str(index);
  const tinygltf::PbrMetallicRoughness& pbr = g.pbrMetallicRoughness;
  m.name = g.name.empty() ? where : g.name;
  if (pbr.baseColorFactor.size() != 4)
    return fail(path_, where + ": baseColorFactor needs 4 numbers");
  Vec4 base;
  for (int i = 0; i < 4; ++i) base[i] = float(std::clamp(pbr.baseColorFactor[size_t(i)], 0.0, 1.0));
  const double metallic = std::clamp(pbr.metallicFactor, 0.0, 1.0);
  const double roughness = std::clamp(pbr.roughnessFactor, 0.0, 1.0);
  const double transmission =
      ext_number(g.extensions, "KHR_materials_transmission", "transmissionFactor", 0.0);
  const bool blend = g.alphaMode == "BLEND", mask = g.alphaMode == "MASK";

  auto normal_tex =
      texture(g.normalTexture.index, g.normalTexture.extensions, false, where + ": normalTexture");
  if (!normal_tex) return normal_tex.error();
  m.normal_tex = *normal_tex;
  if (pbr.baseColorTexture.texCoord != 0 || g.normalTexture.texCoord != 0)
    warn_once("textures on TEXCOORD_1 or higher use TEXCOORD_0");

  // Emission, any class: emissiveFactor times KHR_materials_emissive_strength, emissiveTexture.
  if (g.emissiveFactor.size() != 3) return fail(path_, where + ": emissiveFactor needs 3 numbers");
  const double strength =
      ext_number(g.extensions, "KHR_materials_emissive_strength", "emissiveStrength", 1.0);
  if (!std::isfinite(strength) || strength < 0.0 || strength > 1e6)
    return fail(path_, where +
                           ": KHR_materials_emissive_strength.emissiveStrength must be in [0, 1e6]");
  for (int i = 0; i < 3; ++i) {
    const double e = g.emissiveFactor[size_t(i)];
    if (!std::isfinite(e) || e < 0.0 || e > 1.0)
      return fail(path_, where + ": emissiveFactor must be in [0, 1]");
    m.emission[i] = float(e * strength);
  }
  auto emission_tex = texture(g.emissiveTexture.index, g.emissiveTexture.extensions, true,
                              where + ": emissiveTexture");
  if (!emission_tex) return emission_tex.error();
  m.emission_tex = *emission_tex;

  m.phong_exponent = phong_exponent(roughness);
  if (transmission > 0.0 || (blend && base.w < 0.5f)) {
    m.cls = MaterialClass::kDielectric;
    const double ior = ext_number(g.extensions, "KHR_materials_ior", "ior", 1.5);
    m.ior = float(ior >= 1.0 && ior <= 10.0 ? ior : 1.5);
    m.kh = Vec3(float(1.0 - roughness));
    double color[3];
    const double dist =
        ext_number(g.extensions, "KHR_materials_volume", "attenuationDistance", 0.0);
    if (dist > 0.0 &&
        ext_numbers(g.extensions, "KHR_materials_volume", "attenuationColor", 3, color))
      for (int i = 0; i < 3; ++i)
        m.extinction[i] = float(-std::log(std::clamp(color[i], 1e-4, 1.0)) / dist);
    return m;  // a transmitting surface is never cut out, and has no base colour texture
  }
  auto base_tex = texture(pbr.baseColorTexture.index, pbr.baseColorTexture.extensions, true,
                          where + ": baseColorTexture");
  if (!base_tex) return base_tex.error();
  if (metallic >= 0.5) {
    m.cls = MaterialClass::kMetal;
    m.ks = Vec3(base);
    m.ks_tex = *base_tex;
    m.roughness = float(roughness);  // the path tracer's GGX
  } else {
    m.cls = roughness < 0.5 ? MaterialClass::kPolished : MaterialClass::kDiffuse;
    m.kd = Vec3(base);
    m.kd_tex = *base_tex;
    m.r0 = Vec3(0.04f);  // the path tracer's GGX coat (Whitted reads it for polished only)
    m.roughness = float(roughness);
    if (m.cls == MaterialClass::kPolished) m.kh = Vec3(float(1.0 - roughness));
  }
  if (mask || blend) {
    m.alpha_tex = *base_tex;
    m.alpha_channel = 3;
    m.opacity = base.w;
    m.alpha_cutoff = mask ? float(std::clamp(g.alphaCutoff, 0.0, 1.0)) : 0.5f;
  }
  return m;
}

Result<uint32_t> MaterialMap::texture(int index, const tinygltf::ExtensionMap& ext, bool srgb,
                                      const std::string& where) {
  if (index < 0) return kNoTexture;
  if (size_t(index) >= model_.textures.size())
    return fail(path_, where + ": texture " + str(index) + " out of range (" +
                           str(model_.textures.size()) + " textures)");
  const tinygltf::Texture& t = model_.textures[size_t(index)];
  if (t.source < 0) {
    warn_once("texture " + str(index) + " has no image we can read (ignored)");
    return kNoTexture;
  }
  // KHR_texture_transform in our uv space (v up): v' = v*sy + (1 - sy - oy).
  double offset[2] = {0.0, 0.0}, scale[2] = {1.0, 1.0};
  ext_numbers(ext, "KHR_texture_transform", "offset", 2, offset);
  ext_numbers(ext, "KHR_texture_transform", "scale", 2, scale);
  if (ext_number(ext, "KHR_texture_transform", "rotation", 0.0) != 0.0)
    warn_once("KHR_texture_transform rotation is ignored");
  const Vec2 uv_scale{float(scale[0]), float(scale[1])};
  const Vec2 uv_offset{float(offset[0]), float(1.0 - scale[1] - offset[1])};
  const auto key = std::make_tuple(index, srgb, uv_scale.x, uv_scale.y, uv_offset.x, uv_offset.y);
  if (const auto it = textures_.find(key); it != textures_.end()) return it->second;

  auto img = image(t.source);
  if (!img) return img.error();
  Texture tex;
  tex.kind = TextureKind::kImage;
  tex.image = *img;
  tex.srgb = srgb;
  tex.uv_scale = uv_scale;
  tex.uv_offset = uv_offset;
  if (t.sampler >= 0) {
    if (size_t(t.sampler) >= model_.samplers.size())
      return fail(path_, "texture " + str(index) + ": sampler " + str(t.sampler) + " out of range");
    const tinygltf::Sampler& s = model_.samplers[size_t(t.sampler)];
    const bool clamp = s.wrapS == TINYGLTF_TEXTURE_WRAP_CLAMP_TO_EDGE &&
                       s.wrapT == TINYGLTF_TEXTURE_WRAP_CLAMP_TO_EDGE;
    tex.wrap = clamp ? TextureWrap::kClamp : TextureWrap::kRepeat;
  }
  mesh_.textures.push_back(std::move(tex));
  const uint32_t id = uint32_t(mesh_.textures.size() - 1);
  textures_[key] = id;
  return id;
}

Result<std::shared_ptr<const Image>> MaterialMap::image(int index) {
  if (const auto it = decoded_.find(index); it != decoded_.end()) return it->second;
  if (size_t(index) >= model_.images.size())
    return fail(path_,
                "image " + str(index) + " out of range (" + str(model_.images.size()) + " images)");
  const tinygltf::Image& im = model_.images[size_t(index)];
  const std::string label = path_ + "#image " + str(index);
  Result<std::shared_ptr<const Image>> r = Error{};
  if (im.bufferView >= 0) {
    // Embedded (GLB): the bytes of a bufferView, bounds-checked here (tinygltf does not).
    if (size_t(im.bufferView) >= model_.bufferViews.size())
      return fail(path_,
                  "image " + str(index) + ": bufferView " + str(im.bufferView) + " out of range");
    const tinygltf::BufferView& bv = model_.bufferViews[size_t(im.bufferView)];
    if (bv.buffer < 0 || size_t(bv.buffer) >= model_.buffers.size())
      return fail(path_, "image " + str(index) + ": buffer " + str(bv.buffer) + " out of range");
    const std::vector<unsigned char>& data = model_.buffers[size_t(bv.buffer)].data;
    if (bv.byteOffset > data.size() || bv.byteLength > data.size() - bv.byteOffset)
      return fail(path_, "image " + str(index) + ": bufferView " + str(im.bufferView) +
                             " runs past its buffer");
    r = decode_image(
        std::string(reinterpret_cast<const char*>(data.data()) + bv.byteOffset, bv.byteLength),
        label);
  } else if (const auto e = embedded_.find(index); e != embedded_.end()) {
    r = decode_image(e->second, label);
  } else if (!im.uri.empty() && !im.uri.starts_with("data:")) {
    const size_t colon = im.uri.find(':'), slash = im.uri.find('/');
    if (colon != std::string::npos && (slash == std::string::npos || colon < slash))
      return fail(path_, "image " + str(index) + ": URI scheme '" + im.uri.substr(0, colon) +
                             "' is not supported");
    // Files go through the cache, so models and materials naming one file share its texels.
    r = images_.get(join_path(base_dir_, percent_decode(im.uri)));
    if (!r) return fail(path_, "image " + str(index) + " '" + im.uri + "': " + r.error().message);
  } else {
    return fail(path_, "image " + str(index) + ": no data");
  }
  if (!r) return r.error();
  decoded_[index] = *r;
  return r;
}

}  // namespace frameless::gltf
