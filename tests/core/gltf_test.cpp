// glTF input: small glTFs written here (node transforms, v flip, material mapping, lights,
// textures, bad input); Debian's assimp-testmodels are read in gltf_assimp_test.cpp.
#include <unistd.h>

#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>

#include <gtest/gtest.h>

#include "core/io/file_util.h"
#include "core/scene/scene_build.h"
#include "core/scenes/scene_load.h"

#include "gltf_test_util.h"

namespace frameless {
namespace {

using test_util::base64;
using test_util::expect_near;
using test_util::expect_one_line_error;
using test_util::kPng64;
using test_util::put;

struct TempDir {
  std::string path;
  TempDir() {
    path = (std::filesystem::temp_directory_path() /
            ("frameless_gltf_" + std::to_string(::getpid()) + "_" +
             std::to_string(reinterpret_cast<uintptr_t>(this))))
               .string();
    std::filesystem::remove_all(path);
    std::filesystem::create_directories(path);
  }
  ~TempDir() { std::filesystem::remove_all(path); }
  void write(const std::string& name, const std::string& bytes) const {
    std::ofstream(path + "/" + name, std::ios::binary) << bytes;
  }
};

struct Spec {
  float x0 = 0.0f;                              // first position's x (NaN for the error test)
  std::string child = R"("scale": [2, 2, 2])";  // the mesh node's transform
  std::string material = R"({"pbrMetallicRoughness": {"baseColorFactor": [1, 0.5, 0.25, 1],
                             "metallicFactor": 0, "roughnessFactor": 1}})";
  std::string extra;  // more top-level members, each ending in ','
  std::string primitives = R"({"attributes": {"POSITION": 0, "TEXCOORD_0": 1}, "indices": 2,
                               "material": 0})";
};

// One triangle (0,0,0) (1,0,0) (0,1,0) with uvs (0,0) (1,0) (0.25,0.2), under a node at (1,2,3);
// a directional light pointing down (-Z rotated to -Y) and a red spot light at (0,5,0).
std::string make_gltf(const Spec& s) {
  std::string buf;
  for (float f : {s.x0, 0.0f, 0.0f, 1.0f, 0.0f, 0.0f, 0.0f, 1.0f, 0.0f}) put(buf, f);
  for (float f : {0.0f, 0.0f, 1.0f, 0.0f, 0.25f, 0.2f}) put(buf, f);
  for (uint16_t i : {0, 1, 2}) put(buf, i);
  return R"({"asset": {"version": "2.0"}, "scene": 0, "scenes": [{"nodes": [0, 2, 3]}],
    "extensionsUsed": ["KHR_lights_punctual", "KHR_texture_transform"], )" +
         s.extra + R"(
    "nodes": [{"translation": [1, 2, 3], "children": [1]}, {)" +
         s.child + R"(, "mesh": 0},
      {"rotation": [-0.70710678, 0, 0, 0.70710678], "extensions": {"KHR_lights_punctual": {"light": 0}}},
      {"translation": [0, 5, 0], "extensions": {"KHR_lights_punctual": {"light": 1}}}],
    "meshes": [{"primitives": [)" +
         s.primitives + R"(]}],
    "materials": [)" +
         s.material + R"(],
    "extensions": {"KHR_lights_punctual": {"lights": [{"type": "directional", "intensity": 2},
                   {"type": "spot", "color": [1, 0, 0], "intensity": 10, "spot": {"outerConeAngle": 0.5}}]}},
    "buffers": [{"byteLength": 66, "uri": "data:application/octet-stream;base64,)" +
         base64(buf) + R"("}],
    "bufferViews": [{"buffer": 0, "byteOffset": 0, "byteLength": 36},
                    {"buffer": 0, "byteOffset": 36, "byteLength": 24},
                    {"buffer": 0, "byteOffset": 60, "byteLength": 6}],
    "accessors": [{"bufferView": 0, "componentType": 5126, "count": 3, "type": "VEC3"},
                  {"bufferView": 1, "componentType": 5126, "count": 3, "type": "VEC2"},
                  {"bufferView": 2, "componentType": 5123, "count": 3, "type": "SCALAR"}]})";
}

