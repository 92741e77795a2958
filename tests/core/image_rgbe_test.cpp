// Radiance HDR files (written here by an encoder of the test's own): flat, new-style and
// old-style run-length scanlines decode to the same texels, both row orders, EXPOSURE, and one
// line for every kind of broken file.
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "core/io/image_io.h"
#include "core/io/image_rgbe.h"

namespace frameless {
namespace {

using Pixel = std::array<uint8_t, 4>;

Pixel to_rgbe(float r, float g, float b) {
  const float v = std::max({r, g, b});
  if (v < 1e-32f) return {0, 0, 0, 0};
  int e = 0;
  const float scale = std::frexp(v, &e) * 256.0f / v;
  return {uint8_t(r * scale), uint8_t(g * scale), uint8_t(b * scale), uint8_t(e + 128)};
}

enum class Encoding { kFlat, kRunLength, kOldRepeats };

// A whole file: header, resolution line and the scanlines in `rows` (top row first).
std::string hdr_file(const std::vector<std::vector<Pixel>>& rows, Encoding enc, const std::string& extra = "",
                     bool bottom_up = false) {
  const int h = int(rows.size()), w = int(rows[0].size());
  std::string out = "#?RADIANCE\n# written by a test\nFORMAT=32-bit_rle_rgbe\n" + extra + "\n";
  out += (bottom_up ? "+Y " : "-Y ") + std::to_string(h) + " +X " + std::to_string(w) + "\n";
  for (int k = 0; k < h; ++k) {
    const std::vector<Pixel>& row = rows[size_t(bottom_up ? h - 1 - k : k)];
    if (enc == Encoding::kRunLength) {
      out += {2, 2, char(w >> 8), char(w & 255)};
      for (int c = 0; c < 4; ++c)
        for (int x = 0; x < w;) {  // runs of equal bytes (length >= 3), literals between them
          int run = 1;
          while (x + run < w && run < 127 && row[x + run][c] == row[x][c]) ++run;
          if (run >= 3) {
            out += {char(128 + run), char(row[x][c])};
            x += run;
            continue;
          }
          int lit = 1;
          while (x + lit < w && lit < 128 && !(x + lit + 2 < w && row[x + lit][c] == row[x + lit + 1][c] &&
                                               row[x + lit][c] == row[x + lit + 2][c]))
            ++lit;
          out += char(lit);
          for (int k2 = 0; k2 < lit; ++k2) out += char(row[x + k2][c]);
          x += lit;
        }
    } else {
      for (int x = 0; x < w;) {
        out.append(reinterpret_cast<const char*>(row[x].data()), 4);
        int same = 0;
        while (enc == Encoding::kOldRepeats && x + 1 + same < w && row[x + 1 + same] == row[x] && same < 255) ++same;
        if (same > 0) out += {1, 1, 1, char(same)};
        x += 1 + same;
      }
    }
  }
  return out;
}

// A 40 x 5 image of random radiance over six decades, with runs of equal pixels.
std::vector<std::vector<Pixel>> test_rows() {
  std::mt19937 rng(7);
  std::uniform_real_distribution<float> decade(-3.0f, 3.0f), u(0.0f, 1.0f);
  std::vector<std::vector<Pixel>> rows(5, std::vector<Pixel>(40));
  for (auto& row : rows)
    for (int x = 0; x < 40; ++x) {
      const float s = std::pow(10.0f, decade(rng));
      row[size_t(x)] = x > 0 && x % 10 < 6 ? row[size_t(x - 1)] : to_rgbe(s * u(rng), s * u(rng), s * u(rng));
    }
  rows[2][5] = {0, 0, 0, 0};
  return rows;
}

float expected(const Pixel& p, int c) { return p[3] == 0 ? 0.0f : float((p[c] + 0.5) * std::ldexp(1.0, p[3] - 136)); }

TEST(RadianceHdr, EveryScanlineEncodingDecodesToTheSameTexels) {
  const auto rows = test_rows();
  for (Encoding enc : {Encoding::kFlat, Encoding::kRunLength, Encoding::kOldRepeats}) {
    const std::string bytes = hdr_file(rows, enc);
    auto img = decode_image(bytes, "sky.hdr");
    ASSERT_TRUE(img) << img.error().message;
    const Image& im = **img;
    ASSERT_EQ(im.width, 40);
    ASSERT_EQ(im.height, 5);
    ASSERT_EQ(im.channels, 3);
    ASSERT_TRUE(im.ldr.empty());
    for (int y = 0; y < 5; ++y)
      for (int x = 0; x < 40; ++x)
        for (int c = 0; c < 3; ++c)
          ASSERT_EQ(im.hdr[size_t((y * 40 + x) * 3 + c)], expected(rows[size_t(y)][size_t(x)], c))
              << "encoding " << int(enc) << " at " << x << "," << y;
  }
  // The run-length file is smaller than the flat one: the runs were really used.
  EXPECT_LT(hdr_file(rows, Encoding::kRunLength).size(), hdr_file(rows, Encoding::kFlat).size());
  EXPECT_LT(hdr_file(rows, Encoding::kOldRepeats).size(), hdr_file(rows, Encoding::kFlat).size());
}

TEST(RadianceHdr, ValuesRoundTripWithinTheFormatsPrecision) {
  for (float v : {1e-4f, 0.18f, 1.0f, 3.7f, 1234.5f}) {
    const std::vector<std::vector<Pixel>> rows(1, std::vector<Pixel>(8, to_rgbe(v, 0.5f * v, 0.25f * v)));
    auto img = decode_image(hdr_file(rows, Encoding::kFlat), "v.hdr");
    ASSERT_TRUE(img) << img.error().message;
    EXPECT_NEAR((*img)->hdr[0], v, v / 128.0f);  // 8-bit mantissa of the largest channel
    EXPECT_NEAR((*img)->hdr[1], 0.5f * v, v / 128.0f);
    EXPECT_NEAR((*img)->hdr[2], 0.25f * v, v / 128.0f);
  }
}

TEST(RadianceHdr, BottomUpFilesAndExposure) {
  const auto rows = test_rows();
  auto top = decode_image(hdr_file(rows, Encoding::kRunLength), "a.hdr");
  auto bottom = decode_image(hdr_file(rows, Encoding::kRunLength, "", true), "b.hdr");
  ASSERT_TRUE(top && bottom);
  EXPECT_EQ((*top)->hdr, (*bottom)->hdr);  // +Y files list the bottom row first
  auto exposed = decode_image(hdr_file(rows, Encoding::kFlat, "EXPOSURE=2\nEXPOSURE=4\n"), "e.hdr");
  ASSERT_TRUE(exposed) << exposed.error().message;
  for (size_t k = 0; k < (*top)->hdr.size(); ++k) ASSERT_FLOAT_EQ((*exposed)->hdr[k] * 8.0f, (*top)->hdr[k]);
}

TEST(RadianceHdr, BrokenFilesGetOneLineNamingTheFileAndTheFault) {
  const auto rows = test_rows();
  const std::string good = hdr_file(rows, Encoding::kRunLength);
  const size_t data = good.find("+X 40\n") + 6;
  struct Case {
    std::string bytes, says;
  };
  std::string zero_run = good, long_run = good, wrong_width = good;
  zero_run[data + 4] = 0;
  long_run[data + 4] = char(128 + 100);
  wrong_width[data + 3] = 41;
  const std::vector<Case> cases = {
      {good.substr(0, good.size() - 7), "truncated at scanline 4"},
      {good.substr(0, data + 2), "truncated"},
      {"#?RADIANCE\nFORMAT=32-bit_rle_xyze\n\n-Y 1 +X 1\n\x80\x80\x80\x80", "unsupported Radiance pixel format"},
      {"#?RADIANCE\nFORMAT=32-bit_rle_rgbe\n-Y 1 +X 1\n", "no end"},
      {"#?RADIANCE\n\n-Y 2 -X 2\n", "unsupported resolution line"},
      {"#?RADIANCE\n\n+X 2 -Y 2\n", "unsupported resolution line"},
      {"#?RADIANCE\n\n-Y 0 +X 2\n", "unsupported resolution line"},
      {"#?RADIANCE\n\n-Y 100000 +X 100000\n", "larger than the 8192x8192 texture limit"},
      {"#?RADIANCE\nEXPOSURE=-1\n\n-Y 1 +X 1\n", "EXPOSURE is not a positive number"},
      {"#?RADIANCE\n\n-Y 1 +X 2\n\x01\x01\x01\x01\x01\x01\x01\x01", "repeat before the scanline's first pixel"},
      {zero_run, "run of length 0"},
      {long_run, "crosses the scanline's end"},
      {wrong_width, "width differs"},
      // Quoted header text with a carriage return inside stays on one line (a fuzzer finding).
      {std::string("#?RADIANCE\nFORMAT=32-bit_rle_rgbe\rx\n\n-Y 1 +X 1\n"), "unsupported Radiance pixel format"},
  };
  for (const Case& c : cases) {
    auto img = decode_image(c.bytes, "dir/sky.hdr");
    ASSERT_FALSE(img) << c.says;
    const std::string& m = img.error().message;
    EXPECT_EQ(m.rfind("dir/sky.hdr: ", 0), 0u) << m;
    EXPECT_NE(m.find(c.says), std::string::npos) << m;
    EXPECT_EQ(m.find_first_of("\n\r"), std::string::npos) << m;
  }
}

}  // namespace
}  // namespace frameless
