// Mesh input: OBJ (tinyobjloader) and PLY (ascii, binary little/big endian), and meshes shown
// directly as a scene.
#include <bit>
#include <cstring>

#include <gtest/gtest.h>

#include "core/scenes/scene_load.h"

namespace frameless {
namespace {

const std::string kData = FRAMELESS_TEST_DATA;

TEST(MeshObj, TriangulatesPolygonsAndKeepsNormals) {
  auto m = load_mesh(kData + "/meshes/quad_normals.obj");
  ASSERT_TRUE(m.ok()) << m.error().message;
  EXPECT_EQ(m->positions.size(), 4u);
  EXPECT_EQ(m->triangles.size(), 2u);
  ASSERT_EQ(m->normals.size(), 4u);
  EXPECT_EQ(m->normals[2], Vec3(0, 0, 1));
}

TEST(MeshObj, NegativeIndicesAreRelative) {
  auto m = parse_obj("v 0 0 0\nv 1 0 0\nv 0 1 0\nf -3 -2 -1\n", "rel.obj");
  ASSERT_TRUE(m.ok()) << m.error().message;
  ASSERT_EQ(m->triangles.size(), 1u);
  EXPECT_EQ(m->triangles[0], UVec3(0, 1, 2));
}

TEST(MeshObj, PentagonBecomesThreeTriangles) {
  auto m = parse_obj("v 0 0 0\nv 2 0 0\nv 3 1 0\nv 1 2 0\nv -1 1 0\nf 1 2 3 4 5\n", "p.obj");
  ASSERT_TRUE(m.ok()) << m.error().message;
  EXPECT_EQ(m->triangles.size(), 3u);
}

// Writes a PLY with vertex x y z (float) and a face list, in the given format.
std::string binary_ply(bool big, const char* count_type, const char* index_type, int count_bytes,
                       int index_bytes) {
  std::string h = std::string("ply\nformat ") + (big ? "binary_big_endian" : "binary_little_endian") +
                  " 1.0\nelement vertex 4\nproperty float x\nproperty float y\nproperty float z\n"
                  "element face 1\nproperty list " + count_type + " " + index_type +
                  " vertex_indices\nend_header\n";
  auto put = [&](const void* p, int n) {
    unsigned char b[8];
    std::memcpy(b, p, size_t(n));
    if (big == (std::endian::native == std::endian::little))
      for (int i = 0; i < n / 2; ++i) std::swap(b[i], b[n - 1 - i]);
    h.append(reinterpret_cast<const char*>(b), size_t(n));
  };
  const float v[12] = {0, 0, 0, 1, 0, 0, 1, 1, 0, 0, 1, 0};
  for (float f : v) put(&f, 4);
  const uint64_t four = 4;
  put(&four, count_bytes);  // little-endian host: the low bytes come first
  for (uint64_t i : {0, 1, 2, 3}) put(&i, index_bytes);
  return h;
}

TEST(MeshPly, BinaryLittleAndBigEndianWithAnyIntegerTypes) {
  struct Case {
    bool big;
    const char* ct;
    const char* it;
    int cb, ib;
  } cases[] = {{false, "uchar", "int", 1, 4},  {true, "uchar", "int", 1, 4},
               {false, "ushort", "uint", 2, 4}, {true, "int", "ushort", 4, 2},
               {true, "uint8", "uint8", 1, 1},  {false, "char", "short", 1, 2}};
  for (const Case& c : cases) {
    auto m = parse_ply(binary_ply(c.big, c.ct, c.it, c.cb, c.ib), "b.ply");
    ASSERT_TRUE(m.ok()) << c.ct << " " << c.it << ": " << m.error().message;
    ASSERT_EQ(m->positions.size(), 4u);
    EXPECT_EQ(m->positions[2], Vec3(1, 1, 0)) << c.big;
    ASSERT_EQ(m->triangles.size(), 2u);  // the quad, fan-triangulated
    EXPECT_EQ(m->triangles[1], UVec3(0, 2, 3));
  }
}

TEST(MeshPly, AsciiWithNormalsAndFans) {
  auto m = load_mesh(kData + "/meshes/square.ply");
  ASSERT_TRUE(m.ok()) << m.error().message;
  EXPECT_EQ(m->positions.size(), 5u);
  EXPECT_EQ(m->normals.size(), 5u);
  EXPECT_EQ(m->triangles.size(), 3u);
}

TEST(MeshPly, SkipsOtherElementsAndProperties) {
  const std::string ply =
      "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty uchar red\n"
      "property float y\nproperty float z\nelement edge 1\nproperty int a\nproperty list uchar "
      "float stuff\nelement face 1\nproperty uchar flags\nproperty list uchar uint vertex_index\n"
      "end_header\n0 255 0 0\n1 0 0 0\n0 7 1 0\n5 2 1.5 2.5\n9 3 0 1 2\n";
  auto m = parse_ply(ply, "s.ply");
  ASSERT_TRUE(m.ok()) << m.error().message;
  EXPECT_EQ(m->triangles.size(), 1u);
  EXPECT_EQ(m->positions[2], Vec3(0, 1, 0));
}

TEST(MeshPly, TextureCoordinatesByAnyCommonName) {
  for (const char* names : {"u v", "s t", "texture_u texture_v"}) {
    std::string u(names), v = u.substr(u.find(' ') + 1);
    u = u.substr(0, u.find(' '));
    const std::string ply = "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\n"
                            "property float y\nproperty float z\nproperty float " + u +
                            "\nproperty float " + v +
                            "\nelement face 1\nproperty list uchar int vertex_indices\nend_header\n"
                            "0 0 0 0 0\n1 0 0 1 0\n0 1 0 0.25 1\n3 0 1 2\n";
    auto m = parse_ply(ply, "uv.ply");
    ASSERT_TRUE(m.ok()) << m.error().message;
    ASSERT_EQ(m->uvs.size(), 3u) << names;
    EXPECT_EQ(m->uvs[2], Vec2(0.25f, 1.0f));
  }
  const std::string bad =
      "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\n"
      "property float z\nproperty float u\nproperty float v\nelement face 1\n"
      "property list uchar int vertex_indices\nend_header\n0 0 0 0 0\n1 0 0 nan 0\n"
      "0 1 0 0 1\n3 0 1 2\n";
  auto r = parse_ply(bad, "uv.ply");
  ASSERT_FALSE(r.ok());
  EXPECT_NE(r.error().message.find("uv.ply:13: vertex 1: texture coordinate is not a finite"),
            std::string::npos)
      << r.error().message;
}

TEST(MeshScene, MeshFileIsFramedWithLightAndHemisphere) {
  auto s = load_scene(kData + "/meshes/tetra.obj");
  ASSERT_TRUE(s.ok()) << s.error().message;
  const Scene& sc = **s;
  EXPECT_EQ(sc.lights.size(), 1u);
  EXPECT_EQ(sc.ambient.kind, AmbientKind::kHemisphere);
  EXPECT_EQ(sc.settings.width, 640);
  EXPECT_EQ(sc.settings.height, 480);
  ASSERT_TRUE(camera_is_valid(sc.camera));
  // Every vertex of the bounding box lies inside the view frustum.
  const CameraBasis b = make_camera_basis(sc.camera, sc.settings.width, sc.settings.height);
  for (int i = 0; i < 8; ++i) {
    const Vec3 p(i & 1 ? 1 : -1, i & 2 ? 1 : -1, i & 4 ? 1 : -1);
    const Vec3 d = p - b.eye;
    const float z = glm::dot(d, b.w);
    ASSERT_GT(z, 0.0f);
    EXPECT_LE(std::abs(glm::dot(d, b.u)) / z, b.tan_half * b.aspect);
    EXPECT_LE(std::abs(glm::dot(d, b.v)) / z, b.tan_half);
  }
  Ray r;
  r.org = b.eye;
  r.dir = b.w;
  Hit h;
  EXPECT_TRUE(sc.accel.intersect(r, h));
}

}  // namespace
}  // namespace frameless