Result<ModelData> parse(const std::string& text, const std::string& base_dir = ".") {
  ImageCache images;
  return parse_gltf(text, "t.gltf", base_dir, images);
}

TEST(GltfWritten, NodeTransformsVFlipAndLights) {
  auto r = parse(make_gltf({}));
  ASSERT_TRUE(r.ok()) << r.error().message;
  const MeshData& m = r->mesh;
  ASSERT_EQ(m.positions.size(), 3u);
  expect_near(m.positions[0], Vec3(1, 2, 3));  // translation (1,2,3) * scale 2
  expect_near(m.positions[1], Vec3(3, 2, 3));
  expect_near(m.positions[2], Vec3(1, 4, 3));
  ASSERT_EQ(m.triangles.size(), 1u);
  EXPECT_EQ(m.triangles[0], UVec3(0, 1, 2));
  EXPECT_TRUE(m.normals.empty());  // none in the file: geometric normals
  ASSERT_EQ(m.uvs.size(), 3u);
  EXPECT_NEAR(m.uvs[0].y, 1.0f, 1e-6f);  // v_ours = 1 - v_gltf
  EXPECT_NEAR(m.uvs[2].x, 0.25f, 1e-6f);
  EXPECT_NEAR(m.uvs[2].y, 0.8f, 1e-6f);
  ASSERT_EQ(m.materials.size(), 1u);
  EXPECT_EQ(m.materials[0].cls, MaterialClass::kDiffuse);
  expect_near(m.materials[0].kd, Vec3(1.0f, 0.5f, 0.25f));

  ASSERT_EQ(r->lights.size(), 2u);
  const Light& sun = r->lights[0];
  EXPECT_EQ(sun.kind, LightKind::kDirectional);
  expect_near(sun.direction, Vec3(0, -1, 0));
  expect_near(sun.color, Vec3(1.0f));  // the brightest light (2 lux) is scaled to 1
  const Light& spot = r->lights[1];
  EXPECT_EQ(spot.kind, LightKind::kPoint);
  expect_near(spot.position, Vec3(0, 5, 0));
  // 10 cd at distance^2 = 17 from the box centre (2,3,3), relative to the 2-lux sun.
  expect_near(spot.color, Vec3(10.0f / 17.0f / 2.0f, 0.0f, 0.0f));
  ASSERT_EQ(r->warnings.size(), 1u);
  EXPECT_EQ(r->warnings[0], "spot light 1 treated as a point light");
}

TEST(GltfWritten, MirroringTransformFlipsTheWinding) {
  Spec s;
  s.child = R"("scale": [-2, 2, 2])";
  auto r = parse(make_gltf(s));
  ASSERT_TRUE(r.ok()) << r.error().message;
  expect_near(r->mesh.positions[1], Vec3(-1, 2, 3));
  EXPECT_EQ(r->mesh.triangles[0], UVec3(0, 2, 1));
}

TEST(GltfWritten, PrimitivesSharingVertexAccessorsShareVertices) {
  Spec s;
  s.material += R"(, {"pbrMetallicRoughness": {"metallicFactor": 0, "roughnessFactor": 0}})";
  s.primitives +=
      R"(, {"attributes": {"POSITION": 0, "TEXCOORD_0": 1}, "indices": 2, "material": 1},
                      {"attributes": {"POSITION": 0}, "mode": 6, "material": 1},
                      {"attributes": {"POSITION": 0}, "mode": 1})";
  auto r = parse(make_gltf(s));
  ASSERT_TRUE(r.ok()) << r.error().message;
  EXPECT_EQ(r->mesh.positions.size(), 6u);  // POSITION+TEXCOORD_0 once, POSITION alone once
  ASSERT_EQ(r->mesh.triangles.size(), 3u);
  EXPECT_EQ(r->mesh.triangles[1], r->mesh.triangles[0]);
  EXPECT_EQ(r->mesh.triangles[2], UVec3(3, 4, 5));  // the fan of the second vertex set
  EXPECT_EQ(r->mesh.face_material, (std::vector<uint16_t>{0, 1, 1}));
  EXPECT_EQ(r->mesh.materials.size(), 2u);
  EXPECT_EQ(r->mesh.materials[1].cls, MaterialClass::kPolished);
  ASSERT_EQ(r->warnings.size(), 2u);
  EXPECT_EQ(r->warnings[0], "1 point/line primitive(s) skipped: only triangles are rendered");
}

