// glTF meshes placed by two or more nodes load as one shared mesh and one instance per node
// (mesh_gltf.cpp, gltf_instances.cpp, add_mesh): placements, hierarchies, composition with the
// caller's transform, renders equal to the flattened model's, bad input (Debian's samples:
// gltf_instances_assimp_test.cpp).
#include <unistd.h>

#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>

#include <glm/gtc/matrix_transform.hpp>
#include <glm/gtc/quaternion.hpp>
#include <gtest/gtest.h>

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

using test_util::base64;
using test_util::differing;
using test_util::Image;
using test_util::kMaxDiffering;
using test_util::kPng64;
using test_util::kTolerance;
using test_util::put;
using test_util::render;

struct TempDir {
  std::string path;
  TempDir() {
    path = (std::filesystem::temp_directory_path() /
            ("frameless_gltf_inst_" + std::to_string(::getpid()) + "_" +
             std::to_string(reinterpret_cast<uintptr_t>(this))))
               .string();
    std::filesystem::remove_all(path);
    std::filesystem::create_directories(path);
  }
  ~TempDir() { std::filesystem::remove_all(path); }
  std::string write(const std::string& name, const std::string& bytes) const {
    std::ofstream(path + "/" + name, std::ios::binary) << bytes;
    return path + "/" + name;
  }
};

constexpr int kGridX = 5, kGridY = 4;  // leaf vertices
constexpr size_t kLeafVertices = kGridX * kGridY;
constexpr size_t kLeafTriangles = 2 * (kGridX - 1) * (kGridY - 1);

// The leaf: a curved sheet z = 0.2 sin(3x) + 0.15 y^2 over x in [-0.5, 0.5], y in [0, 1],
// facing +z, with its analytic normals and u along x, v along y; positions are then scaled by
// kSize (the leaves fill more of the image) and `scale`.
std::string leaf_buffer(float scale) {
  constexpr float kSize = 1.6f;
  std::string pos, nrm, uv, idx;
  for (int j = 0; j < kGridY; ++j)
    for (int i = 0; i < kGridX; ++i) {
      const float x = -0.5f + float(i) / (kGridX - 1), y = float(j) / (kGridY - 1);
      const float z = 0.2f * std::sin(3.0f * x) + 0.15f * y * y;
      for (float f : {x * kSize * scale, y * kSize * scale, z * kSize * scale}) put(pos, f);
      const Vec3 n = glm::normalize(Vec3(-0.6f * std::cos(3.0f * x), -0.3f * y, 1.0f));
      for (float f : {n.x, n.y, n.z}) put(nrm, f);
      for (float f : {x + 0.5f, y}) put(uv, f);
    }
  for (int j = 0; j + 1 < kGridY; ++j)
    for (int i = 0; i + 1 < kGridX; ++i) {
      const uint16_t a = uint16_t(j * kGridX + i), b = uint16_t(a + 1);
      const uint16_t c = uint16_t(b + kGridX), d = uint16_t(a + kGridX);
      for (uint16_t k : {a, b, c, a, c, d}) put(idx, k);
    }
  return pos + nrm + uv + idx;
}

// A leaf mesh placed by nodes, and a ground quad (mesh 0, placed once by the first root). The
// leaf is written `copies` times as meshes 1..copies with identical primitives: a file whose
// nodes name meshes 1, 2, 3 places three copies the loader flattens, the same nodes all naming
// mesh 1 place one shared mesh. `nodes` are the leaf nodes (JSON objects, "@K" replaced by the
// mesh index of the K-th leaf placement, K = 0..9); `roots` the scene's leaf roots.
struct ModelSpec {
  std::string nodes;
  std::string roots = "0, 1, 2";
  int copies = 1;
  float leaf_scale = 1.0f;
};

