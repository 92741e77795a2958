// Radiance HDR decoding: a text header, a resolution line, then RGBE scanlines (shared
// exponent: value = (mantissa + 0.5) * 2^(e - 136), Radiance's own colr_color rounding).
#include "core/io/image_rgbe.h"

#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <new>

#include "core/io/file_util.h"
#include "core/io/image_io.h"

namespace frameless {
namespace {

constexpr size_t kMaxHeader = 1 << 16;  // a header longer than this has lost its blank line

// One header line without its newline; false at the end of the bytes.
bool next_line(const std::string& b, size_t& pos, std::string& line) {
  const size_t end = b.find('\n', pos);
  if (end == std::string::npos || end - pos > kMaxHeader) return false;
  line.assign(b, pos, end - pos);
  if (!line.empty() && line.back() == '\r') line.pop_back();
  pos = end + 1;
  return true;
}

// A positive decimal integer of at most 9 digits; false otherwise.
bool parse_side(const char* s, const char** end, long& out) {
  if (*s < '0' || *s > '9') return false;
  char* e = nullptr;
  errno = 0;
  out = std::strtol(s, &e, 10);
  if (errno != 0 || out <= 0 || e - s > 9) return false;
  *end = e;
  return true;
}

// The scanline at `pos` into `out` (4 * width bytes): new-style run-length when it starts with
// 2, 2 and the width, otherwise flat pixels with old-style repeats (1, 1, 1, count).
const char* read_scanline(const std::string& b, size_t& pos, int width, uint8_t* out) {
  const auto at = [&](size_t k) { return uint8_t(b[pos + k]); };
  if (width >= 8 && width < 32768 && b.size() - pos >= 4 && at(0) == 2 && at(1) == 2 && !(at(2) & 0x80)) {
    if ((int(at(2)) << 8 | at(3)) != width) return "a run-length scanline's width differs from the image's";
    pos += 4;
    for (int c = 0; c < 4; ++c)
      for (int x = 0; x < width;) {
        if (pos >= b.size()) return "the file is truncated";
        int count = uint8_t(b[pos++]);
        const bool run = count > 128;
        if (run) count -= 128;
        if (count == 0) return "a run of length 0";
        if (count > width - x) return "a run crosses the scanline's end";
        if (b.size() - pos < size_t(run ? 1 : count)) return "the file is truncated";
        for (int k = 0; k < count; ++k, ++x) out[4 * x + c] = uint8_t(b[run ? pos : pos + k]);
        pos += run ? 1 : size_t(count);
      }
    return nullptr;
  }
  int shift = 0;
  for (int x = 0; x < width;) {
    if (b.size() - pos < 4) return "the file is truncated";
    const uint8_t* p = reinterpret_cast<const uint8_t*>(b.data() + pos);
    pos += 4;
    if (p[0] == 1 && p[1] == 1 && p[2] == 1) {  // old-style: repeat the previous pixel
      if (x == 0) return "a repeat before the scanline's first pixel";
      if (shift > 16) return "a repeat count too large";
      const long count = long(p[3]) << shift;
      if (count > width - x) return "a repeat crosses the scanline's end";
      for (long k = 0; k < count; ++k, ++x) std::memcpy(out + 4 * x, out + 4 * (x - 1), 4);
      shift += 8;
    } else {
      std::memcpy(out + 4 * x++, p, 4);
      shift = 0;
    }
  }
  return nullptr;
}

}  // namespace

bool looks_like_rgbe(const std::string& b) {
  return b.compare(0, 10, "#?RADIANCE") == 0 || b.compare(0, 6, "#?RGBE") == 0;
}

Result<std::shared_ptr<const Image>> decode_rgbe(const std::string& b, const std::string& path) {
  if (!looks_like_rgbe(b)) return file_error(path, "not a Radiance HDR file (no #?RADIANCE line)");
  size_t pos = 0;
  std::string line;
  double exposure = 1.0;
  bool header_ended = false;
  next_line(b, pos, line);  // the program line
  while (next_line(b, pos, line)) {
    if (line.empty()) {
      header_ended = true;
      break;
    }
    if (line.rfind("FORMAT=", 0) == 0 && line != "FORMAT=32-bit_rle_rgbe")
      return file_error(path, "unsupported Radiance pixel format '" + line.substr(7) + "' (expected 32-bit_rle_rgbe)");
    if (line.rfind("EXPOSURE=", 0) == 0) {
      char* end = nullptr;
      const double e = std::strtod(line.c_str() + 9, &end);
      if (end == line.c_str() + 9 || !std::isfinite(e) || e <= 0.0)
        return file_error(path, "EXPOSURE is not a positive number: '" + line.substr(9) + "'");
      exposure *= e;  // pixels were multiplied by each exposure: divide them all out
    }
  }
  if (!header_ended) return file_error(path, "the Radiance header has no end (no blank line)");
  if (!next_line(b, pos, line)) return file_error(path, "the resolution line is missing");
  // "-Y height +X width" (top row first) or "+Y height +X width" (bottom row first).
  const char* s = line.c_str();
  long h = 0, w = 0;
  const bool y_down = std::strncmp(s, "-Y ", 3) == 0, y_up = std::strncmp(s, "+Y ", 3) == 0;
  const char* rest = s + 3;
  if ((!y_down && !y_up) || !parse_side(rest, &rest, h) || std::strncmp(rest, " +X ", 4) != 0 ||
      !parse_side(rest + 4, &rest, w) || *rest != '\0')
    return file_error(path, "unsupported resolution line '" + line + "' (expected -Y H +X W or +Y H +X W)");
  if (uint64_t(w) * uint64_t(h) > kMaxTexturePixels)
    return file_error(path, "image is " + std::to_string(w) + "x" + std::to_string(h) +
                          ", larger than the 8192x8192 texture limit");
  // Every scanline takes at least 4 bytes: a shorter file cannot hold the image.
  if (b.size() - pos < uint64_t(h) * 4)
    return file_error(path, "the file is truncated (too short for " + std::to_string(w) + "x" + std::to_string(h) + ")");
  try {
    auto image = std::make_shared<Image>();
    image->path = path;
    image->width = int(w);
    image->height = int(h);
    image->channels = 3;
    image->hdr.assign(size_t(w) * size_t(h) * 3, 0.0f);
    std::vector<uint8_t> rgbe(size_t(w) * 4);
    for (long y = 0; y < h; ++y) {
      if (const char* what = read_scanline(b, pos, int(w), rgbe.data()))
        return file_error(path, std::string(what) + " at scanline " + std::to_string(y));
      float* row = image->hdr.data() + size_t(y_down ? y : h - 1 - y) * size_t(w) * 3;
      for (long x = 0; x < w; ++x) {
        const uint8_t* p = rgbe.data() + 4 * x;
        if (p[3] == 0) continue;  // exponent 0: black
        const double scale = std::ldexp(1.0, int(p[3]) - 136) / exposure;
        for (int c = 0; c < 3; ++c) row[3 * x + c] = float((p[c] + 0.5) * scale);
      }
    }
    return std::shared_ptr<const Image>(std::move(image));
  } catch (const std::bad_alloc&) {
    return file_error(path, "out of memory");
  }
}

}  // namespace frameless