TEST(GltfWritten, MatrixTransform) {
  Spec s;
  s.child =
      R"("matrix": [0, 1, 0, 0,  -1, 0, 0, 0,  0, 0, 1, 0,  10, 0, 0, 1])";  // +90° about z, x+10
  auto r = parse(make_gltf(s));
  ASSERT_TRUE(r.ok()) << r.error().message;
  expect_near(r->mesh.positions[1], Vec3(11, 3, 3));  // (1,0,0) -> (0,1,0) + (10,0,0) + (1,2,3)
}

TEST(GltfWritten, NonFinitePositionIsAnError) {
  Spec s;
  s.x0 = std::nanf("");
  auto r = parse(make_gltf(s));
  expect_one_line_error(r, "t.gltf");
  EXPECT_EQ(r.error().message, "t.gltf: accessor 0: non-finite value");
}

TEST(GltfWritten, MaterialMapping) {
  struct Case {
    const char* material;
    MaterialClass cls;
  };
  const Case cases[] = {
      {R"({"pbrMetallicRoughness": {"baseColorFactor": [0.9, 0.8, 0.7, 1], "roughnessFactor": 0.5}})",
       MaterialClass::kMetal},  // metallicFactor defaults to 1
      {R"({"pbrMetallicRoughness": {"metallicFactor": 0, "roughnessFactor": 0.2}})",
       MaterialClass::kPolished},
      {R"({"extensions": {"KHR_materials_transmission": {"transmissionFactor": 1},
           "KHR_materials_ior": {"ior": 1.3}}})",
       MaterialClass::kDielectric},
      {R"({"alphaMode": "BLEND", "pbrMetallicRoughness": {"baseColorFactor": [1, 1, 1, 0.2]}})",
       MaterialClass::kDielectric},
      {R"({"pbrMetallicRoughness": {"metallicFactor": 0}})", MaterialClass::kDiffuse},
  };
  for (const Case& c : cases) {
    SCOPED_TRACE(c.material);
    Spec s;
    s.material = c.material;
    auto r = parse(make_gltf(s));
    ASSERT_TRUE(r.ok()) << r.error().message;
    const Material& m = r->mesh.materials.at(0);
    EXPECT_EQ(m.cls, c.cls);
    if (m.cls == MaterialClass::kMetal) {
      expect_near(m.ks, Vec3(0.9f, 0.8f, 0.7f));
      EXPECT_NEAR(m.phong_exponent, 30.0f, 1e-3f);  // 2 / 0.5^4 - 2
    }
    if (m.cls == MaterialClass::kPolished) {
      expect_near(m.r0, Vec3(0.04f));
      expect_near(m.kh, Vec3(0.8f));
      EXPECT_NEAR(m.phong_exponent, 1248.0f, 0.1f);  // 2 / 0.2^4 - 2
    }
    if (std::strstr(c.material, "1.3")) {
      EXPECT_NEAR(m.ior, 1.3f, 1e-6f);
    }
  }
}

