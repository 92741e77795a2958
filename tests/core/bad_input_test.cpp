// Bad input: every malformed scene or mesh gives one line naming the file, the line or JSON field,
// and the problem; nothing crashes, hangs or allocates what a lying header claims.
#include <gtest/gtest.h>

#include "core/scenes/scene_load.h"

namespace frameless {
namespace {

const std::string kData = FRAMELESS_TEST_DATA;

// Asserts failure with a one-line message containing every one of `parts`.
void expect_error(const Error& e, std::initializer_list<const char*> parts) {
  EXPECT_EQ(e.message.find('\n'), std::string::npos) << e.message;
  for (const char* p : parts) EXPECT_NE(e.message.find(p), std::string::npos) << "want '" << p << "' in: " << e.message;
}

template <class T>
void expect_fails(const Result<T>& r, std::initializer_list<const char*> parts) {
  ASSERT_FALSE(r.ok()) << "accepted bad input";
  expect_error(r.error(), parts);
}

// A valid scene with one object; tests swap in a bad piece.
std::string scene_with(const std::string& object, const std::string& extra = "") {
  return R"({"materials":{"m":{"class":"diffuse","kd":0.5}},)" + extra + R"("objects":[)" + object + "]}";
}
const std::string kSphere = R"({"type":"sphere","center":[0,0,0],"radius":1,"material":"m"})";

auto json(const std::string& text) { return parse_scene_json(text, "bad.json", kData + "/scenes"); }

TEST(BadInput, ControlSceneIsAccepted) {
  // The fixtures below are bad only in the piece each test changes.
  ASSERT_TRUE(json(scene_with(kSphere)).ok()) << json(scene_with(kSphere)).error().message;
}

TEST(BadInput, JsonSyntaxErrorNamesLineAndColumn) {
  expect_fails(json("{\n  \"objects\": [\n    {\"type\": \"sphere\",, }\n  ]\n}"), {"bad.json:3:", "syntax error"});
  expect_fails(json(""), {"bad.json:1:", "syntax error"});
  expect_fails(json("{\"objects\": [1, 2"), {"bad.json:1:", "syntax error"});
}

TEST(BadInput, MissingFiles) {
  expect_fails(load_scene(kData + "/scenes/no_such.json"), {"no_such.json", "cannot open"});
  expect_fails(load_scene(kData + "/meshes/no_such.ply"), {"no_such.ply", "cannot open"});
  expect_fails(json(scene_with(R"({"type":"mesh","file":"gone.obj","material":"m"})")),
               {"bad.json", "objects[0].file", "gone.obj", "cannot open"});
}

TEST(BadInput, NonFiniteNumbers) {
  expect_fails(json(scene_with(R"({"type":"sphere","center":[0,1e999,0],"radius":1,"material":"m"})")),
               {"bad.json:1:", "1e999"});
  expect_fails(parse_obj("v 0 0 0\nv 1 nan 0\nv 0 1 0\nf 1 2 3\n", "nan.obj"), {"nan.obj:2:", "finite"});
  expect_fails(parse_obj("v 0 0 0\nv 1 0 0\nv 0 inf 0\nf 1 2 3\n", "inf.obj"), {"inf.obj:3:", "finite"});
  expect_fails(parse_ply("ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\n"
                         "property float z\nelement face 1\nproperty list uchar int vertex_indices\n"
                         "end_header\n0 0 0\n1 NaN 0\n0 1 0\n3 0 1 2\n", "nan.ply"),
               {"nan.ply:11:", "vertex 1"});
}

TEST(BadInput, NegativeOrZeroRadius) {
  expect_fails(json(scene_with(R"({"type":"sphere","center":[0,0,0],"radius":-1,"material":"m"})")),
               {"bad.json", "objects[0].radius", "> 0"});
  expect_fails(json(scene_with(kSphere + "," + R"({"type":"sphere","center":[0,0,0],"radius":0,"material":"m"})")),
               {"bad.json", "objects[1].radius"});
  expect_fails(json(scene_with(kSphere, R"("lights":[{"type":"spherical","position":[0,5,0],"radius":-2}],)")),
               {"bad.json", "lights[0].radius"});
}

TEST(BadInput, UnknownMaterialName) {
  expect_fails(json(scene_with(R"({"type":"sphere","center":[0,0,0],"radius":1,"material":"gold"})")),
               {"bad.json", "objects[0].material", "unknown material 'gold'"});
}

TEST(BadInput, AbsurdResolution) {
  for (const char* s : {R"("settings":{"width":0},)", R"("settings":{"height":16385},)",
                        R"("settings":{"width":-5},)", R"("settings":{"width":1e12},)"})
    expect_fails(json(scene_with(kSphere, s)), {"bad.json", "settings."});
}

TEST(BadInput, UnknownKeysAndWrongTypes) {
  expect_fails(json(scene_with(R"({"type":"sphere","center":[0,0,0],"radus":1,"material":"m"})")),
               {"bad.json", "objects[0].radus", "unknown key"});
  expect_fails(json(scene_with(R"({"type":"sphere","center":"origin","radius":1,"material":"m"})")),
               {"bad.json", "objects[0].center", "array of 3"});
  expect_fails(json(scene_with(R"({"type":"sphere","center":[0,0,0],"radius":"big","material":"m"})")),
               {"bad.json", "objects[0].radius", "number"});
  expect_fails(json(scene_with(kSphere, R"("camera":{"eye":[0,0,5],"look":[0,0,5]},)")), {"bad.json", "camera"});
  expect_fails(json(scene_with(kSphere, R"("bogus":1,)")), {"bad.json", "bogus", "unknown key"});
  expect_fails(json("[1,2,3]"), {"bad.json", "expected an object"});
  expect_fails(json(R"({"materials":{"m":{"class":"metal","kd":1}},"objects":[]})"),
               {"bad.json", "materials.m.kd", "unknown key"});
}

TEST(BadInput, OutOfRangeVertexIndex) {
  expect_fails(parse_obj("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\nf 1 2 4\n", "idx.obj"), {"idx.obj:5:", "out of range"});
  expect_fails(parse_obj("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 -4\n", "neg.obj"), {"neg.obj:4:", "out of range"});
  expect_fails(parse_obj("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 0 1 2\n", "zero.obj"), {"zero.obj:4:", "out of range"});
  expect_fails(parse_ply("ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\n"
                         "property float z\nelement face 1\nproperty list uchar int vertex_indices\n"
                         "end_header\n0 0 0\n1 0 0\n0 1 0\n3 0 1 3\n", "idx.ply"),
               {"idx.ply:13:", "out of range"});
  expect_fails(json(scene_with(R"({"type":"triangles","material":"m","vertices":[[0,0,0],[1,0,0],[0,1,0]],"indices":[[0,1,3]]})")),
               {"bad.json", "objects[0].indices[0][2]"});
}

TEST(BadInput, EmptyMesh) {
  expect_fails(parse_obj("# nothing\nv 0 0 0\n", "empty.obj"), {"empty.obj", "empty mesh"});
  expect_fails(parse_ply("ply\nformat ascii 1.0\nelement vertex 0\nproperty float x\nproperty float y\n"
                         "property float z\nend_header\n", "empty.ply"),
               {"empty.ply", "empty mesh"});
  expect_fails(json(R"({"objects":[]})"), {"bad.json", "objects", "empty"});
  expect_fails(json(scene_with(R"({"type":"triangles","material":"m","vertices":[],"indices":[]})")),
               {"bad.json", "objects[0]"});
}

TEST(BadInput, BadPlyHeader) {
  expect_fails(parse_ply("plx\nformat ascii 1.0\nend_header\n", "h.ply"), {"h.ply:1:", "bad PLY header"});
  expect_fails(parse_ply("ply\nformat ascii 2.0\nend_header\n", "h.ply"), {"h.ply:2:", "version"});
  expect_fails(parse_ply("ply\nformat ascii 1.0\nelement vertex 3\nproperty flot x\nend_header\n", "h.ply"),
               {"h.ply:4:", "unknown type"});
  expect_fails(parse_ply("ply\nformat ascii 1.0\nelement vertex 3\n", "h.ply"), {"h.ply:", "no end_header"});
  expect_fails(parse_ply("ply\nformat ascii 1.0\nelement face 1\nproperty list float int vertex_indices\nend_header\n", "h.ply"),
               {"h.ply:4:", "not an integer type"});
}

std::string binary_header(const std::string& vertices, const std::string& faces) {
  return "ply\nformat binary_little_endian 1.0\nelement vertex " + vertices +
         "\nproperty float x\nproperty float y\nproperty float z\nelement face " + faces +
         "\nproperty list uchar int vertex_indices\nend_header\n";
}

TEST(BadInput, TruncatedBinaryPly) {
  std::string ply = binary_header("3", "1") + std::string(36, '\0');  // vertices, then no face
  expect_fails(parse_ply(ply, "trunc.ply"), {"trunc.ply:", "truncated"});
  ply = binary_header("3", "1") + std::string(20, '\0');  // cut inside the vertices
  expect_fails(parse_ply(ply, "trunc.ply"), {"trunc.ply:", "truncated"});
}

// A header claiming 2^31 vertices over a 100-byte body fails at once, without allocating.
TEST(BadInput, LyingPlyHeaderFailsFast) {
  const std::string ply = binary_header("2147483648", "1") + std::string(100, '\x01');
  expect_fails(parse_ply(ply, "lie.ply"), {"lie.ply:3:", "2147483648"});
  std::string faces = binary_header("3", "1") + std::string(36, '\0');
  faces += '\xff';  // a 255-corner face with no indices behind it
  expect_fails(parse_ply(faces, "lie.ply"), {"lie.ply:", "exceeds"});
  const std::string huge = "ply\nformat binary_little_endian 1.0\nelement nothing 18446744073709551615\n"
                           "element vertex 0\nproperty float x\nproperty float y\nproperty float z\nend_header\n";
  expect_fails(parse_ply(huge, "lie.ply"), {"lie.ply", "empty mesh"});
}

TEST(BadInput, UnknownSceneSpec) {
  expect_fails(load_scene("not-a-scene"), {"not-a-scene", "built-in"});
  expect_fails(load_scene(kData + "/meshes/tetra.stl"), {"tetra.stl"});
  // The error names every kind of file the loader reads (it once listed three of nine).
  const auto unknown = load_scene("not-a-scene");
  ASSERT_FALSE(unknown.ok());
  for (const std::string kind : {".json", ".obj", ".ply", ".gltf", ".glb", ".vdb", ".nrrd", ".nhdr", ".spheres"}) {
    EXPECT_TRUE(is_scene_file("x" + kind)) << kind;
    EXPECT_NE(unknown.error().message.find(kind + (kind == ".spheres" ? ")" : ",")), std::string::npos)
        << kind << ": " << unknown.error().message;
  }
  EXPECT_FALSE(is_scene_file("x.stl"));
}

}  // namespace
}  // namespace frameless