std::string make_model(const ModelSpec& s) {
  std::string nodes;
  size_t leaf_nodes = 0;
  for (size_t i = 0; i < s.nodes.size(); ++i) {
    if (s.nodes[i] == '{') ++leaf_nodes;
    if (s.nodes[i] != '@' || i + 1 == s.nodes.size()) {
      nodes += s.nodes[i];
      continue;
    }
    const int k = s.nodes[++i] - '0';
    nodes += std::to_string(s.copies == 1 ? 1 : 1 + k % s.copies);
  }
  std::string buf = leaf_buffer(s.leaf_scale);
  while (buf.size() % 4) buf += '\0';
  const size_t ground_at = buf.size();
  for (float f : {-2.2f, -0.3f, 1.8f, 2.2f, -0.3f, 1.8f, 2.2f, -0.3f, -1.0f, -2.2f, -0.3f, -1.0f})
    put(buf, f);
  for (uint16_t k : {0, 1, 2, 0, 2, 3}) put(buf, k);
  std::string meshes =
      R"({"primitives": [{"attributes": {"POSITION": 4}, "indices": 5, "material": 0}]})";
  for (int c = 0; c < s.copies; ++c)
    meshes += R"(, {"primitives": [{"attributes": {"POSITION": 0, "NORMAL": 1, "TEXCOORD_0": 2},
                                   "indices": 3, "material": 1}]})";
  // The ground first (its material is the model's first), then the leaves and two lights.
  std::string roots = std::to_string(leaf_nodes) + ", " + s.roots;
  for (size_t k = 1; k < 3; ++k) roots += ", " + std::to_string(leaf_nodes + k);
  auto view = [](size_t offset, size_t length) {
    return R"({"buffer": 0, "byteOffset": )" + std::to_string(offset) + R"(, "byteLength": )" +
           std::to_string(length) + "}";
  };
  auto accessor = [](int view, int type, size_t count, const char* shape) {
    return R"({"bufferView": )" + std::to_string(view) + R"(, "componentType": )" +
           std::to_string(type) + R"(, "count": )" + std::to_string(count) + R"(, "type": ")" +
           shape + "\"}";
  };
  const size_t nv = kLeafVertices, ni = 3 * kLeafTriangles;
  std::string out = R"({"asset": {"version": "2.0"}, "scene": 0, "scenes": [{"nodes": [)";
  out += roots;
  out += R"(]}], "extensionsUsed": ["KHR_lights_punctual"], "nodes": [)";
  out += nodes;
  out += R"(, {"mesh": 0},
      {"translation": [2, 4, 3], "extensions": {"KHR_lights_punctual": {"light": 0}}},
      {"translation": [-3, 3, 2], "extensions": {"KHR_lights_punctual": {"light": 1}}}],
    "extensions": {"KHR_lights_punctual": {"lights": [{"type": "point", "intensity": 30},
                   {"type": "point", "color": [0.6, 0.7, 1], "intensity": 12}]}},
    "materials": [{"pbrMetallicRoughness": {"baseColorFactor": [0.5, 0.6, 0.5, 1],
                     "metallicFactor": 0, "roughnessFactor": 1}},
                  {"alphaMode": "MASK", "pbrMetallicRoughness": {"metallicFactor": 0,
                     "roughnessFactor": 0.3, "baseColorTexture": {"index": 0}}}],
    "textures": [{"source": 0}], "images": [{"uri": "data:image/png;base64,)";
  out += kPng64;
  out += R"("}], "meshes": [)";
  out += meshes;
  out += R"(], "buffers": [{"byteLength": )";
  out += std::to_string(buf.size());
  out += R"(, "uri": "data:application/octet-stream;base64,)";
  out += base64(buf);
  out += R"("}], "bufferViews": [)";
  out += view(0, 12 * nv) + ", " + view(12 * nv, 12 * nv) + ", " + view(24 * nv, 8 * nv) + ", " +
         view(32 * nv, 2 * ni) + ", " + view(ground_at, 48) + ", " + view(ground_at + 48, 12);
  out += R"(], "accessors": [)";
  out += accessor(0, 5126, nv, "VEC3") + ", " + accessor(1, 5126, nv, "VEC3") + ", " +
         accessor(2, 5126, nv, "VEC2") + ", " + accessor(3, 5123, ni, "SCALAR") + ", " +
         accessor(4, 5126, 4, "VEC3") + ", " + accessor(5, 5123, 6, "SCALAR");
  out += "]}";
  return out;
}

// Three placements: a translation, a rotation about an oblique axis, and a mirroring
// non-uniform scale.
const std::string kThreeNodes =
    R"({"translation": [-1.4, 0.1, 0.2], "mesh": @0},
       {"translation": [1.3, 0.3, -0.4], "rotation": [0.2236, 0.4472, 0.1118, 0.8597], "mesh": @1},
       {"translation": [0.1, 0.2, 1.1], "scale": [-1.3, 0.6, 1.1], "mesh": @2})";