TEST(GltfWritten, TexturesFromADataUriWithSamplerTransformAndMask) {
  Spec s;
  s.material = R"({"alphaMode": "MASK", "alphaCutoff": 0.3,
      "pbrMetallicRoughness": {"metallicFactor": 0, "baseColorTexture": {"index": 0,
        "extensions": {"KHR_texture_transform": {"offset": [0.5, 0], "scale": [2, 2]}}}},
      "normalTexture": {"index": 0}})";
  s.extra = R"("images": [{"uri": "data:image/png;base64,)" + kPng64 + R"("}],
      "samplers": [{"wrapS": 33071, "wrapT": 33071}], "textures": [{"source": 0, "sampler": 0}],)";
  auto r = parse(make_gltf(s));
  ASSERT_TRUE(r.ok()) << r.error().message;
  const MeshData& m = r->mesh;
  const Material& mat = m.materials.at(0);
  ASSERT_EQ(m.textures.size(), 2u);  // sRGB colour and linear normal map share one image
  ASSERT_LT(mat.kd_tex, 2u);
  EXPECT_EQ(mat.alpha_tex, mat.kd_tex);
  EXPECT_EQ(mat.alpha_channel, 3);
  EXPECT_FLOAT_EQ(mat.alpha_cutoff, 0.3f);
  EXPECT_FLOAT_EQ(mat.opacity, 1.0f);
  ASSERT_LT(mat.normal_tex, 2u);
  EXPECT_NE(mat.normal_tex, mat.kd_tex);
  const Texture& colour = m.textures[mat.kd_tex];
  const Texture& normal = m.textures[mat.normal_tex];
  EXPECT_TRUE(colour.srgb);
  EXPECT_FALSE(normal.srgb);
  EXPECT_EQ(colour.image, normal.image);
  ASSERT_TRUE(colour.image);
  EXPECT_EQ(colour.image->width, 2);
  EXPECT_EQ(colour.image->height, 1);
  EXPECT_EQ(colour.wrap, TextureWrap::kClamp);
  EXPECT_EQ(colour.uv_scale, Vec2(2.0f, 2.0f));
  EXPECT_EQ(colour.uv_offset, Vec2(0.5f, -1.0f));  // v: 1 - scale - offset
  EXPECT_EQ(normal.uv_scale, Vec2(1.0f, 1.0f));
}

// Emission: emissiveFactor times KHR_materials_emissive_strength, with its texture (sRGB);
// factors outside [0, 1] and negative or absurd strengths are one-line errors.
TEST(GltfWritten, EmissionFactorStrengthAndTexture) {
  Spec s;
  s.material = R"({"emissiveFactor": [1, 0.5, 0.25], "emissiveTexture": {"index": 0},
      "extensions": {"KHR_materials_emissive_strength": {"emissiveStrength": 8}},
      "pbrMetallicRoughness": {"metallicFactor": 0}})";
  s.extra = R"("images": [{"uri": "data:image/png;base64,)" + kPng64 + R"("}],
      "textures": [{"source": 0}],)";
  auto r = parse(make_gltf(s));
  ASSERT_TRUE(r.ok()) << r.error().message;
  const Material& mat = r->mesh.materials.at(0);
  expect_near(mat.emission, Vec3(8.0f, 4.0f, 2.0f));
  ASSERT_LT(mat.emission_tex, r->mesh.textures.size());
  EXPECT_TRUE(r->mesh.textures[mat.emission_tex].srgb);
  Spec plain;  // no emissive members: no emission
  auto p = parse(make_gltf(plain));
  ASSERT_TRUE(p.ok()) << p.error().message;
  EXPECT_EQ(p->mesh.materials.at(0).emission, Vec3(0.0f));
  for (const char* bad : {R"({"emissiveFactor": [1, -0.5, 0]})", R"({"emissiveFactor": [2, 0, 0]})",
                          R"({"emissiveFactor": [1, 1, 1], "extensions":
                              {"KHR_materials_emissive_strength": {"emissiveStrength": -1}}})"}) {
    SCOPED_TRACE(bad);
    Spec b;
    b.material = bad;
    auto e = parse(make_gltf(b));
    ASSERT_FALSE(e.ok());
    EXPECT_NE(e.error().message.find("emissive"), std::string::npos) << e.error().message;
    EXPECT_EQ(e.error().message.find('\n'), std::string::npos) << e.error().message;
  }
}

