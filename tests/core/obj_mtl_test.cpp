// OBJ with MTL materials and textures: per-face materials, the MTL -> Parker class mapping,
// texture paths (spaces, backslashes, case), one-line errors, the sanitised copy tinyobjloader
// gets, and add_mesh carrying uvs and materials into a scene. Texture PNGs are written at test
// time into a temporary folder, next to copies of the OBJ/MTL files.
#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>

#include <gtest/gtest.h>

#include "core/io/mesh_obj.h"
#include "core/scene/scene_build.h"
#include "core/scenes/scene_load.h"
#include "png_chunks.h"

namespace frameless {
namespace {

namespace fs = std::filesystem;
const std::string kData = FRAMELESS_TEST_DATA;

// A minimal PNG (8-bit, stored deflate blocks): channels 1 grey, 3 RGB, 4 RGBA.
using testing::crc32;

void put32(std::string& s, uint32_t v) {
  for (int k = 3; k >= 0; --k) s += char((v >> (8 * k)) & 0xff);
}
std::string png_bytes(int w, int h, int channels, uint8_t seed) {
  std::string raw;
  for (int y = 0; y < h; ++y) {
    raw += '\0';  // filter: none
    for (int x = 0; x < w * channels; ++x) raw += char(seed + 40 * ((x / channels + y) & 1) + x);
  }
  std::string z = "\x78\x01";
  for (size_t i = 0; i < raw.size() || i == 0; i += 65535) {
    const size_t n = std::min<size_t>(65535, raw.size() - i);
    z += char(i + n >= raw.size() ? 1 : 0);
    z += char(n & 0xff), z += char(n >> 8), z += char(~n & 0xff), z += char((~n >> 8) & 0xff);
    z += raw.substr(i, n);
  }
  uint32_t a = 1, b = 0;
  for (unsigned char c : raw) a = (a + c) % 65521, b = (b + a) % 65521;
  put32(z, (b << 16) | a);
  auto chunk = [](std::string& out, const std::string& type_data) {
    put32(out, uint32_t(type_data.size() - 4));
    out += type_data;
    put32(out, crc32(type_data));
  };
  std::string ihdr = "IHDR";
  put32(ihdr, uint32_t(w));
  put32(ihdr, uint32_t(h));
  const char type = channels == 1 ? 0 : channels == 3 ? 2 : 6;
  ihdr += std::string{8, type, 0, 0, 0};
  std::string out = "\x89PNG\r\n\x1a\n";
  chunk(out, ihdr);
  chunk(out, "IDAT" + z);
  chunk(out, std::string("IEND"));
  return out;
}

// A fresh folder under the system temporary folder, removed with the test.
class TempDir {
 public:
  TempDir() {
    std::string tmpl = (fs::temp_directory_path() / "frameless_objmtl_XXXXXX").string();
    if (!mkdtemp(tmpl.data())) ADD_FAILURE() << "mkdtemp failed";
    dir_ = tmpl;
  }
  ~TempDir() {
    std::error_code ec;
    fs::remove_all(dir_, ec);
  }
  std::string path(const std::string& rel) const { return dir_ + "/" + rel; }
  std::string write(const std::string& rel, const std::string& bytes) const {
    const fs::path p = path(rel);
    fs::create_directories(p.parent_path());
    std::ofstream(p, std::ios::binary) << bytes;
    return p.string();
  }
  std::string png(const std::string& rel, int channels = 3, uint8_t seed = 10) const {
    return write(rel, png_bytes(2, 2, channels, seed));
  }
  std::string copy(const std::string& data_rel) const {
    const std::string to = path(fs::path(data_rel).filename().string());
    fs::copy_file(kData + "/" + data_rel, to, fs::copy_options::overwrite_existing);
    return to;
  }