const std::string kThreeNodesNoRotation =
    R"({"translation": [-1.4, 0.1, 0.2], "mesh": @0},
       {"translation": [1.3, 0.3, -0.4], "mesh": @1},
       {"translation": [0.1, 0.2, 1.1], "scale": [-1.3, 0.6, 1.1], "mesh": @2})";

// A parent with translation, rotation and a non-uniform scale over two placing children (one by
// TRS, one by a matrix) and a grandchild under the first child.
const std::string kHierarchy =
    R"({"translation": [0.5, 0.2, -0.3], "rotation": [0, 0.3827, 0, 0.9239], "scale": [1.2, 0.8, 1],
        "children": [1, 2]},
       {"translation": [-1, 0, 0.5], "rotation": [0.2588, 0, 0, 0.9659], "mesh": @0, "children": [3]},
       {"matrix": [0, 0, -1, 0,  0, 1, 0, 0,  1, 0, 0, 0,  1.5, 0.1, 0, 1], "mesh": @1},
       {"translation": [0, 1.2, 0], "scale": [0.5, -0.5, 0.5], "mesh": @2})";

Result<ModelData> parse(const std::string& text) {
  ImageCache images;
  return parse_gltf(text, "t.gltf", ".", images);
}

// The world matrices the test expects, composed here independently of the loader.
glm::mat4 trs(const Vec3& t, const glm::quat& r, const Vec3& s) {
  return glm::translate(glm::mat4(1.0f), t) * glm::mat4_cast(r) * glm::scale(glm::mat4(1.0f), s);
}
glm::quat quat(float x, float y, float z, float w) { return glm::normalize(glm::quat(w, x, y, z)); }

void expect_near(const glm::mat4& a, const glm::mat4& b, float tol = 2e-5f) {
  for (int c = 0; c < 4; ++c)
    for (int r = 0; r < 4; ++r)
      EXPECT_NEAR(a[c][r], b[c][r], tol) << "column " << c << " row " << r;
}

void expect_near(const Vec3& a, const Vec3& b, float tol) {
  EXPECT_NEAR(a.x, b.x, tol);
  EXPECT_NEAR(a.y, b.y, tol);
  EXPECT_NEAR(a.z, b.z, tol);
}

// Each placement of the shared leaf puts its vertices where the flattened copy (in node order,
// after the ground's 4 vertices) has them.
void expect_placements_match_copies(const MeshData& instanced, const MeshData& flat) {
  ASSERT_EQ(instanced.shared.size(), 1u);
  const MeshData& leaf = instanced.shared[0];
  ASSERT_GE(flat.positions.size(), 4 + instanced.placements.size() * kLeafVertices);
  for (size_t k = 0; k < instanced.placements.size(); ++k)
    for (size_t i = 0; i < kLeafVertices; ++i) {
      const Vec3 p(instanced.placements[k].to_model * Vec4(leaf.positions[i], 1.0f));
      expect_near(p, flat.positions[4 + k * kLeafVertices + i], 1e-5f);
    }
}

