// glTF input: Debian's assimp-testmodels (good and broken models), and small glTFs written here
// (node transforms, v flip, material mapping, lights, textures, bad input).
#include <unistd.h>

#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>

#include <gtest/gtest.h>

#include "core/scene_build.h"
#include "core/scene_io.h"

namespace frameless {
namespace {

const std::string kModels = "/usr/share/assimp/models/glTF2";

#define REQUIRE_ASSIMP_MODELS()          \
  if (!std::filesystem::exists(kModels)) \
  GTEST_SKIP() << "assimp-testmodels is not installed (apt-get install assimp-testmodels)"

// A one-line error naming the file.
void expect_one_line_error(const Result<ModelData>& r, const std::string& name) {
  ASSERT_FALSE(r.ok()) << name << " loaded";
  const std::string& msg = r.error().message;
  EXPECT_EQ(msg.find('\n'), std::string::npos) << msg;
  EXPECT_NE(msg.find(name), std::string::npos) << msg;
}

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

std::string base64(const std::string& in) {
  static const char* k = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
  std::string out;
  for (size_t i = 0; i < in.size(); i += 3) {
    uint32_t v = uint32_t(uint8_t(in[i])) << 16;
    if (i + 1 < in.size()) v |= uint32_t(uint8_t(in[i + 1])) << 8;
    if (i + 2 < in.size()) v |= uint32_t(uint8_t(in[i + 2]));
    out += k[v >> 18 & 63];
    out += k[v >> 12 & 63];
    out += i + 1 < in.size() ? k[v >> 6 & 63] : '=';
    out += i + 2 < in.size() ? k[v & 63] : '=';
  }
  return out;
}

template <class T>
void put(std::string& b, T v) {
  b.append(reinterpret_cast<const char*>(&v), sizeof v);
}

// A 2x1 RGBA PNG: opaque red, transparent blue.
const std::string kPng64 =
    "iVBORw0KGgoAAAANSUhEUgAAAAIAAAABCAYAAAD0In+KAAAADUlEQVR4nGP4z8AARgAO+gL+"
    "9R5MqQAAAABJRU5ErkJggg==";

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

void expect_near(const Vec3& a, const Vec3& b) {
  EXPECT_NEAR(a.x, b.x, 1e-5f);
  EXPECT_NEAR(a.y, b.y, 1e-5f);
  EXPECT_NEAR(a.z, b.z, 1e-5f);
}

TEST(GltfAssimp, BoxTexturedAsGltfGlbAndEmbedded) {
  REQUIRE_ASSIMP_MODELS();
  for (const char* file :
       {"BoxTextured-glTF/BoxTextured.gltf", "BoxTextured-glTF-Binary/BoxTextured.glb",
        "BoxTextured-glTF-Embedded/BoxTextured.gltf"}) {
    SCOPED_TRACE(file);
    ImageCache images;
    auto r = load_gltf(kModels + "/" + file, images);
    ASSERT_TRUE(r.ok()) << r.error().message;
    const MeshData& m = r->mesh;
    EXPECT_EQ(m.triangles.size(), 12u);
    EXPECT_EQ(m.uvs.size(), m.positions.size());
    EXPECT_EQ(m.normals.size(), m.positions.size());
    ASSERT_EQ(m.face_material.size(), 12u);
    ASSERT_EQ(m.materials.size(), 1u);
    const Material& mat = m.materials[0];
    EXPECT_EQ(mat.cls, MaterialClass::kDiffuse);  // metallicFactor 0, roughness 1
    ASSERT_LT(mat.kd_tex, m.textures.size());
    const Texture& t = m.textures[mat.kd_tex];
    ASSERT_TRUE(t.image);
    EXPECT_EQ(t.image->width, 211);  // CesiumLogoFlat.png
    EXPECT_EQ(t.image->height, 211);
    EXPECT_TRUE(t.srgb);
    for (const Vec2& uv : m.uvs) EXPECT_TRUE(uv.y >= 0.0f && uv.y <= 1.0f);
    EXPECT_TRUE(r->warnings.empty());
  }
}

TEST(GltfAssimp, ImageFilesAreSharedThroughTheCache) {
  REQUIRE_ASSIMP_MODELS();
  ImageCache images;
  auto a = load_gltf(kModels + "/BoxTextured-glTF/BoxTextured.gltf", images);
  auto b = load_gltf(kModels + "/BoxTextured-glTF/BoxTextured.gltf", images);
  ASSERT_TRUE(a.ok() && b.ok());
  EXPECT_EQ(images.size(), 1u);
  EXPECT_EQ(a->mesh.textures[0].image, b->mesh.textures[0].image);
}

TEST(GltfAssimp, TwoCylinderEngineHasManyTrianglesAndMaterials) {
  REQUIRE_ASSIMP_MODELS();
  ImageCache images;
  auto r = load_gltf(kModels + "/2CylinderEngine-glTF-Binary/2CylinderEngine.glb", images);
  ASSERT_TRUE(r.ok()) << r.error().message;
  EXPECT_GT(r->mesh.triangles.size(), 50000u);
  EXPECT_GT(r->mesh.materials.size(), 3u);
  EXPECT_EQ(r->mesh.face_material.size(), r->mesh.triangles.size());
  for (uint16_t f : r->mesh.face_material) ASSERT_LT(f, r->mesh.materials.size());
  for (const UVec3& t : r->mesh.triangles)
    for (int k = 0; k < 3; ++k) ASSERT_LT(t[k], r->mesh.positions.size());
}

TEST(GltfAssimp, CamerasBecomeCamerasAndOrthographicIsSkipped) {
  REQUIRE_ASSIMP_MODELS();
  ImageCache images;
  auto r = load_gltf(kModels + "/cameras/Cameras.gltf", images);
  ASSERT_TRUE(r.ok()) << r.error().message;
  ASSERT_EQ(r->cameras.size(), 1u);
  const Camera& c = r->cameras[0];
  expect_near(c.eye, Vec3(0.5f, 0.5f, 3.0f));
  expect_near(c.look, Vec3(0.5f, 0.5f, 2.0f));
  expect_near(c.up, Vec3(0.0f, 1.0f, 0.0f));
  EXPECT_NEAR(c.fov_deg, 0.7f * 180.0f / kPi, 1e-4f);
  ASSERT_EQ(r->warnings.size(), 1u);
  EXPECT_NE(r->warnings[0].find("orthographic"), std::string::npos);
}

TEST(GltfAssimp, PrimitiveModesTrianglesStripsAndFans) {
  REQUIRE_ASSIMP_MODELS();
  const std::string dir = kModels + "/glTF-Asset-Generator/Mesh_PrimitiveMode/";
  for (int i = 0; i <= 15; ++i) {
    const std::string file =
        dir + "Mesh_PrimitiveMode_" + (i < 10 ? "0" : "") + std::to_string(i) + ".gltf";
    SCOPED_TRACE(file);
    ImageCache images;
    auto r = load_gltf(file, images);
    const bool triangles = (i >= 4 && i <= 6) || i >= 11;
    if (triangles) {
      ASSERT_TRUE(r.ok()) << r.error().message;
      EXPECT_EQ(r->mesh.triangles.size(), 2u);
    } else {
      expect_one_line_error(r, file);  // points and lines only: nothing to render
      EXPECT_NE(r.error().message.find("no triangles"), std::string::npos);
    }
  }
}

TEST(GltfAssimp, BrokenModelsGiveOneLineErrors) {
  REQUIRE_ASSIMP_MODELS();
  const std::pair<const char*, const char*> cases[] = {
      {"RecursiveNodes/RecursiveNodes.gltf", "reached twice"},
      {"IndexOutOfRange/IndexOutOfRange.gltf", "out of range"},
      {"IndexOutOfRange/AllIndicesOutOfRange.gltf", "out of range"},
      {"MissingBin/BoxTextured.gltf", "buffer 0: cannot read 'BoxTextured0.bin'"},
      {"BoxWithInfinites-glTF-Binary/BoxWithInfinites.glb", "non-finite value"},
      {"wrongTypes/badArray.gltf", "meshes[0].primitives: expected an array of objects"},
      {"wrongTypes/badExtension.gltf", "KHR_texture_transform: expected an object"},
      {"wrongTypes/badNumber.gltf", "normalTexture.scale: expected a number"},
      {"wrongTypes/badObject.gltf", "pbrMetallicRoughness: expected an object"},
      {"wrongTypes/badString.gltf", "scenes[0].name: expected a string"},
      {"wrongTypes/badUint.gltf", "index: expected a non-negative integer"},
      {"SchemaFailures/sceneWrongType.gltf", "scene: expected a non-negative integer"},
      {"draco/2CylinderEngine.gltf",
       "extensionsRequired: 'KHR_draco_mesh_compression' is not supported"},
      {"TestNoRootNode/NoScene.gltf", "no triangles"},
      {"TestNoRootNode/SceneWithoutNodes.gltf", "no triangles"},
  };
  for (const auto& [file, what] : cases) {
    SCOPED_TRACE(file);
    ImageCache images;
    auto r = load_gltf(kModels + "/" + file, images);
    expect_one_line_error(r, file);
    if (!r.ok()) {
      EXPECT_NE(r.error().message.find(what), std::string::npos) << r.error().message;
    }
  }
}

TEST(GltfAssimp, TruncatedAndCorruptedGlbNeverCrash) {
  REQUIRE_ASSIMP_MODELS();
  auto bytes = read_file_bytes(kModels + "/BoxTextured-glTF-Binary/BoxTextured.glb");
  ASSERT_TRUE(bytes.ok());
  ImageCache images;
  for (size_t n = 0; n < bytes->size(); n += 97) {
    auto r = parse_gltf(bytes->substr(0, n), "cut.glb", ".", images);
    if (!r.ok()) {
      EXPECT_EQ(r.error().message.find('\n'), std::string::npos) << r.error().message;
    }
  }
  // The BIN chunk claims 8 bytes more than the file holds (tinygltf would read past the end).
  std::string bad = *bytes;
  const size_t bin = 20 + (uint8_t(bad[12]) | uint8_t(bad[13]) << 8 | uint8_t(bad[14]) << 16);
  uint32_t len;
  std::memcpy(&len, bad.data() + bin, 4);
  len += 8;
  std::memcpy(bad.data() + bin, &len, 4);
  auto r = parse_gltf(bad, "bin.glb", ".", images);
  ASSERT_FALSE(r.ok());
  EXPECT_NE(r.error().message.find("BIN chunk runs past the end"), std::string::npos)
      << r.error().message;
  // Flipped bytes throughout the binary chunk and the JSON.
  uint32_t seed = 1;
  for (int k = 0; k < 300; ++k) {
    std::string b = *bytes;
    seed = seed * 1664525u + 1013904223u;
    b[seed % b.size()] = char(seed >> 24);
    auto q = parse_gltf(b, "flip.glb", ".", images);
    if (!q.ok()) {
      EXPECT_EQ(q.error().message.find('\n'), std::string::npos) << q.error().message;
    }
  }
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
