// glTF input from Debian's assimp-testmodels: good models (as .gltf, .glb and embedded, shared
// images, many materials, cameras, primitive modes) and broken ones (one-line errors, truncated
// and corrupted GLBs that never crash).
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <string>
#include <utility>

#include <gtest/gtest.h>

#include "core/io/file_util.h"
#include "core/scene/scene_build.h"
#include "core/scenes/scene_load.h"

#include "gltf_test_util.h"

namespace frameless {
namespace {

using test_util::expect_near;
using test_util::expect_one_line_error;
using test_util::kModels;

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

}  // namespace
}  // namespace frameless
