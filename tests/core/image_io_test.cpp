// Image files: PNG/JPEG/OpenEXR decoding (files written here by libpng, libjpeg and by hand for
// EXR), refusal of bad files before allocating, and the shared image cache.
#include <unistd.h>

#include <cmath>
#include <csetjmp>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <random>

#include <gtest/gtest.h>
#include <jpeglib.h>
#include <png.h>

#include "core/io/image_io.h"
#include "core/scene/texture.h"
#include "exr_writer.h"
#include "png_chunks.h"

namespace frameless {
namespace {

namespace fs = std::filesystem;

// ---- writers ----

void append_png(png_structp png, png_bytep data, size_t n) {
  static_cast<std::string*>(png_get_io_ptr(png))->append(reinterpret_cast<char*>(data), n);
}

// Encodes rows with libpng (16-bit samples big-endian); "" on failure. Every object here exists
// before setjmp, so the longjmp skips no destructor.
std::string png_file(int w, int h, int color, int depth, const std::vector<uint8_t>& data,
                     const std::vector<png_color>& palette = {},
                     const std::vector<uint8_t>& trns = {}) {
  std::string out;
  png_structp png = png_create_write_struct(PNG_LIBPNG_VER_STRING, nullptr, nullptr, nullptr);
  png_infop info = png_create_info_struct(png);
  if (setjmp(png_jmpbuf(png))) {
    png_destroy_write_struct(&png, &info);
    ADD_FAILURE() << "libpng could not write the test image";
    return "";
  }
  png_set_write_fn(png, &out, append_png, nullptr);
  png_set_IHDR(png, info, uint32_t(w), uint32_t(h), depth, color, PNG_INTERLACE_NONE,
               PNG_COMPRESSION_TYPE_DEFAULT, PNG_FILTER_TYPE_DEFAULT);
  if (!palette.empty()) png_set_PLTE(png, info, palette.data(), int(palette.size()));
  if (!trns.empty()) png_set_tRNS(png, info, trns.data(), int(trns.size()), nullptr);
  png_write_info(png, info);
  const size_t row_bytes = png_get_rowbytes(png, info);
  for (int y = 0; y < h; ++y) png_write_row(png, data.data() + size_t(y) * row_bytes);
  png_write_end(png, nullptr);
  png_destroy_write_struct(&png, &info);
  return out;
}

std::string jpeg_file(int w, int h, int components, const std::vector<uint8_t>& data) {
  jpeg_compress_struct cinfo;
  jpeg_error_mgr err;
  cinfo.err = jpeg_std_error(&err);
  jpeg_create_compress(&cinfo);
  unsigned char* buffer = nullptr;
  unsigned long size = 0;
  jpeg_mem_dest(&cinfo, &buffer, &size);
  cinfo.image_width = JDIMENSION(w);
  cinfo.image_height = JDIMENSION(h);
  cinfo.input_components = components;
  cinfo.in_color_space = components == 1 ? JCS_GRAYSCALE : JCS_RGB;
  jpeg_set_defaults(&cinfo);
  jpeg_set_quality(&cinfo, 100, TRUE);
  jpeg_start_compress(&cinfo, TRUE);
  while (cinfo.next_scanline < cinfo.image_height) {
    JSAMPROW row = const_cast<uint8_t*>(data.data()) + size_t(cinfo.next_scanline) * w * components;
    jpeg_write_scanlines(&cinfo, &row, 1);
  }
  jpeg_finish_compress(&cinfo);
  jpeg_destroy_compress(&cinfo);
  std::string out(reinterpret_cast<char*>(buffer), size);
  std::free(buffer);
  return out;
}

using testing::crc32;
using testing::be32;
using testing::png_chunk;
using testing::write_exr;

std::string read_all(const std::string& path) {
  std::ifstream f(path, std::ios::binary);
  return std::string(std::istreambuf_iterator<char>(f), {});
}

class TextureFile : public ::testing::Test {
 protected:
  void SetUp() override {
    const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
    dir_ = fs::temp_directory_path() /
           ("frameless_texture_" + std::to_string(getpid()) + "_" + info->name());
    fs::remove_all(dir_);
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }

  std::string write(const std::string& name, const std::string& bytes) {
    const std::string path = (dir_ / name).string();
    fs::create_directories(fs::path(path).parent_path());
    std::ofstream(path, std::ios::binary) << bytes;
    return path;
  }
  std::string path(const std::string& name) const { return (dir_ / name).string(); }