TEST(GltfInstances, MeshPlacedByThreeNodesBecomesOneSharedMesh) {
  auto r = parse(make_model({kThreeNodes}));
  ASSERT_TRUE(r.ok()) << r.error().message;
  const MeshData& m = r->mesh;
  ASSERT_EQ(m.shared.size(), 1u);
  ASSERT_EQ(m.placements.size(), 3u);
  EXPECT_EQ(m.triangles.size(), 2u);       // the ground, used once, stays flat; no leaf triangles
  EXPECT_EQ(m.positions.size(), 4u + 6u);  // its own vertices with flat normals: 2 x 3 more
  const MeshData& leaf = m.shared[0];
  EXPECT_EQ(leaf.triangles.size(), kLeafTriangles);
  EXPECT_EQ(leaf.positions.size(), kLeafVertices);
  EXPECT_EQ(leaf.normals.size(), kLeafVertices);
  EXPECT_EQ(leaf.uvs.size(), kLeafVertices);
  EXPECT_TRUE(leaf.materials.empty());
  ASSERT_EQ(leaf.face_material.size(), kLeafTriangles);
  ASSERT_EQ(m.materials.size(), 2u);
  EXPECT_EQ(leaf.face_material[0], 1u);  // materials in order of first use: the ground's first
  EXPECT_TRUE(m.materials[1].cutout());  // MASK: the leaf's own material
  expect_near(m.placements[0].to_model, trs({-1.4f, 0.1f, 0.2f}, glm::quat(1, 0, 0, 0), Vec3(1)));
  expect_near(m.placements[1].to_model,
              trs({1.3f, 0.3f, -0.4f}, quat(0.2236f, 0.4472f, 0.1118f, 0.8597f), Vec3(1)));
  expect_near(m.placements[2].to_model,
              trs({0.1f, 0.2f, 1.1f}, glm::quat(1, 0, 0, 0), {-1.3f, 0.6f, 1.1f}));

  // The same nodes naming three identical meshes: three flattened copies, as before.
  auto f = parse(make_model({kThreeNodes, "0, 1, 2", 3}));
  ASSERT_TRUE(f.ok()) << f.error().message;
  EXPECT_TRUE(f->mesh.shared.empty());
  EXPECT_EQ(f->mesh.triangles.size(), 2 + 3 * kLeafTriangles);
  expect_placements_match_copies(m, f->mesh);

  // Through the command line's path (frameless render/view model.gltf).
  TempDir dir;
  auto s = load_scene(dir.write("leaves.gltf", make_model({kThreeNodes})));
  ASSERT_TRUE(s.ok()) << s.error().message;
  const Geometry& g = (*s)->geometry;
  EXPECT_EQ(g.instance_meshes.size(), 1u);
  EXPECT_EQ(g.instances.size(), 3u);
  EXPECT_EQ(g.num_triangles(), 2u);
  EXPECT_EQ(represented_triangles(g), 2 + 3 * kLeafTriangles);
}

// The instanced model renders as the flattened one; with the middle node's rotation dropped
// from the instanced file the same comparison fails (the test sees a wrong transform).
TEST(GltfInstances, InstancedModelRendersLikeTheFlattenedOne) {
  TempDir dir;
  auto flat = load_scene(dir.write("flat.gltf", make_model({kThreeNodes, "0, 1, 2", 3})));
  auto inst = load_scene(dir.write("inst.gltf", make_model({kThreeNodes})));
  auto wrong = load_scene(dir.write("wrong.gltf", make_model({kThreeNodesNoRotation})));
  ASSERT_TRUE(flat.ok()) << flat.error().message;
  ASSERT_TRUE(inst.ok()) << inst.error().message;
  ASSERT_TRUE(wrong.ok()) << wrong.error().message;
  ASSERT_EQ((*inst)->geometry.instances.size(), 3u);
  ASSERT_TRUE((*flat)->geometry.instances.empty());
  const Image a = render(**flat), b = render(**inst), c = render(**wrong);
  // The leaves cover a good part of the image: their red texels, and cut-out holes.
  size_t red = 0;
  for (const Vec3& p : a.rgb) red += p.x > 2.0f * p.y + 0.02f ? 1 : 0;
  EXPECT_GT(red, 50u);
  EXPECT_LE(differing(a, b, kTolerance), kMaxDiffering);
  EXPECT_GT(differing(a, c, kTolerance), 10 * kMaxDiffering);
}

TEST(GltfInstances, ParentTransformsComposeWithTheChildren) {
  const ModelSpec spec{kHierarchy, "0"};
  auto r = parse(make_model(spec));
  ASSERT_TRUE(r.ok()) << r.error().message;
  const MeshData& m = r->mesh;
  ASSERT_EQ(m.shared.size(), 1u);
  ASSERT_EQ(m.placements.size(), 3u);
  const glm::mat4 parent = trs({0.5f, 0.2f, -0.3f}, quat(0, 0.3827f, 0, 0.9239f), {1.2f, 0.8f, 1});
  const glm::mat4 child = parent * trs({-1, 0, 0.5f}, quat(0.2588f, 0, 0, 0.9659f), Vec3(1));
  glm::mat4 by_matrix(0.0f);  // +90 degrees about y, then (1.5, 0.1, 0)
  by_matrix[0] = Vec4(0, 0, -1, 0);
  by_matrix[1] = Vec4(0, 1, 0, 0);
  by_matrix[2] = Vec4(1, 0, 0, 0);
  by_matrix[3] = Vec4(1.5f, 0.1f, 0, 1);
  // Depth-first in file order: the first child, its grandchild, then the second child.
  expect_near(m.placements[0].to_model, child);
  expect_near(m.placements[1].to_model,
              child * trs({0, 1.2f, 0}, glm::quat(1, 0, 0, 0), {0.5f, -0.5f, 0.5f}));
  expect_near(m.placements[2].to_model, parent * by_matrix);
  auto f = parse(make_model({kHierarchy, "0", 3}));
  ASSERT_TRUE(f.ok()) << f.error().message;
  expect_placements_match_copies(m, f->mesh);
}

