// Debian's glTF samples (assimp-testmodels) whose meshes several nodes place load as shared meshes
// and instances: the same triangles represented as by the flattened model (each placement a
// copy, as before instancing), and the same image.
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <string>
#include <utility>
#include <vector>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "core/accel/instance.h"
#include "core/io/file_util.h"
#include "core/scene/scene_build.h"
#include "core/scene/scene_finalize.h"
#include "core/scenes/scene_load.h"
#include "core/shading/render_sample.h"

#include "gltf_instances_util.h"
#include "gltf_test_util.h"

namespace frameless {
namespace {

using test_util::differing;
using test_util::kMaxDiffering;
using test_util::kModels;
using test_util::kTolerance;
using test_util::put;
using test_util::render;

uint64_t represented(const MeshData& m) {
  uint64_t n = m.triangles.size();
  for (const MeshPlacement& p : m.placements) n += m.shared[p.mesh].triangles.size();
  return n;
}

// The glTF JSON with a copy of a mesh for every node after the first that names it: the loader
// flattens every placement, as it did before instancing (the reference these tests compare to).
std::string unshared_json(const std::string& text) {
  nlohmann::json j = nlohmann::json::parse(text);
  std::vector<uint8_t> used(j["meshes"].size(), 0);
  for (nlohmann::json& node : j["nodes"]) {
    if (!node.contains("mesh")) continue;
    const size_t m = node["mesh"].get<size_t>();
    if (used[m]++) {
      node["mesh"] = j["meshes"].size();
      j["meshes"].push_back(j["meshes"][m]);
    }
  }
  return j.dump();
}

uint32_t u32(const std::string& b, size_t at) {
  uint32_t v;
  std::memcpy(&v, b.data() + at, 4);
  return v;
}

// The same for a GLB: its JSON chunk replaced, the binary chunk kept.
std::string unshared_glb(const std::string& glb) {
  std::string json = unshared_json(glb.substr(20, u32(glb, 12)));
  while (json.size() % 4) json += ' ';
  const std::string bin = glb.substr(20 + u32(glb, 12));
  std::string out = glb.substr(0, 8);
  put(out, uint32_t(12 + 8 + json.size() + bin.size()));
  put(out, uint32_t(json.size()));
  out += "JSON" + json + bin;
  return out;
}

// Instanced and flattened (unshared) loads of a sample: the same triangles represented, and the
// same image when the instanced model is rendered.
struct Loaded {
  ModelData instanced, flattened;
};

Loaded load_both(const std::string& file, bool glb) {
  ImageCache images;
  auto bytes = read_file_bytes(file);
  EXPECT_TRUE(bytes.ok());
  const std::string dir = file.substr(0, file.find_last_of('/'));
  auto a = load_gltf(file, images);
  auto b = parse_gltf(glb ? unshared_glb(*bytes) : unshared_json(*bytes), file, dir, images);
  EXPECT_TRUE(a.ok()) << a.error().message;
  EXPECT_TRUE(b.ok()) << b.error().message;
  if (!a.ok() || !b.ok()) return {};
  return {std::move(*a), std::move(*b)};
}

size_t differing_renders(const MeshData& instanced, const MeshData& flattened) {
  auto a = make_mesh_scene(instanced, "instanced");
  auto b = make_mesh_scene(flattened, "flattened");
  EXPECT_FALSE(a->geometry.instances.empty());
  EXPECT_TRUE(b->geometry.instances.empty());
  finalize_scene(*a);
  finalize_scene(*b);
  return differing(render(*a), render(*b), kTolerance);
}

// 2CylinderEngine places 14 of its 29 meshes 52 times: they are stored once, and the model
// renders as its flattened copy.
TEST(GltfInstancesAssimp, TwoCylinderEngineSharesItsRepeatedMeshes) {
  REQUIRE_ASSIMP_MODELS();
  const Loaded l = load_both(kModels + "/2CylinderEngine-glTF-Binary/2CylinderEngine.glb", true);
  const MeshData& m = l.instanced.mesh;
  EXPECT_EQ(m.shared.size(), 14u);
  EXPECT_EQ(m.placements.size(), 52u);
  EXPECT_TRUE(l.flattened.mesh.placements.empty());
  uint64_t stored = m.triangles.size();
  for (const MeshData& s : m.shared) stored += s.triangles.size();
  // Non-degenerate triangles of the placed meshes, counted from the file's accessors: all
  // represented, as many as flattening stores, of which 59% are stored.
  EXPECT_EQ(represented(m), 110342u);
  EXPECT_EQ(l.flattened.mesh.triangles.size(), 110342u);
  EXPECT_EQ(stored, 65317u);
  EXPECT_LE(differing_renders(m, l.flattened.mesh), kMaxDiffering);
}

// KHR_texture_transform textures on shared meshes: the same image as the flattened copies.
TEST(GltfInstancesAssimp, TextureTransformTestSharesTexturedMeshes) {
  REQUIRE_ASSIMP_MODELS();
  const Loaded l = load_both(kModels + "/textureTransform/TextureTransformTest.gltf", false);
  const MeshData& m = l.instanced.mesh;
  EXPECT_EQ(m.shared.size(), 2u);
  EXPECT_EQ(m.placements.size(), 5u);
  EXPECT_EQ(represented(m), 24u);
  EXPECT_EQ(l.flattened.mesh.triangles.size(), 24u);
  EXPECT_LE(differing_renders(m, l.flattened.mesh), kMaxDiffering);
}

}  // namespace
}  // namespace frameless