  // Loads a file that must fail; the message names it and is one line.
  std::string refused(const std::string& p) {
    auto img = load_image(p);
    EXPECT_FALSE(img.ok()) << p;
    if (img.ok()) return "";
    const std::string& m = img.error().message;
    EXPECT_EQ(m.rfind(p + ": ", 0), 0u) << m;
    EXPECT_EQ(m.find('\n'), std::string::npos) << m;
    return m;
  }

  fs::path dir_;
};

std::shared_ptr<const Image> must_load(const std::string& path) {
  auto img = load_image(path);
  EXPECT_TRUE(img.ok()) << img.error().message;
  return img.ok() ? *img : nullptr;
}

// ---- decoding ----

TEST_F(TextureFile, DecodesPngLayouts) {
  auto grey = must_load(write("g.png", png_file(2, 1, PNG_COLOR_TYPE_GRAY, 8, {10, 200})));
  ASSERT_TRUE(grey);
  EXPECT_EQ(grey->channels, 1);
  EXPECT_EQ(grey->ldr, (std::vector<uint8_t>{10, 200}));
  EXPECT_TRUE(grey->hdr.empty());

  auto ga = must_load(write("ga.png", png_file(1, 1, PNG_COLOR_TYPE_GRAY_ALPHA, 8, {7, 99})));
  ASSERT_TRUE(ga);
  EXPECT_EQ(ga->channels, 2);
  EXPECT_EQ(ga->ldr, (std::vector<uint8_t>{7, 99}));

  // 1x2 RGB: row 0 of the file is row 0 of the image.
  auto rgb = must_load(write("rgb.png", png_file(1, 2, PNG_COLOR_TYPE_RGB, 8, {1, 2, 3, 4, 5, 6})));
  ASSERT_TRUE(rgb);
  EXPECT_EQ(rgb->width, 1);
  EXPECT_EQ(rgb->height, 2);
  EXPECT_EQ(rgb->channels, 3);
  EXPECT_EQ(rgb->ldr, (std::vector<uint8_t>{1, 2, 3, 4, 5, 6}));

  auto rgba = must_load(write("rgba.png", png_file(1, 1, PNG_COLOR_TYPE_RGBA, 8, {9, 8, 7, 6})));
  ASSERT_TRUE(rgba);
  EXPECT_EQ(rgba->channels, 4);
  EXPECT_EQ(rgba->ldr, (std::vector<uint8_t>{9, 8, 7, 6}));

  // Palette with a transparent entry expands to RGBA.
  auto pal = must_load(write("pal.png", png_file(2, 1, PNG_COLOR_TYPE_PALETTE, 8, {1, 0},
                                                 {{10, 20, 30}, {40, 50, 60}}, {128})));
  ASSERT_TRUE(pal);
  EXPECT_EQ(pal->channels, 4);
  EXPECT_EQ(pal->ldr, (std::vector<uint8_t>{40, 50, 60, 255, 10, 20, 30, 128}));

  // 2-bit grey 0,1,2,3 packed in one byte expands to 0,85,170,255.
  auto g2 = must_load(write("g2.png", png_file(4, 1, PNG_COLOR_TYPE_GRAY, 2, {0x1b})));
  ASSERT_TRUE(g2);
  EXPECT_EQ(g2->ldr, (std::vector<uint8_t>{0, 85, 170, 255}));

  // 16-bit samples become 8-bit.
  auto rgb16 = must_load(write(
      "rgb16.png", png_file(1, 1, PNG_COLOR_TYPE_RGB, 16, {0x80, 0x80, 0xff, 0xff, 0x00, 0x00})));
  ASSERT_TRUE(rgb16);
  EXPECT_EQ(rgb16->channels, 3);
  EXPECT_EQ(rgb16->ldr, (std::vector<uint8_t>{128, 255, 0}));
}

TEST_F(TextureFile, DecodesJpeg) {
  std::vector<uint8_t> flat(16 * 16 * 3);
  for (size_t i = 0; i < flat.size(); i += 3) flat[i] = 200, flat[i + 1] = 100, flat[i + 2] = 50;
  auto rgb = must_load(write("c.jpg", jpeg_file(16, 16, 3, flat)));
  ASSERT_TRUE(rgb);
  EXPECT_EQ(rgb->width, 16);
  EXPECT_EQ(rgb->height, 16);
  ASSERT_EQ(rgb->channels, 3);
  ASSERT_EQ(rgb->ldr.size(), flat.size());
  for (size_t i = 0; i < flat.size(); ++i) EXPECT_NEAR(rgb->ldr[i], flat[i], 3) << i;

  auto grey = must_load(write("g.jpg", jpeg_file(8, 8, 1, std::vector<uint8_t>(64, 77))));
  ASSERT_TRUE(grey);
  ASSERT_EQ(grey->channels, 1);
  for (uint8_t v : grey->ldr) EXPECT_NEAR(v, 77, 2);
}

TEST_F(TextureFile, DecodesExrAndZeroesNonFinite) {
  const float nan = std::numeric_limits<float>::quiet_NaN(), inf = kInfinity;
  write_exr(path("c.exr"), 2, 1, {"A", "B", "G", "R"},
            {{1.0f, 0.5f}, {3.0f, -inf}, {2.0f, 7.0f}, {nan, 1e4f}});
  auto img = must_load(path("c.exr"));
  ASSERT_TRUE(img);
  EXPECT_EQ(img->width, 2);
  EXPECT_EQ(img->height, 1);
  ASSERT_EQ(img->channels, 4);
  EXPECT_TRUE(img->ldr.empty());
  EXPECT_EQ(img->hdr, (std::vector<float>{0.0f, 2.0f, 3.0f, 1.0f, 1e4f, 7.0f, 0.0f, 0.5f}));

  write_exr(path("y.exr"), 1, 2, {"Y"}, {{0.25f, 4.0f}});
  auto y = must_load(path("y.exr"));
  ASSERT_TRUE(y);
  ASSERT_EQ(y->channels, 1);
  EXPECT_EQ(y->hdr, (std::vector<float>{0.25f, 4.0f}));
  Texture tex;
  tex.image = y;
  EXPECT_EQ(sample_texture(tex, {Vec2(0.5f, 0.75f), Vec3(0)}), Vec4(0.25f, 0.25f, 0.25f, 1.0f));
}

TEST_F(TextureFile, SrgbTexelsDecodeToLinearAlphaStaysLinear) {
  auto img = must_load(write("s.png", png_file(1, 1, PNG_COLOR_TYPE_RGBA, 8, {128, 255, 0, 128})));
  ASSERT_TRUE(img);
  Texture tex;
  tex.image = img;
  Vec4 c = sample_texture(tex, {Vec2(0.5f), Vec3(0)});
  EXPECT_NEAR(c.x, 0.2158605f, 1e-6f);
  EXPECT_EQ(c.y, 1.0f);
  EXPECT_EQ(c.z, 0.0f);
  EXPECT_NEAR(c.w, 128.0f / 255.0f, 1e-6f);
  tex.srgb = false;
  c = sample_texture(tex, {Vec2(0.5f), Vec3(0)});
  EXPECT_NEAR(c.x, 128.0f / 255.0f, 1e-6f);
  EXPECT_NEAR(c.w, 128.0f / 255.0f, 1e-6f);
}

// ---- cache ----

TEST_F(TextureFile, CacheSharesOneDecodePerFile) {
  const std::string bytes = png_file(1, 1, PNG_COLOR_TYPE_GRAY, 8, {5});
  write("dir/a.png", bytes);
  write("dir/b.png", bytes);
  ImageCache cache;
  auto a = cache.get(path("dir/a.png"));
  auto a2 = cache.get(path("dir/./a.png"));
  auto a3 = cache.get(path("dir/../dir/a.png"));
  ASSERT_TRUE(a.ok() && a2.ok() && a3.ok());
  EXPECT_EQ(a->get(), a2->get());
  EXPECT_EQ(a->get(), a3->get());
  EXPECT_EQ(cache.size(), 1u);
  auto b = cache.get(path("dir/b.png"));
  ASSERT_TRUE(b.ok());
  EXPECT_NE(a->get(), b->get());
  EXPECT_EQ(cache.size(), 2u);
  auto missing = cache.get(path("dir/none.png"));
  ASSERT_FALSE(missing.ok());
  EXPECT_EQ(cache.size(), 2u);
}

// ---- bad input ----

TEST_F(TextureFile, MissingFileSaysSo) {
  const std::string p = path("none.png");
  EXPECT_EQ(refused(p), p + ": cannot open: No such file or directory");
}

TEST_F(TextureFile, RefusesEmptyTruncatedAndRandomFiles) {
  refused(write("empty.png", ""));

  std::vector<uint8_t> pixels(64 * 64 * 3);
  std::mt19937 rng(7);
  for (uint8_t& v : pixels) v = uint8_t(rng());
  const std::string png = png_file(64, 64, PNG_COLOR_TYPE_RGB, 8, pixels);
  ASSERT_TRUE(decode_image(png, "whole.png").ok());
  refused(write("half.png", png.substr(0, png.size() / 2)));
  refused(write("no_iend.png", png.substr(0, png.size() - 12)));
  refused(write("signature.png", png.substr(0, 8)));

  const std::string jpg = jpeg_file(64, 64, 3, pixels);
  ASSERT_TRUE(decode_image(jpg, "whole.jpg").ok());
  refused(write("half.jpg", jpg.substr(0, jpg.size() / 2)));
  refused(write("header.jpg", jpg.substr(0, 300)));
  refused(write("soi.jpg", jpg.substr(0, 3)));

  write_exr(path("whole.exr"), 8, 8, {"R"}, {std::vector<float>(64, 1.0f)});
  const std::string exr = read_all(path("whole.exr"));
  ASSERT_TRUE(decode_image(exr, "whole.exr").ok());
  refused(write("half.exr", exr.substr(0, exr.size() / 2)));
  refused(write("magic.exr", exr.substr(0, 4)));

  std::string noise(4096, '\0');
  for (char& c : noise) c = char(rng());
  const std::string m = refused(write("noise.bin", noise));
  EXPECT_NE(m.find("unknown image format"), std::string::npos) << m;
  // Valid magic followed by garbage.
  refused(write("noise.png", png.substr(0, 8) + noise));
  refused(write("noise.jpg", jpg.substr(0, 2) + "\xff" + noise));
  refused(write("noise.exr", exr.substr(0, 8) + noise));
  refused(write("noise_after_header.exr", exr.substr(0, exr.size() - 300) + noise.substr(0, 300)));
}

TEST_F(TextureFile, RefusesHugePngBeforeAllocating) {
  // A valid signature and IHDR (with its CRC) claiming 100000 x 100000 RGBA, then an empty IDAT.
  const std::string ihdr = be32(100000) + be32(100000) + std::string("\x08\x06\x00\x00\x00", 5);
  const std::string bytes = std::string("\x89PNG\r\n\x1a\n", 8) + png_chunk("IHDR", ihdr) +
                            png_chunk("IDAT", "") + png_chunk("IEND", "");
  const std::string p = write("huge.png", bytes);
  EXPECT_EQ(refused(p), p + ": image is 100000x100000, larger than the 8192x8192 texture limit");
  // Zero width is refused too.
  const std::string zero = be32(0) + be32(5) + std::string("\x08\x02\x00\x00\x00", 5);
  refused(write("zero.png", std::string("\x89PNG\r\n\x1a\n", 8) + png_chunk("IHDR", zero) +
                                png_chunk("IEND", "")));
}

TEST_F(TextureFile, RefusesHugeJpegAndExrBeforeAllocating) {
  // JPEG: patch the SOF0 height and width to 10000 x 10000 (100 Mpixel).
  std::string jpg = jpeg_file(8, 8, 3, std::vector<uint8_t>(8 * 8 * 3, 40));
  const size_t sof = jpg.find("\xff\xc0");
  ASSERT_NE(sof, std::string::npos);
  for (size_t at : {sof + 5, sof + 7}) jpg[at] = char(10000 >> 8), jpg[at + 1] = char(10000 & 255);
  const std::string pj = write("huge.jpg", jpg);
  EXPECT_EQ(refused(pj), pj + ": image is 10000x10000, larger than the 8192x8192 texture limit");

  // EXR: patch the dataWindow box (xmin ymin xmax ymax, little-endian int32) to 20000 x 5000.
  write_exr(path("small.exr"), 4, 4, {"R"}, {std::vector<float>(16, 1.0f)});
  std::string exr = read_all(path("small.exr"));
  const std::string key("dataWindow\0box2i\0", 17);
  const size_t at = exr.find(key);
  ASSERT_NE(at, std::string::npos);
  const size_t box = at + key.size() + 4;
  const int32_t window[4] = {0, 0, 19999, 4999};
  std::memcpy(&exr[box], window, sizeof window);
  const std::string pe = write("huge.exr", exr);
  EXPECT_EQ(refused(pe), pe + ": image is 20000x5000, larger than the 8192x8192 texture limit");

  // Few pixels but a huge decoding buffer (the fuzzer's find): 16,777,216 x 1, ZIP (16 lines a
  // chunk) would make OpenEXR allocate 1 GiB before reading a pixel.
  const int32_t wide[4] = {0, 0, 16777215, 0};
  std::memcpy(&exr[box], wide, sizeof wide);
  const std::string ckey("compression\0compression\0", 24);
  const size_t cat = exr.find(ckey);
  ASSERT_NE(cat, std::string::npos);
  exr[cat + ckey.size() + 4] = char(3);  // ZIP_COMPRESSION
  const std::string pw = write("wide.exr", exr);
  EXPECT_EQ(refused(pw), pw + ": invalid EXR: a chunk needs 1073741824 bytes to decode (16777216 pixels wide, 16 "
                              "lines a chunk), more than 268435456");
}

}  // namespace
}  // namespace frameless