TEST(GltfWritten, ImageFilesResolveRelativeToTheModelWithPercentDecoding) {
  TempDir dir;
  std::string png;
  {
    // Decode kPng64 through a data-URI glTF, then write the bytes out.
    static const std::string k = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
    uint32_t acc = 0;
    int bits = 0;
    for (char c : kPng64) {
      if (c == '=') break;
      acc = acc << 6 | uint32_t(k.find(c));
      bits += 6;
      if (bits >= 8) {
        bits -= 8;
        png += char(acc >> bits & 0xff);
      }
    }
  }
  dir.write("my tex.png", png);
  Spec s;
  s.material =
      R"({"pbrMetallicRoughness": {"metallicFactor": 0, "baseColorTexture": {"index": 0}}})";
  s.extra = R"("images": [{"uri": "my%20tex.png"}], "textures": [{"source": 0}],)";
  dir.write("ok.gltf", make_gltf(s));
  ImageCache images;
  auto r = load_gltf(dir.path + "/ok.gltf", images);
  ASSERT_TRUE(r.ok()) << r.error().message;
  EXPECT_EQ(images.size(), 1u);
  EXPECT_EQ(r->mesh.textures.at(0).image->width, 2);

  s.extra = R"("images": [{"uri": "missing%20image.png"}], "textures": [{"source": 0}],)";
  dir.write("missing.gltf", make_gltf(s));
  auto bad = load_gltf(dir.path + "/missing.gltf", images);
  expect_one_line_error(bad, "missing.gltf");
  EXPECT_NE(bad.error().message.find("'missing%20image.png'"), std::string::npos)
      << bad.error().message;
}

TEST(GltfWritten, BadInputGivesOneLineErrors) {
  const std::string good = make_gltf({});
  auto replaced = [&](const std::string& from, const std::string& to) {
    std::string t = good;
    const size_t at = t.find(from);
    EXPECT_NE(at, std::string::npos) << from;
    return at == std::string::npos ? t : t.replace(at, from.size(), to);
  };
  const std::pair<std::string, const char*> cases[] = {
      {replaced(R"("count": 3, "type": "VEC3")", R"("count": 4, "type": "VEC3")"),
       "run past the end"},
      {replaced(R"("byteLength": 36})", R"("byteLength": 36, "byteStride": 400})"), "byteStride"},
      {replaced(R"("bufferView": 2,)", R"("bufferView": 7,)"),
       "accessor[2] invalid bufferView"},  // tinygltf's check
      {replaced(R"("indices": 2)", R"("indices": 9)"),
       "indices accessor out of bounds"},  // tinygltf's
      {replaced(R"("material": 0)", R"("material": 3)"), "material 3 out of range"},
      {replaced(R"("children": [1])", R"("children": [0])"), "reached twice"},
      {replaced(R"("mesh": 0})", R"("mesh": 5})"), "mesh 5 out of range"},
      {replaced(R"("componentType": 5123, "count": 3, "type": "SCALAR")",
                R"("componentType": 5123, "count": 1, "type": "VEC3")"),
       "indices must be"},
      {replaced(R"("extensionsUsed")",
                R"("extensionsRequired": ["EXT_meshopt_compression"], "extensionsUsed")"),
       "extensionsRequired: 'EXT_meshopt_compression' is not supported"},
      {replaced(R"("byteLength": 66)", R"("byteLength": 70)"), "t.gltf: "},
      {replaced(R"({"asset")", std::string(200, '[')), "nested deeper"},
      {replaced(R"("scene": 0)", R"("scene": 0,,)"), "JSON"},
      {"", "JSON"},
      {"glTF", "GLB: truncated header"},
  };
  for (const auto& [text, what] : cases) {
    SCOPED_TRACE(what);
    auto r = parse(text);
    expect_one_line_error(r, "t.gltf");
    if (!r.ok()) {
      EXPECT_NE(r.error().message.find(what), std::string::npos) << r.error().message;
    }
  }
}

TEST(GltfWritten, BufferUriSchemesAreRefused) {
  // Buffer URIs with a scheme are refused before tinygltf could try them.
  std::string t = make_gltf({});
  const size_t at = t.find("data:application");
  t.replace(at, t.find('"', at) - at, "http://example.com/x.bin");
  auto r = parse(t);
  expect_one_line_error(r, "t.gltf");
  EXPECT_NE(r.error().message.find("URI scheme 'http' is not supported"), std::string::npos);
}

}  // namespace
}  // namespace frameless
