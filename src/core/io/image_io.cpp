// Texture image decoding (PNG, JPEG, OpenEXR, Radiance HDR, told apart by magic bytes) and the per-file cache.
// Libraries never print or exit: their messages become one-line Errors naming the file.
#include "core/io/image_io.h"

#include <algorithm>
#include <cmath>
#include <csetjmp>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <limits>
#include <new>
#include <system_error>

#include <png.h>
// jpeglib.h needs FILE and size_t (cstdio) first; jerror.h needs jpeglib.h's configuration.
#include <jpeglib.h>
#include <jerror.h>

#include <IexBaseExc.h>
#include <ImathBox.h>
#include <ImfChannelList.h>
#include <ImfFrameBuffer.h>
#include <ImfHeader.h>
#include <ImfIO.h>
#include <ImfInputFile.h>

#include "core/io/exr_stream.h"
#include "core/io/file_util.h"
#include "core/io/image_rgbe.h"

namespace frameless {
namespace {

constexpr uint64_t kMaxTextureSide = 8192;  // for the message only
static_assert(kMaxTextureSide * kMaxTextureSide == kMaxTexturePixels);

// Library messages may carry newlines or trailing dots; errors stay on one line.
Error library_error(const std::string& path, std::string what) {
  for (char& c : what)
    if (c == '\n' || c == '\r' || c == '\t') c = ' ';
  while (!what.empty() && (what.back() == ' ' || what.back() == '.')) what.pop_back();
  return Error{path + ": " + what};
}

// The decompression-bomb check, done on the header before any texel is allocated.
bool size_ok(uint64_t w, uint64_t h) {
  return w > 0 && h > 0 && w <= kMaxTexturePixels && h <= kMaxTexturePixels &&
         w * h <= kMaxTexturePixels;
}

Error size_error(const std::string& path, int64_t w, int64_t h) {
  const std::string dims = std::to_string(w) + "x" + std::to_string(h);
  if (w <= 0 || h <= 0) return library_error(path, "image is " + dims + ", which has no pixels");
  const std::string side = std::to_string(kMaxTextureSide);
  return library_error(path, "image is " + dims + ", larger than the " + side + "x" + side +
                                 " texture limit");
}

uint32_t read_be32(const std::string& b, size_t at) {
  return uint32_t(uint8_t(b[at])) << 24 | uint32_t(uint8_t(b[at + 1])) << 16 |
         uint32_t(uint8_t(b[at + 2])) << 8 | uint32_t(uint8_t(b[at + 3]));
}

uint32_t read_le32(const std::string& b, size_t at) {
  return uint32_t(uint8_t(b[at])) | uint32_t(uint8_t(b[at + 1])) << 8 |
         uint32_t(uint8_t(b[at + 2])) << 16 | uint32_t(uint8_t(b[at + 3])) << 24;
}

// ---- PNG (libpng classic API: no gamma transform, so texels stay as stored) ----

struct PngJob {
  const std::string* bytes = nullptr;
  size_t pos = 0;
  png_structp png = nullptr;
  png_infop info = nullptr;
  Image* image = nullptr;
  std::vector<png_bytep> rows;
  bool too_large = false;
  char message[256] = "";
};

void png_read_bytes(png_structp png, png_bytep out, size_t n) {
  auto* job = static_cast<PngJob*>(png_get_io_ptr(png));
  if (n > job->bytes->size() - job->pos) png_error(png, "file is truncated");
  std::memcpy(out, job->bytes->data() + job->pos, n);
  job->pos += n;
}

void png_on_error(png_structp png, png_const_charp msg) {
  auto* job = static_cast<PngJob*>(png_get_error_ptr(png));
  std::snprintf(job->message, sizeof job->message, "%s", msg);
  png_longjmp(png, 1);
}

void png_on_warning(png_structp, png_const_charp) {}

// Runs libpng; false on error (job.message) or refusal (job.too_large). No C++ object lives in
// this frame, so a longjmp back here skips no destructor.
bool run_png(PngJob& job) {
  png_structp png = job.png;
  png_infop info = job.info;
  if (setjmp(png_jmpbuf(png))) return false;
  png_set_read_fn(png, &job, png_read_bytes);
  png_read_info(png, info);
  const uint32_t w = png_get_image_width(png, info), h = png_get_image_height(png, info);
  if (!size_ok(w, h)) {
    job.image->width = int(std::min<uint32_t>(w, std::numeric_limits<int>::max()));
    job.image->height = int(std::min<uint32_t>(h, std::numeric_limits<int>::max()));
    job.too_large = true;
    return false;
  }
  const int color = png_get_color_type(png, info), depth = png_get_bit_depth(png, info);
  if (color == PNG_COLOR_TYPE_PALETTE) png_set_palette_to_rgb(png);
  if (color == PNG_COLOR_TYPE_GRAY && depth < 8) png_set_expand_gray_1_2_4_to_8(png);
  if (png_get_valid(png, info, PNG_INFO_tRNS)) png_set_tRNS_to_alpha(png);
  if (depth == 16) png_set_scale_16(png);  // rounds (strip_16 would truncate)
  png_set_interlace_handling(png);
  png_read_update_info(png, info);
  const int channels = png_get_channels(png, info);
  if (channels < 1 || channels > 4 || png_get_rowbytes(png, info) != size_t(w) * channels)
    png_error(png, "unsupported pixel layout");
  Image& img = *job.image;
  img.width = int(w);
  img.height = int(h);
  img.channels = channels;
  img.ldr.resize(size_t(w) * h * channels);
  job.rows.resize(h);
  for (uint32_t y = 0; y < h; ++y) job.rows[y] = img.ldr.data() + size_t(y) * w * channels;
  png_read_image(png, job.rows.data());
  png_read_end(png, nullptr);  // a file cut after the pixels still lacks IEND: an error
  return true;
}

Result<std::shared_ptr<const Image>> decode_png(const std::string& bytes, const std::string& path) {
  // IHDR is the first chunk: refuse absurd sizes before libpng sees the file.
  if (bytes.size() >= 24 && bytes.compare(12, 4, "IHDR") == 0) {
    const uint32_t w = read_be32(bytes, 16), h = read_be32(bytes, 20);
    if (!size_ok(w, h)) return size_error(path, w, h);
  }
  auto image = std::make_shared<Image>();
  image->path = path;
  PngJob job;
  job.bytes = &bytes;
  job.image = image.get();
  job.png = png_create_read_struct(PNG_LIBPNG_VER_STRING, &job, png_on_error, png_on_warning);
  if (job.png) job.info = png_create_info_struct(job.png);
  if (!job.png || !job.info) {
    png_destroy_read_struct(job.png ? &job.png : nullptr, nullptr, nullptr);
    return library_error(path, "out of memory");
  }
  bool ok = false;
  try {
    ok = run_png(job);
  } catch (const std::bad_alloc&) {
    std::snprintf(job.message, sizeof job.message, "out of memory");
  }
  png_destroy_read_struct(&job.png, &job.info, nullptr);
  if (job.too_large) return size_error(path, image->width, image->height);
  if (!ok) return library_error(path, std::string("invalid PNG: ") + job.message);
  return std::shared_ptr<const Image>(std::move(image));
}

// ---- JPEG (libjpeg-turbo) ----

struct JpegError {
  jpeg_error_mgr mgr;  // first, so libjpeg's pointer converts back
  std::jmp_buf jump;
  char message[JMSG_LENGTH_MAX];
};

[[noreturn]] void jpeg_on_error(j_common_ptr cinfo) {
  auto* err = reinterpret_cast<JpegError*>(cinfo->err);
  (*cinfo->err->format_message)(cinfo, err->message);
  std::longjmp(err->jump, 1);
}

// Warnings that mean the data is cut or corrupt end the decode: no partial images.
void jpeg_on_message(j_common_ptr cinfo, int level) {
  if (level >= 0) return;  // trace messages
  switch (cinfo->err->msg_code) {
    case JWRN_JPEG_EOF:
    case JWRN_HIT_MARKER:
    case JWRN_MUST_RESYNC:
    case JWRN_HUFF_BAD_CODE:
    case JWRN_ARITH_BAD_CODE:
    case JWRN_NOT_SEQUENTIAL:
    case JWRN_BOGUS_PROGRESSION:
      jpeg_on_error(cinfo);
    default:
      cinfo->err->num_warnings++;
  }
}

void jpeg_silent(j_common_ptr) {}

struct JpegJob {
  const std::string* bytes = nullptr;
  jpeg_decompress_struct cinfo;
  JpegError err;
  Image* image = nullptr;
  bool created = false;
  bool too_large = false;
};

// Runs libjpeg; same frame discipline as run_png.
bool run_jpeg(JpegJob& job) {
  jpeg_decompress_struct* cinfo = &job.cinfo;
  cinfo->err = jpeg_std_error(&job.err.mgr);
  job.err.mgr.error_exit = jpeg_on_error;
  job.err.mgr.emit_message = jpeg_on_message;
  job.err.mgr.output_message = jpeg_silent;
  job.err.message[0] = '\0';
  if (setjmp(job.err.jump)) return false;
  jpeg_create_decompress(cinfo);
  job.created = true;
  jpeg_mem_src(cinfo, reinterpret_cast<const unsigned char*>(job.bytes->data()),
               (unsigned long)job.bytes->size());
  if (jpeg_read_header(cinfo, TRUE) != JPEG_HEADER_OK) ERREXIT(cinfo, JERR_NO_IMAGE);
  Image& img = *job.image;
  img.width = int(cinfo->image_width);
  img.height = int(cinfo->image_height);
  if (!size_ok(cinfo->image_width, cinfo->image_height)) {
    job.too_large = true;
    return false;
  }
  const J_COLOR_SPACE in = cinfo->jpeg_color_space;
  const bool cmyk = in == JCS_CMYK || in == JCS_YCCK;
  cinfo->out_color_space = in == JCS_GRAYSCALE ? JCS_GRAYSCALE : cmyk ? JCS_CMYK : JCS_RGB;
  jpeg_start_decompress(cinfo);
  const int n = cinfo->output_components;
  if (n != (in == JCS_GRAYSCALE ? 1 : cmyk ? 4 : 3)) ERREXIT(cinfo, JERR_CONVERSION_NOTIMPL);
  const size_t w = cinfo->output_width, h = cinfo->output_height;
  img.width = int(w);
  img.height = int(h);
  img.channels = cmyk ? 3 : n;
  img.ldr.resize(w * h * size_t(n));  // CMYK is packed down to RGB in place below
  while (cinfo->output_scanline < h) {
    JSAMPROW row = img.ldr.data() + size_t(cinfo->output_scanline) * w * n;
    if (jpeg_read_scanlines(cinfo, &row, 1) != 1) ERREXIT(cinfo, JERR_INPUT_EOF);
  }
  jpeg_finish_decompress(cinfo);
  if (cmyk) {
    // Adobe writes inverted CMYK (libjpeg hands it back as stored): R = C*K/255.
    uint8_t* p = img.ldr.data();
    for (size_t i = 0; i < w * h; ++i) {
      const unsigned k = p[4 * i + 3];
      for (int c = 0; c < 3; ++c) p[3 * i + c] = uint8_t((p[4 * i + c] * k + 127) / 255);
    }
    img.ldr.resize(w * h * 3);
  }
  return true;
}

Result<std::shared_ptr<const Image>> decode_jpeg(const std::string& bytes,
                                                 const std::string& path) {
  auto image = std::make_shared<Image>();
  image->path = path;
  JpegJob job;
  job.bytes = &bytes;
  job.image = image.get();
  bool ok = false;
  try {
    ok = run_jpeg(job);
  } catch (const std::bad_alloc&) {
    std::snprintf(job.err.message, sizeof job.err.message, "out of memory");
  }
  if (job.created) jpeg_destroy_decompress(&job.cinfo);
  if (job.too_large) return size_error(path, image->width, image->height);
  if (!ok) return library_error(path, std::string("invalid JPEG: ") + job.err.message);
  return std::shared_ptr<const Image>(std::move(image));
}

// ---- OpenEXR (C++ API over the bytes in memory) ----

Result<std::shared_ptr<const Image>> decode_exr(const std::string& bytes, const std::string& path) {
  auto image = std::make_shared<Image>();
  image->path = path;
  try {
    ExrMemoryStream stream(bytes, path);
    // Header first, alone: the size check must come before InputFile sizes its tables, and the
    // attributes' claimed sizes before OpenEXR allocates them.
    if (const std::string p = exr_header_problem(bytes); !p.empty()) return library_error(path, "invalid EXR: " + p);
    Imf::Header header;
    int version = int(read_le32(bytes, 4));
    stream.seekg(8);
    header.readFrom(stream, version);
    const Imath::Box2i dw = header.dataWindow();
    const int64_t w = int64_t(dw.max.x) - dw.min.x + 1, h = int64_t(dw.max.y) - dw.min.y + 1;
    if (w <= 0 || h <= 0 || !size_ok(uint64_t(w), uint64_t(h))) return size_error(path, w, h);
    if (const std::string p = exr_chunk_problem(header); !p.empty()) return library_error(path, "invalid EXR: " + p);

    stream.seekg(0);
    Imf::InputFile file(stream);
    const Imf::ChannelList& list = file.header().channels();
    const bool rgb = list.findChannel("R") || list.findChannel("G") || list.findChannel("B");
    const bool alpha = list.findChannel("A") != nullptr;
    if (!rgb && !list.findChannel("Y")) return library_error(path, "EXR has no R, G, B or Y channel");
    std::vector<const char*> names = rgb ? std::vector<const char*>{"R", "G", "B"}
                                         : std::vector<const char*>{"Y"};
    if (alpha) names.push_back("A");
    for (const char* name : names) {
      const Imf::Channel* c = list.findChannel(name);
      if (c && (c->xSampling != 1 || c->ySampling != 1))
        return library_error(path, std::string("EXR channel ") + name + " is subsampled (unsupported)");
    }
    if (!file.isComplete()) return library_error(path, "EXR file is truncated");

    const int n = int(names.size());
    image->width = int(w);
    image->height = int(h);
    image->channels = n;
    image->hdr.assign(size_t(w) * size_t(h) * size_t(n), 0.0f);
    Imf::FrameBuffer fb;
    for (int k = 0; k < n; ++k)  // a channel missing from the file reads as the fill value 0
      fb.insert(names[size_t(k)],
                Imf::Slice::Make(Imf::FLOAT, image->hdr.data() + k, dw, sizeof(float) * n,
                                 sizeof(float) * n * size_t(w)));
    file.setFrameBuffer(fb);
    file.readPixels(dw.min.y, dw.max.y);
  } catch (const std::bad_alloc&) {
    return library_error(path, "out of memory");
  } catch (const std::exception& e) {
    return library_error(path, std::string("invalid EXR: ") + e.what());
  } catch (...) {
    return library_error(path, "invalid EXR");
  }
  // Non-finite texels read as 0; huge ones are capped so that bilinear sums stay finite.
  constexpr float kCap = 1e30f;
  for (float& v : image->hdr) v = std::isfinite(v) ? std::clamp(v, -kCap, kCap) : 0.0f;
  return std::shared_ptr<const Image>(std::move(image));
}

bool starts_with(const std::string& b, const char* magic, size_t n) {
  return b.size() >= n && std::memcmp(b.data(), magic, n) == 0;
}

}  // namespace

Result<std::shared_ptr<const Image>> decode_image(const std::string& bytes,
                                                  const std::string& path) {
  if (bytes.empty()) return library_error(path, "file is empty");
  if (starts_with(bytes, "\x89PNG\r\n\x1a\n", 8)) return decode_png(bytes, path);
  if (starts_with(bytes, "\xff\xd8\xff", 3)) return decode_jpeg(bytes, path);
  if (starts_with(bytes, "\x76\x2f\x31\x01", 4)) {
    if (bytes.size() < 8) return library_error(path, "invalid EXR: file is truncated");
    return decode_exr(bytes, path);
  }
  if (looks_like_rgbe(bytes)) return decode_rgbe(bytes, path);
  return library_error(path, "unknown image format (expected PNG, JPEG, OpenEXR or Radiance HDR)");
}

Result<std::shared_ptr<const Image>> load_image(const std::string& path) {
  auto bytes = read_file_bytes(path);
  if (!bytes) return bytes.error();
  return decode_image(*bytes, path);
}

Result<std::shared_ptr<const Image>> ImageCache::get(const std::string& path) {
  std::error_code ec;
  std::string key = std::filesystem::weakly_canonical(path, ec).string();
  if (ec || key.empty()) key = path;
  for (const auto& [k, image] : images_)
    if (k == key) return image;
  auto image = load_image(path);
  if (image) images_.emplace_back(key, *image);
  return image;
}

}  // namespace frameless