// A JSON "mesh" object's transform (or any caller's) composes with the node transforms: the
// scene's instance i is placed by m * to_model; without instancing, copies land in the same place.
TEST(GltfInstances, CallerTransformComposesWithNodeTransforms) {
  auto r = parse(make_model({kThreeNodes}));
  ASSERT_TRUE(r.ok()) << r.error().message;
  const MeshData& m = r->mesh;
  const glm::mat4 placed = trs({3, -1, 2}, quat(0.1f, -0.7f, 0.2f, 0.6f), {2, 2, -0.5f});
  Scene inst, flat;
  add_material(inst, Material{});  // the model's materials come after the scene's own
  add_mesh(inst, m, placed, 0, false, true);
  add_mesh(flat, m, placed, 0, false, false);
  ASSERT_EQ(inst.geometry.instances.size(), 3u);
  ASSERT_EQ(inst.geometry.instance_meshes.size(), 1u);
  EXPECT_EQ(inst.geometry.num_triangles(), 2u);
  EXPECT_TRUE(flat.geometry.instances.empty());
  ASSERT_EQ(flat.geometry.num_triangles(), 2 + 3 * kLeafTriangles);
  const Geometry& leaf = inst.geometry.instance_meshes[0]->geometry;
  ASSERT_EQ(leaf.positions.size(), kLeafVertices);
  for (size_t k = 0; k < 3; ++k) {
    const Instance& i = inst.geometry.instances[k];
    const glm::mat4 want = placed * m.placements[k].to_model;
    EXPECT_EQ(i.to_world.m, glm::mat3(want));
    EXPECT_EQ(i.to_world.t, Vec3(want[3]));
    for (size_t v = 0; v < kLeafVertices; ++v)
      expect_near(i.to_world.point(leaf.positions[v]),
                  flat.geometry.positions[m.positions.size() + k * kLeafVertices + v], 1e-4f);
  }
  // The shared mesh names the scene's material ids, as the flat ground does.
  ASSERT_EQ(inst.materials.size(), 3u);
  EXPECT_EQ(leaf.triangle_material[0], 1 + m.shared[0].face_material[0]);
  EXPECT_TRUE(inst.materials[leaf.triangle_material[0]].cutout());
  EXPECT_EQ(inst.geometry.triangle_material[0], 1 + m.face_material[0]);
  EXPECT_FALSE(inst.materials[inst.geometry.triangle_material[0]].cutout());
  // A caller transform that flattens the model to a plane cannot be inverted: copies instead.
  Scene squashed;
  add_mesh(squashed, m, glm::scale(glm::mat4(1.0f), Vec3(1, 0, 1)), 0, false, true);
  EXPECT_TRUE(squashed.geometry.instances.empty());
  EXPECT_EQ(squashed.geometry.num_triangles(), 2 + 3 * kLeafTriangles);
}

