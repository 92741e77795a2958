// Reading and writing the light slab's EXR mosaic and its header attributes.
#include "core/io/lightfield_file.h"

#include <cmath>
#include <filesystem>
#include <new>
#include <system_error>

#include <ImathBox.h>
#include <ImfChannelList.h>
#include <ImfFrameBuffer.h>
#include <ImfHeader.h>
#include <ImfInputFile.h>
#include <ImfIntAttribute.h>
#include <ImfMatrixAttribute.h>
#include <ImfOutputFile.h>
#include <ImfStringAttribute.h>
#include <ImfVecAttribute.h>

#include "core/io/exr_stream.h"
#include "core/io/file_util.h"

namespace frameless {
namespace {

template <class A>
const A* attribute(const Imf::Header& h, const char* name) {
  return h.findTypedAttribute<A>(name);
}

}  // namespace

Result<std::shared_ptr<const LightField>> decode_lightfield(const std::string& bytes, const std::string& path) {
  auto lf = std::make_shared<LightField>();
  lf->source = path;
  try {
    ExrMemoryStream stream(bytes, path);
    {  // the header alone first: sizes are checked before the library sizes its tables
      if (bytes.size() < 8 || bytes.compare(0, 4, "\x76\x2f\x31\x01") != 0)
        return file_error(path, "not an OpenEXR file (a lightfield is an EXR mosaic; docs/lightfields.md)");
      if (const std::string p = exr_header_problem(bytes); !p.empty()) return file_error(path, p);
      Imf::Header header;
      int version = int(uint8_t(bytes[4])) | int(uint8_t(bytes[5])) << 8 | int(uint8_t(bytes[6])) << 16 |
                          int(uint8_t(bytes[7])) << 24;
      stream.seekg(8);
      header.readFrom(stream, version);
      const Imath::Box2i dw = header.dataWindow();
      const int64_t w = int64_t(dw.max.x) - dw.min.x + 1, ht = int64_t(dw.max.y) - dw.min.y + 1;
      if (w <= 0 || ht <= 0 || uint64_t(w) * uint64_t(ht) > (uint64_t(1) << 31))
        return file_error(path, "image of " + std::to_string(w) + "x" + std::to_string(ht) + " texels is empty or larger than 2^31");
      if (const std::string p = exr_chunk_problem(header); !p.empty()) return file_error(path, p);
      stream.seekg(0);
    }
    Imf::InputFile file(stream);
    const Imf::Header& h = file.header();
    const auto* version = attribute<Imf::IntAttribute>(h, "frameless:lightfield");
    if (!version) return file_error(path, "not a lightfield (an EXR without the frameless:lightfield attribute)");
    if (version->value() != kLightfieldFormatVersion)
      return file_error(path, "lightfield format version " + std::to_string(version->value()) + " (this frameless reads " +
                            std::to_string(kLightfieldFormatVersion) + ")");
    const auto* uv = attribute<Imf::V2iAttribute>(h, "frameless:uv");
    const auto* st = attribute<Imf::V2iAttribute>(h, "frameless:st");
    const auto* slab = attribute<Imf::M44fAttribute>(h, "frameless:slab");
    if (!uv || !st || !slab) return file_error(path, "lightfield header needs frameless:uv, frameless:st (V2i) and frameless:slab (M44f)");
    const Imath::V2i u = uv->value(), s = st->value();
    if (u.x < 1 || u.y < 1 || s.x < 1 || s.y < 1 || u.x > 1024 || u.y > 1024 || s.x > 8192 || s.y > 8192)
      return file_error(path, "frameless:uv " + std::to_string(u.x) + "x" + std::to_string(u.y) + " / frameless:st " +
                            std::to_string(s.x) + "x" + std::to_string(s.y) + " out of range (uv 1-1024, st 1-8192)");
    lf->nu = uint32_t(u.x), lf->nv = uint32_t(u.y), lf->ns = uint32_t(s.x), lf->nt = uint32_t(s.y);
    const Imath::Box2i dw = h.dataWindow();
    const int64_t w = int64_t(dw.max.x) - dw.min.x + 1, ht = int64_t(dw.max.y) - dw.min.y + 1;
    if (w != int64_t(lf->width()) || ht != int64_t(lf->height()))
      return file_error(path, "image is " + std::to_string(w) + "x" + std::to_string(ht) + " but uv x st makes " +
                            std::to_string(lf->width()) + "x" + std::to_string(lf->height()));
    const Imf::ChannelList& list = h.channels();
    for (const char* c : {"R", "G", "B", "A"}) {
      const Imf::Channel* ch = list.findChannel(c);
      if (!ch) return file_error(path, std::string("lightfield has no ") + c + " channel");
      if (ch->xSampling != 1 || ch->ySampling != 1) return file_error(path, std::string("channel ") + c + " is subsampled");
    }
    if (!file.isComplete()) return file_error(path, "file is truncated");
    const Imath::M44f& m = slab->value();  // row-vector convention: p' = p * m
    for (int r = 0; r < 3; ++r)
      for (int c = 0; c < 3; ++c) lf->slab_to_model.m[r][c] = m[r][c];
    lf->slab_to_model.t = Vec3(m[3][0], m[3][1], m[3][2]);
    if (m[0][3] != 0.0f || m[1][3] != 0.0f || m[2][3] != 0.0f || m[3][3] != 1.0f)
      return file_error(path, "frameless:slab must be affine (last column 0 0 0 1)");
    if (const auto* scene = attribute<Imf::StringAttribute>(h, "frameless:scene")) lf->source = path + " (" + scene->value() + ")";
    lf->rgba.assign(size_t(w) * size_t(ht) * 4, 0);
    Imf::FrameBuffer fb;
    const char* names[4] = {"R", "G", "B", "A"};
    for (int k = 0; k < 4; ++k)
      fb.insert(names[k], Imf::Slice::Make(Imf::HALF, lf->rgba.data() + k, dw, 4 * sizeof(uint16_t),
                                           4 * sizeof(uint16_t) * size_t(w)));
    file.setFrameBuffer(fb);
    file.readPixels(dw.min.y, dw.max.y);
  } catch (const std::bad_alloc&) {
    return file_error(path, "out of memory");
  } catch (const std::exception& e) {
    return file_error(path, std::string("invalid lightfield EXR: ") + e.what());
  } catch (...) {
    return file_error(path, "invalid lightfield EXR");
  }
  const std::string problem = check_lightfield(*lf);
  if (!problem.empty()) return file_error(path, problem);
  return std::shared_ptr<const LightField>(std::move(lf));
}

Result<std::shared_ptr<const LightField>> load_lightfield(const std::string& path) {
  Result<std::string> bytes = read_file_bytes(path);
  if (!bytes) return bytes.error();
  return decode_lightfield(*bytes, path);
}

Result<bool> write_lightfield(const std::string& path, const LightField& lf) {
  const std::string problem = check_lightfield(lf);
  if (!problem.empty()) return file_error(path, problem);
  const std::string tmp = path + ".tmp";
  try {
    Imf::Header h(int(lf.width()), int(lf.height()));
    h.compression() = Imf::ZIP_COMPRESSION;
    for (const char* c : {"R", "G", "B", "A"}) h.channels().insert(c, Imf::Channel(Imf::HALF));
    h.insert("frameless:lightfield", Imf::IntAttribute(kLightfieldFormatVersion));
    h.insert("frameless:uv", Imf::V2iAttribute(Imath::V2i(int(lf.nu), int(lf.nv))));
    h.insert("frameless:st", Imf::V2iAttribute(Imath::V2i(int(lf.ns), int(lf.nt))));
    Imath::M44f m;  // identity; row-vector convention
    for (int r = 0; r < 3; ++r)
      for (int c = 0; c < 3; ++c) m[r][c] = lf.slab_to_model.m[r][c];
    m[3][0] = lf.slab_to_model.t.x, m[3][1] = lf.slab_to_model.t.y, m[3][2] = lf.slab_to_model.t.z;
    h.insert("frameless:slab", Imf::M44fAttribute(m));
    h.insert("frameless:scene", Imf::StringAttribute(lf.source));
    Imf::OutputFile file(tmp.c_str(), h);
    Imf::FrameBuffer fb;
    const char* names[4] = {"R", "G", "B", "A"};
    const size_t w = lf.width();
    for (int k = 0; k < 4; ++k)
      fb.insert(names[k], Imf::Slice(Imf::HALF, (char*)(lf.rgba.data() + k), 4 * sizeof(uint16_t), 4 * sizeof(uint16_t) * w));
    file.setFrameBuffer(fb);
    file.writePixels(int(lf.height()));
  } catch (const std::exception& e) {
    std::error_code ec;
    std::filesystem::remove(tmp, ec);
    return file_error(path, std::string("cannot write: ") + e.what());
  }
  std::error_code ec;
  std::filesystem::rename(tmp, path, ec);
  if (ec) {
    std::filesystem::remove(tmp, ec);
    return file_error(path, "cannot write: " + ec.message());
  }
  return true;
}

}  // namespace frameless
