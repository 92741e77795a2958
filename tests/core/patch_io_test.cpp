// POV-Ray bicubic_patch reader: the teapot's syntax and its u/v mapping (normals outward), and a
// one-line error naming the line for each kind of bad input.
#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "core/geometry/bezier.h"
#include "core/io/patch_io.h"

namespace frameless {
namespace {

const char* const kTeapot = "/usr/share/doc/povray/examples/advanced/teapot/teapot.inc";
const std::string kData = FRAMELESS_TEST_DATA;

// 16 points <j, i, k> (k = 4i + j) as POV-Ray writes them: four rows of four, no commas.
std::string points(int count = 16, const char* sep = " ") {
  std::string s;
  for (int k = 0; k < count; ++k) {  // appended piece by piece (GCC 12's -Wstringop-overflow)
    s += '<';
    s += std::to_string(k % 4);
    s += ", ";
    s += std::to_string(k / 4);
    s += ", ";
    s += std::to_string(k);
    s += '>';
    s += k % 4 == 3 ? "\n" : sep;
  }
  return s;
}

Result<std::vector<BezierPatch>> parse(const std::string& text) { return parse_bicubic_patches(text, "t.inc"); }

// The error of parsing `text`: one line, "t.inc:LINE: ...", containing `what`.
void expect_error(const std::string& text, int line, const std::string& what) {
  auto r = parse(text);
  ASSERT_FALSE(r.ok()) << text;
  const std::string& m = r.error().message;
  EXPECT_EQ(m.find('\n'), std::string::npos) << m;
  EXPECT_EQ(m.rfind("t.inc:" + std::to_string(line) + ": ", 0), 0u) << m;
  EXPECT_NE(m.find(what), std::string::npos) << m;
}

TEST(PatchIo, ReadsTeapotStyleBlocksAndSkipsTheRest) {
  const std::string text =
      "// bicubic_patch { in a comment\n"
      "/* nested /* bicubic_patch { */ still a comment */\n"
      "#declare Flat_Enough = 0.0001;\n"
      "#declare Name = \"bicubic_patch { <1 }\";\n"
      "union {\n"
      "  bicubic_patch { type 1 flatness Flat_Enough u_steps 5 v_steps 5\n" +
      points() +
      "    texture { pigment { color rgb <1, 0, 0> } finish { phong 1 } }\n"
      "  }\n"
      "  sphere { <0, 0, 0>, 1 }\n"
      "  bicubic_patch { type 0 accuracy .01, " + points(16, ", ") + " no_shadow double_illuminate }\n"
      "  rotate <-110, 20, 0>\n"
      "}\n";
  auto r = parse(text);
  ASSERT_TRUE(r.ok()) << r.error().message;
  ASSERT_EQ(r->size(), 2u);
  for (const BezierPatch& p : *r)
    for (int k = 0; k < 16; ++k) EXPECT_EQ(p.p[k], Vec3(float(k % 4), float(k / 4), float(k))) << k;
  // File row i is row i of the patch: u along a row, v down the rows.
  EXPECT_EQ(bezier_eval((*r)[0], 1.0f, 0.0f), Vec3(3, 0, 3));
  EXPECT_EQ(bezier_eval((*r)[0], 0.0f, 1.0f), Vec3(0, 3, 12));
}

TEST(PatchIo, LoadsAFile) {
  auto r = load_bicubic_patches(kData + "/patches/two_patches.inc");
  ASSERT_TRUE(r.ok()) << r.error().message;
  ASSERT_EQ(r->size(), 2u);
  // The flat square's edge v = 1 is the bent patch's edge v = 0.
  for (int j = 0; j < 4; ++j) EXPECT_EQ((*r)[0].p[12 + j], (*r)[1].p[j]);
  EXPECT_EQ((*r)[1].p[15], Vec3(3.0f, 5.5f, 3.0f));
}

TEST(PatchIo, BadInputNamesTheLine) {
  const std::string head = "// two lines\n\nbicubic_patch { type 1\n";  // the block opens on line 3
  expect_error(head + points(15) + "}\n", 7, "expected 16 control points, got 15");
  expect_error(head + points(16) + "<0, 0, 0>\n}\n", 8, "more than 16 control points");
  expect_error(head + points(5) + "<nan, 0, 0>\n" + points(10) + "}", 5, "'nan' is not a finite number");
  expect_error(head + points(8) + "<0, -inf, 0>\n" + points(7) + "}", 6, "'inf' is not a finite number");
  expect_error(head + points(4) + "<0, 0, 1e999>\n" + points(11) + "}", 5, "'1e999' is not a finite number");
  expect_error(head + points(4) + "<0, 0, 1e39>\n" + points(11) + "}", 5, "'1e39' is not a finite number");
  expect_error(head + "<1, 2>\n" + points(15) + "}", 4, "malformed vector: expected ','");
  expect_error(head + "<1 2 3>\n" + points(15) + "}", 4, "malformed vector: expected ','");
  expect_error(head + points(4) + "<1, 2, x>\n" + points(11) + "}", 5, "malformed vector: expected a number, got 'x'");
  expect_error(head + points(4) + "<1, 2, 3, 4>\n" + points(11) + "}", 5, "malformed vector: expected '>'");
  expect_error(head + points(16), 3, "block is not closed");
  expect_error(head + points(16) + "texture { pigment { rgb 1 }\n}\n", 3, "block is not closed");
  expect_error(head + points(3), 3, "block is not closed");
  expect_error(head + "smoothness 2\n" + points(16) + "}", 4, "unknown keyword 'smoothness'");
  expect_error(head + points(16) + "  hollow\n}", 8, "unknown keyword 'hollow'");
  expect_error(head + points(16) + "  rotate <0, 90, 0>\n}", 8, "transforms inside the block are not supported");
  expect_error(head + points(16) + "  type 1\n}", 8, "'type' must come before the control points");
  expect_error(head + "flatness <1, 2, 3>\n" + points(16) + "}", 4, "'flatness' needs a number");
  expect_error("\n\nbicubic_patch\n<1, 2, 3>", 4, "expected '{'");
  expect_error("\n/* never closed\n" + head + points(16) + "}", 2, "unterminated /* comment");
  expect_error("#include \"x.inc\n" + head + points(16) + "}", 1, "unterminated string");
  expect_error(head + points(16) + "}\n\nbicubic_patch { " + points(16, "\x01"), 10, "expected 16 control points, got 1");
}

TEST(PatchIo, FileWithoutPatchesOrUnreadable) {
  auto none = parse("sphere { <0, 0, 0>, 1 }\n// bicubic_patch {\n");
  ASSERT_FALSE(none.ok());
  EXPECT_EQ(none.error().message, "t.inc: no bicubic_patch block");
  auto missing = load_bicubic_patches("/nonexistent/teapot.inc");
  ASSERT_FALSE(missing.ok());
  EXPECT_EQ(missing.error().message.rfind("/nonexistent/teapot.inc: cannot open", 0), 0u) << missing.error().message;
}

TEST(PatchIo, TeapotParsesTo32Patches) {
  auto r = load_bicubic_patches(kTeapot);
  if (!r) GTEST_SKIP() << "no teapot (apt-get install povray-examples): " << r.error().message;
  ASSERT_EQ(r->size(), 32u);
  // The first rim patch, as written on lines 19-22 of teapot.inc.
  EXPECT_EQ((*r)[0].p[0], Vec3(1.4f, 0.0f, 2.4f));
  EXPECT_EQ((*r)[0].p[3], Vec3(0.0f, -1.4f, 2.4f));
  EXPECT_EQ((*r)[0].p[4], Vec3(1.3375f, 0.0f, 2.53125f));
  EXPECT_EQ((*r)[31].p[15], Vec3(1.5f, 0.0f, 0.15f));
}

// Counts the crossings of the whole teapot by a ray leaving the surface along the normal: even
// (out of the solid) when the normal points outward.
int crossings(const std::vector<PatchSurface>& teapot, const Ray& ray) {
  int n = 0;
  for (const PatchSurface& s : teapot) {
    float tmin = 0.0f, t, u, v;
    while (s.intersect(ray, tmin, kInfinity, t, u, v)) ++n, tmin = t + 1e-4f;
  }
  return n;
}

TEST(PatchIo, TeapotNormalsPointOutward) {
  auto r = load_bicubic_patches(kTeapot);
  if (!r) GTEST_SKIP() << "no teapot (apt-get install povray-examples): " << r.error().message;
  std::vector<PatchSurface> teapot;
  for (const BezierPatch& p : *r) teapot.emplace_back(p, 4);
  // Parity along the normal from 5 x 5 points of each patch. The handle and spout ends lie
  // inside the body (the teapot is not a clean solid there), so a few samples per patch may
  // count wrong; every patch must be outward on a large majority.
  int outward_total = 0;
  for (size_t k = 0; k < r->size(); ++k) {
    int outward = 0;
    for (int a = 0; a < 5; ++a)
      for (int b = 0; b < 5; ++b) {
        const float u = 0.1f + 0.2f * a, v = 0.1f + 0.2f * b;
        const Vec3 n = bezier_normal((*r)[k], u, v);
        Ray ray;
        ray.org = bezier_eval((*r)[k], u, v) + 1e-3f * n;
        ray.dir = n;
        outward += crossings(teapot, ray) % 2 == 0;
      }
    EXPECT_GE(outward, 20) << "patch " << k;
    outward_total += outward;
  }
  EXPECT_GE(outward_total, 32 * 25 * 95 / 100);
  // POV-Ray's own order (u along the rows) is the transpose: its du x dv points inward.
  BezierPatch body = (*r)[4], transposed;
  for (int i = 0; i < 4; ++i)
    for (int j = 0; j < 4; ++j) transposed.p[4 * i + j] = body.p[4 * j + i];
  const Vec3 q = bezier_eval(body, 0.5f, 0.5f);
  EXPECT_GT(glm::dot(bezier_normal(body, 0.5f, 0.5f), Vec3(q.x, q.y, 0.0f)), 0.0f);
  EXPECT_LT(glm::dot(bezier_normal(transposed, 0.5f, 0.5f), Vec3(q.x, q.y, 0.0f)), 0.0f);
}

}  // namespace
}  // namespace frameless