// A JSON scene's "mesh" object places the model by its transform (scale with a mirror, rotation,
// translation): the image is the one of the same object naming the flattened twin file.
TEST(GltfInstances, JsonMeshObjectPlacesTheModelByItsTransform) {
  TempDir dir;
  dir.write("inst.gltf", make_model({kThreeNodes}));
  dir.write("flat.gltf", make_model({kThreeNodes, "0, 1, 2", 3}));
  auto scene = [&](const std::string& file) {
    return parse_scene_json(R"({"camera": {"eye": [2, 3, 8], "look": [0, 0.5, 0], "fov": 40},
      "lights": [{"position": [4, 8, 6], "color": [0.9, 0.9, 0.9]}],
      "objects": [{"type": "mesh", "file": ")" +
                                file + R"(",
        "transform": {"translate": [0.3, -0.2, 0.1], "rotate": {"axis": [0, 1, 0], "degrees": 35},
                      "scale": [1.2, 0.9, -1.1]}}]})",
                            dir.path + "/s.json", dir.path);
  };
  auto inst = scene("inst.gltf");
  auto flat = scene("flat.gltf");
  ASSERT_TRUE(inst.ok()) << inst.error().message;
  ASSERT_TRUE(flat.ok()) << flat.error().message;
  EXPECT_EQ(represented_triangles((*inst)->geometry), 2 + 3 * kLeafTriangles);
  const Image a = render(**flat), b = render(**inst);
  size_t red = 0;
  for (const Vec3& p : a.rgb) red += p.x > 2.0f * p.y + 0.02f ? 1 : 0;
  EXPECT_GT(red, 50u);
  EXPECT_LE(differing(a, b, kTolerance), kMaxDiffering);
}

TEST(GltfInstances, SingularAndNonFiniteNodeTransforms) {
  // A node squashing the leaf flat cannot be an instance: its copy is flattened, as before, and
  // the two other nodes still share the mesh.
  std::string nodes = kThreeNodes;
  nodes.replace(nodes.find("[-1.3, 0.6, 1.1]"), 16, "[0, 0.6, 1.1]");
  auto r = parse(make_model({nodes}));
  ASSERT_TRUE(r.ok()) << r.error().message;
  EXPECT_EQ(r->mesh.placements.size(), 2u);
  EXPECT_EQ(r->mesh.triangles.size(), 2 + kLeafTriangles);
  // Non-finite transforms give the error they always gave.
  nodes = kThreeNodes;
  nodes.replace(nodes.find("[-1.3, 0.6, 1.1]"), 16, "[1e300, 1, 1]");
  for (int copies : {1, 3}) {
    auto bad = parse(make_model({nodes, "0, 1, 2", copies}));
    ASSERT_FALSE(bad.ok());
    EXPECT_EQ(bad.error().message, "t.gltf: node 2: transform is not finite");
  }
  // A finite transform that carries vertices past float range: one line, shared or copied.
  nodes = kThreeNodes;
  nodes.replace(nodes.find("[-1.3, 0.6, 1.1]"), 16, "[1e30, 1, 1]");
  for (int copies : {1, 3}) {
    SCOPED_TRACE(copies);
    auto bad = parse(make_model({nodes, "0, 1, 2", copies, 1e10f}));
    ASSERT_FALSE(bad.ok());
    EXPECT_NE(bad.error().message.find("position is not finite after the node transform"),
              std::string::npos)
        << bad.error().message;
    EXPECT_EQ(bad.error().message.find('\n'), std::string::npos);
  }
}

TEST(GltfInstances, BadNodeReferencesGiveOneLineErrors) {
  const std::string good = kThreeNodes;
  auto with = [&](const std::string& from, const std::string& to, const std::string& roots) {
    std::string nodes = good;
    nodes.replace(nodes.find(from), from.size(), to);
    return make_model({nodes, roots});
  };
  const std::pair<std::string, std::string> cases[] = {
      {with(R"("mesh": @1})", R"("mesh": 7})", "0, 1, 2"),
       "t.gltf: mesh 7 out of range (2 meshes)"},
      {with(R"("mesh": @1})", R"("mesh": @1, "children": [0]})", "0, 1, 2"),
       "t.gltf: node 0: reached twice (a cycle in the node hierarchy, or two parents)"},
      {with(R"("mesh": @1})", R"("mesh": @1, "children": [1]})", "1"),
       "t.gltf: node 1: reached twice (a cycle in the node hierarchy, or two parents)"},
      {with(R"("mesh": @1})", R"("mesh": @1, "children": [40]})", "0, 1, 2"),
       "t.gltf: node 40 out of range (6 nodes)"},
  };
  for (const auto& [text, message] : cases) {
    auto r = parse(text);
    ASSERT_FALSE(r.ok()) << message;
    EXPECT_EQ(r.error().message, message);
  }
}

}  // namespace
}  // namespace frameless