 private:
  std::string dir_;
};

const Material* find_material(const MeshData& m, const std::string& name) {
  for (const Material& mat : m.materials)
    if (mat.name == name) return &mat;
  return nullptr;
}

void expect_one_line_error(const Result<MeshData>& r, std::initializer_list<std::string> parts) {
  ASSERT_FALSE(r.ok());
  const std::string& msg = r.error().message;
  EXPECT_EQ(msg.find('\n'), std::string::npos) << msg;
  for (const std::string& p : parts) EXPECT_NE(msg.find(p), std::string::npos) << "'" << p << "' not in: " << msg;
}

TEST(ObjMtl, PerFaceMaterialsUvsAndSplitVertices) {
  TempDir tmp;
  const std::string obj = tmp.copy("meshes/mtl/two_materials.obj");
  tmp.copy("meshes/mtl/two_materials.mtl");
  tmp.png("checker.png");
  ImageCache images;
  auto m = load_obj_with_materials(obj, images);
  ASSERT_TRUE(m.ok()) << m.error().message;
  // Materials in order of first use: the triangle before usemtl gets the default one.
  ASSERT_EQ(m->materials.size(), 3u);
  EXPECT_EQ(m->materials[0].name, "default");
  EXPECT_EQ(m->materials[1].name, "brick");
  EXPECT_EQ(m->materials[2].name, "red paint");
  ASSERT_EQ(m->triangles.size(), 5u);
  EXPECT_EQ(m->face_material, (std::vector<uint16_t>{0, 1, 1, 2, 2}));
  // 9 distinct (v, vt, vn) corners: position 2 appears with vt 2 and vt 1.
  EXPECT_EQ(m->positions.size(), 9u);
  ASSERT_EQ(m->uvs.size(), m->positions.size());
  ASSERT_EQ(m->normals.size(), m->positions.size());
  for (size_t t = 0; t < m->triangles.size(); ++t)
    for (int k = 0; k < 3; ++k) {
      const uint32_t v = m->triangles[t][k];
      // Every quad maps its corners onto the unit square: uv equals position minus the quad's origin.
      if (t >= 1) {
        const Vec3 origin = t >= 3 ? Vec3(1, 0, 0) : Vec3(0);
        EXPECT_EQ(m->uvs[v], Vec2(m->positions[v] - origin)) << t << " " << k;
      }
    }
  const Material& brick = m->materials[1];
  EXPECT_EQ(brick.cls, MaterialClass::kDiffuse);
  ASSERT_NE(brick.kd_tex, kNoTexture);
  ASSERT_EQ(m->textures.size(), 1u);
  EXPECT_TRUE(m->textures[0].srgb);
  ASSERT_TRUE(m->textures[0].image);
  EXPECT_EQ(m->textures[0].image->width, 2);
  EXPECT_EQ(m->materials[2].cls, MaterialClass::kPolished);
  EXPECT_EQ(m->materials[2].kd_tex, kNoTexture);
}

TEST(ObjMtl, MtlMapsOntoParkerClasses) {
  ImageCache images;
  auto m = load_obj_with_materials(kData + "/meshes/mtl/classes.obj", images);
  ASSERT_TRUE(m.ok()) << m.error().message;
  ASSERT_EQ(m->materials.size(), 10u);
  auto get = [&](const char* name) -> const Material& {
    const Material* mat = find_material(*m, name);
    EXPECT_NE(mat, nullptr) << name;
    static const Material none;
    return mat ? *mat : none;
  };
  const Material& glass = get("glass");
  EXPECT_EQ(glass.cls, MaterialClass::kDielectric);
  EXPECT_FLOAT_EQ(glass.ior, 1.33f);
  EXPECT_NEAR(glass.extinction.x, std::log(2.0f), 1e-5f);
  EXPECT_EQ(glass.extinction.y, 0.0f);
  EXPECT_EQ(glass.kh, Vec3(1.0f));
  EXPECT_EQ(glass.phong_exponent, 200.0f);
  const Material& tinted = get("tinted");
  EXPECT_EQ(tinted.cls, MaterialClass::kDielectric);
  EXPECT_FLOAT_EQ(tinted.ior, 1.5f);
  EXPECT_NEAR(tinted.extinction.z, -std::log(0.8f), 1e-5f);
  EXPECT_EQ(get("ghost").cls, MaterialClass::kDielectric);
  const Material& cutout = get("cutout");
  EXPECT_EQ(cutout.cls, MaterialClass::kDiffuse);
  EXPECT_FLOAT_EQ(cutout.opacity, 0.3f);
  EXPECT_TRUE(cutout.cutout());
  const Material& chrome = get("chrome");
  EXPECT_EQ(chrome.cls, MaterialClass::kMetal);
  EXPECT_EQ(chrome.ks, Vec3(0.9f));
  EXPECT_EQ(chrome.phong_exponent, 300.0f);
  const Material& mirror = get("mirror paint");
  EXPECT_EQ(mirror.cls, MaterialClass::kPolished);
  EXPECT_EQ(mirror.r0, Vec3(0.7f));
  EXPECT_EQ(mirror.kd, Vec3(0.5f, 0.2f, 0.2f));
  const Material& plastic = get("plastic");
  EXPECT_EQ(plastic.cls, MaterialClass::kPolished);
  EXPECT_NEAR(plastic.r0.x, 0.04f, 1e-6f);
  EXPECT_EQ(plastic.kh, Vec3(0.5f));
  EXPECT_EQ(plastic.phong_exponent, 50.0f);
  const Material& matte = get("matte");
  EXPECT_EQ(matte.cls, MaterialClass::kDiffuse);
  EXPECT_EQ(matte.kh, Vec3(0.0f));
  EXPECT_EQ(get("opaque filter").cls, MaterialClass::kDiffuse);
  EXPECT_EQ(get("inverted tr").opacity, 1.0f);
  // One triangle per material, in file order.
  for (uint16_t i = 0; i < 10; ++i) EXPECT_EQ(m->face_material[i], i);
}

TEST(ObjMtl, TexturePathsWithSpacesBackslashesAndCase) {
  TempDir tmp;
  tmp.png("my tex.png");
  tmp.png("sub/dir/t.png", 3, 20);
  tmp.png("textures/checker.PNG", 3, 30);
  tmp.png("mask.png", 1, 40);
  tmp.write("maps.mtl",
            "newmtl spaced\nmap_Kd -s 2 3 1 -o 0.5 0.25 0 -clamp on my tex.png\n"
            "newmtl windows\nKd 0.5 0.5 0.5\nKs 0.5 0.5 0.5\nmap_Kd sub\\dir\\t.png\nmap_Ks sub\\dir\\t.png\n"
            "newmtl cased\nmap_Kd Textures/CHECKER.png\nbump -bm 0.3 TEXTURES\\Checker.png\nmap_d mask.png\n");
  const std::string obj = tmp.write(
      "maps.obj", "mtllib maps.mtl\nv 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0 0\nvt 1 0\nvt 0 1\n"
                  "usemtl spaced\nf 1/1 2/2 3/3\nusemtl windows\nf 1/1 2/2 3/3\nusemtl cased\nf 1/1 2/2 3/3\n");
  ImageCache images;
  auto m = load_obj_with_materials(obj, images);
  ASSERT_TRUE(m.ok()) << m.error().message;
  ASSERT_EQ(m->materials.size(), 3u);
  const Material& spaced = m->materials[0];
  ASSERT_NE(spaced.kd_tex, kNoTexture);
  const Texture& st = m->textures[spaced.kd_tex];
  EXPECT_EQ(st.uv_scale, Vec2(2, 3));
  EXPECT_EQ(st.uv_offset, Vec2(0.5f, 0.25f));
  EXPECT_EQ(st.wrap, TextureWrap::kClamp);
  EXPECT_TRUE(st.srgb);
  const Material& win = m->materials[1];
  EXPECT_EQ(win.cls, MaterialClass::kPolished);
  ASSERT_NE(win.kd_tex, kNoTexture);
  EXPECT_EQ(win.kd_tex, win.kh_tex);  // the same image with the same options: one texture
  const Material& cased = m->materials[2];
  ASSERT_NE(cased.kd_tex, kNoTexture);
  ASSERT_NE(cased.bump_tex, kNoTexture);
  EXPECT_EQ(m->textures[cased.kd_tex].image, m->textures[cased.bump_tex].image);
  EXPECT_FALSE(m->textures[cased.bump_tex].srgb);
  EXPECT_FLOAT_EQ(cased.bump_scale, 0.3f);
  ASSERT_NE(cased.alpha_tex, kNoTexture);
  EXPECT_FALSE(m->textures[cased.alpha_tex].srgb);
  EXPECT_EQ(cased.alpha_channel, 0);  // grey mask without alpha: its first channel
  EXPECT_EQ(images.size(), 4u);       // decoded once per file
}

TEST(ObjMtl, MissingLibraryOrTextureIsOneLineError) {
  TempDir tmp;
  const std::string obj = tmp.write("a.obj", "v 0 0 0\nmtllib nothere.mtl\nv 1 0 0\nv 0 1 0\nf 1 2 3\n");
  ImageCache images;
  expect_one_line_error(load_obj_with_materials(obj, images),
                        {obj + ":2: mtllib: cannot open 'nothere.mtl'"});
  const std::string mtl = tmp.write("b.mtl", "newmtl unused\nmap_Kd gone too.png\nnewmtl used\nKd 1 0 0\nmap_Kd gone.png\n");
  const std::string obj2 = tmp.write("b.obj", "mtllib b.mtl\nv 0 0 0\nv 1 0 0\nv 0 1 0\nusemtl used\nf 1 2 3\n");
  expect_one_line_error(load_obj_with_materials(obj2, images),
                        {mtl + ":5: map_Kd: cannot open 'gone.png'"});
  // Textures of materials no face uses are never loaded.
  tmp.png("gone.png");
  EXPECT_TRUE(load_obj_with_materials(obj2, images).ok());
  tmp.write("b.mtl", "newmtl used\nKd 0.5 nan 0.5\n");
  expect_one_line_error(load_obj_with_materials(obj2, images), {mtl + ":2: Kd:", "finite"});
}

TEST(ObjMtl, UnusedStatementsNeverReachTinyobj) {
  // vw with a huge id is undefined behaviour inside tinyobjloader (float -> int).
  const std::string text =
      "v 0 0 0\nv 1 0 0\nv 0 1 0\nvw 8888888888 1 0.5\nvp 0.5\nl 1 2\np 1\ncstype bspline\n"
      "curv 0 1 1 2\ng group\ns 1\nf 1 2 3\n";
  auto scan = scan_obj(text, "vw.obj");
  ASSERT_TRUE(scan.ok()) << scan.error().message;
  for (const char* gone : {"vw", "vp", "l ", "p ", "cstype", "curv", "g ", "s "})
    EXPECT_EQ(scan->text.find(gone), std::string::npos) << gone;
  EXPECT_EQ(std::count(scan->text.begin(), scan->text.end(), '\n'), 12);  // line numbers kept
  auto m = parse_obj(text, "vw.obj");
  ASSERT_TRUE(m.ok()) << m.error().message;
  EXPECT_EQ(m->triangles.size(), 1u);
}

TEST(ObjMtl, TextureCoordinatesAreChecked) {
  const std::string v = "v 0 0 0\nv 1 0 0\nv 0 1 0\n";
  expect_one_line_error(parse_obj(v + "vt 0 0\nf 1/1 2/2 3/1\n", "t.obj"),
                        {"t.obj:5: f: texture index '2' out of range (1..1)"});
  expect_one_line_error(parse_obj(v + "vt 0 0\nf 1/1/ 2/-2 3/1\n", "n.obj"), {"n.obj:5:", "texture index '-2'"});
  expect_one_line_error(parse_obj(v + "vt 0 inf\nf 1 2 3\n", "i.obj"), {"i.obj:4: vt: 'inf' is not a finite number"});
  expect_one_line_error(parse_obj(v + "vt 0.5\nf 1 2 3\n", "o.obj"), {"o.obj:4: vt: expected 2 or 3 numbers"});
  expect_one_line_error(parse_obj(v + "vt 0 0 0 0\nf 1 2 3\n", "f.obj"), {"f.obj:4: vt: expected 2 or 3 numbers"});
  EXPECT_TRUE(parse_obj(v + "vt 0 0 0\nvt 1 0\nf 1/1 2/2 3/-1\n", "ok.obj").ok());
}

TEST(ObjMtl, AddMeshKeepsUvsAndOffsetsMaterials) {
  Scene s;
  s.materials.push_back(Material{});
  s.textures.push_back(Texture{});
  MeshData plain;
  plain.positions = {Vec3(0), Vec3(1, 0, 0), Vec3(0, 1, 0)};
  plain.triangles = {UVec3(0, 1, 2)};
  add_mesh(s, plain, glm::mat4(1.0f), 0);
  EXPECT_TRUE(s.geometry.uvs.empty());
  MeshData textured = plain;
  textured.positions.push_back(Vec3(1, 1, 0));
  textured.triangles.push_back(UVec3(1, 3, 2));
  textured.uvs = {Vec2(0), Vec2(1, 0), Vec2(0, 1), Vec2(1)};
  textured.textures.push_back(Texture{});
  textured.materials.resize(2);
  textured.materials[0].kd_tex = 0;
  textured.face_material = {1, 0};
  add_mesh(s, textured, glm::mat4(1.0f), 0);
  const Geometry& g = s.geometry;
  ASSERT_EQ(g.uvs.size(), g.positions.size());
  EXPECT_EQ(g.uvs[0], Vec2(0));  // padding for the mesh without uvs
  EXPECT_EQ(g.uvs[6], Vec2(1));
  ASSERT_EQ(s.materials.size(), 3u);
  ASSERT_EQ(s.textures.size(), 2u);
  EXPECT_EQ(s.materials[1].kd_tex, 1u);
  EXPECT_EQ(s.materials[2].kd_tex, kNoTexture);
  EXPECT_EQ(g.triangle_material, (std::vector<uint16_t>{0, 2, 1}));
  // Override: the caller's material everywhere, nothing of the mesh's is added.
  add_mesh(s, textured, glm::mat4(1.0f), 0, true);
  EXPECT_EQ(s.materials.size(), 3u);
  EXPECT_EQ(g.triangle_material.back(), 0);
  // A mesh with normals turns earlier geometry flat-shaded: uvs stay one per position.
  MeshData normals = plain;
  normals.normals.assign(3, Vec3(0, 0, 1));
  add_mesh(s, normals, glm::mat4(1.0f), 0);
  ASSERT_EQ(g.normals.size(), g.positions.size());
  ASSERT_EQ(g.uvs.size(), g.positions.size());
  // Triangle 2 is the textured mesh's second one: its corners keep uvs (1,0), (1,1), (0,1).
  const UVec3 t = g.triangles[2];
  EXPECT_EQ(g.uvs[t.x], Vec2(1, 0));
  EXPECT_EQ(g.uvs[t.y], Vec2(1));
  EXPECT_EQ(g.uvs[t.z], Vec2(0, 1));
}

TEST(ObjMtl, BoxAndQuadHavePlanarUvs) {
  Scene s;
  add_box(s, Vec3(-1, -2, -3), Vec3(1, 2, 3), 0);
  const Geometry& g = s.geometry;
  ASSERT_EQ(g.positions.size(), 24u);
  ASSERT_EQ(g.uvs.size(), 24u);
  ASSERT_EQ(g.triangles.size(), 12u);
  for (const UVec3& t : g.triangles) {
    const Vec3 a = g.positions[t.x], b = g.positions[t.y], c = g.positions[t.z];
    const Vec3 n = glm::cross(b - a, c - a);
    EXPECT_GT(glm::dot(n, (a + b + c) / 3.0f), 0.0f);  // outward
    // uv is affine in position over each face: the uv frame keeps the face's winding.
    const Vec2 du = g.uvs[t.y] - g.uvs[t.x], dv = g.uvs[t.z] - g.uvs[t.x];
    EXPECT_GT(du.x * dv.y - du.y * dv.x, 0.0f);
  }
  // Side faces stand upright: v grows with y.
  for (size_t f = 0; f < 2; ++f)
    EXPECT_GT(g.positions[4 * f + 2].y, g.positions[4 * f].y);
  add_quad(s, Vec3(0, 5, 0), Vec3(0, 1, 0), 2.0f, 0);
  ASSERT_EQ(g.uvs.size(), 28u);
  EXPECT_EQ(g.uvs[24], Vec2(0));
  EXPECT_EQ(g.uvs[26], Vec2(1));
}

TEST(ObjMtl, LoadSceneKeepsTheFileMaterials) {
  TempDir tmp;
  const std::string obj = tmp.copy("meshes/mtl/two_materials.obj");
  tmp.copy("meshes/mtl/two_materials.mtl");
  tmp.png("checker.png");
  auto s = load_scene(obj);
  ASSERT_TRUE(s.ok()) << s.error().message;
  const Scene& scene = **s;
  EXPECT_EQ(scene.materials.size(), 3u);
  EXPECT_EQ(scene.textures.size(), 1u);
  EXPECT_EQ(scene.geometry.uvs.size(), scene.geometry.positions.size());
  EXPECT_FALSE(scene.lights.empty());
  // A plain OBJ still gets the default material.
  auto plain = load_scene(kData + "/meshes/tetra.obj");
  ASSERT_TRUE(plain.ok()) << plain.error().message;
  ASSERT_EQ((*plain)->materials.size(), 1u);
  EXPECT_EQ((*plain)->materials[0].name, "default");
}

// OBJ+MTL models of Debian's assimp-testmodels, when installed.
TEST(ObjMtl, AssimpTestModels) {
  const std::string dir = "/usr/share/assimp/models/OBJ";
  if (!fs::exists(dir + "/spider.obj"))
    GTEST_SKIP() << "assimp-testmodels is not installed (" << dir << ")";
  ImageCache images;
  auto spider = load_obj_with_materials(dir + "/spider.obj", images);  // map_Kd .\name.jpg
  ASSERT_TRUE(spider.ok()) << spider.error().message;
  EXPECT_GT(spider->materials.size(), 1u);
  EXPECT_FALSE(spider->textures.empty());
  EXPECT_EQ(spider->uvs.size(), spider->positions.size());
  auto regr = load_obj_with_materials(dir + "/regr01.obj", images);
  ASSERT_TRUE(regr.ok()) << regr.error().message;
  EXPECT_GT(regr->materials.size(), 1u);
  auto spaces = load_obj_with_materials(dir + "/space_in_material_name.obj", images);
  ASSERT_TRUE(spaces.ok()) << spaces.error().message;
  const Material* plastic = find_material(*spaces, "Hard Shiny Plastic White");
  ASSERT_NE(plastic, nullptr);
  EXPECT_NEAR(plastic->kd.x, 0.141176f, 1e-6f);
  auto cube = load_obj_with_materials(dir + "/cube_usemtl.obj", images);  // names mtl3, undefined
  ASSERT_TRUE(cube.ok()) << cube.error().message;
  EXPECT_EQ(cube->materials.size(), 3u);
  EXPECT_NE(find_material(*cube, "mtl2"), nullptr);
}

}  // namespace
}  // namespace frameless
