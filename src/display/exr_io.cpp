#include "display/exr_io.h"

#include <ImfChannelList.h>
#include <ImfDoubleAttribute.h>
#include <ImfFloatAttribute.h>
#include <ImfFrameBuffer.h>
#include <ImfHeader.h>
#include <ImfInputFile.h>
#include <ImfIntAttribute.h>
#include <ImfMatrixAttribute.h>
#include <ImfOutputFile.h>
#include <ImfStandardAttributes.h>
#include <ImfStringAttribute.h>

#include <cstdio>

#include "display/atomic_file.h"

namespace frameless {

Result<bool> write_exr(const std::string& path, int width, int height,
                       const std::vector<ExrChannel>& channels, const ExrAttributes& attrs) {
  if (width <= 0 || height <= 0) return Error{path + ": cannot write an empty image"};
  const std::string tmp = temporary_path_for(path);
  try {
    Imf::Header header(width, height);
    header.compression() = Imf::ZIP_COMPRESSION;
    // zlib level 1: a wall-clock capture on 2 cores kept 67-74 of 90 ticks instead of 53-58
    // (zlib was a quarter of the capture's CPU), for files about a third larger.
    header.zipCompressionLevel() = 1;
    for (const auto& [k, v] : attrs.strings) header.insert(k, Imf::StringAttribute(v));
    for (const auto& [k, v] : attrs.floats) header.insert(k, Imf::FloatAttribute(v));
    for (const auto& [k, v] : attrs.doubles) header.insert(k, Imf::DoubleAttribute(v));
    for (const auto& [k, v] : attrs.ints) header.insert(k, Imf::IntAttribute(v));
    if (attrs.frames_per_second)
      Imf::addFramesPerSecond(header, Imf::Rational(*attrs.frames_per_second));
    if (attrs.cap_date) Imf::addCapDate(header, *attrs.cap_date);
    if (attrs.world_to_camera && attrs.world_to_camera->size() == 16) {
      const std::vector<float>& m = *attrs.world_to_camera;
      Imf::addWorldToCamera(header, Imath::M44f(m[0], m[1], m[2], m[3], m[4], m[5], m[6], m[7],
                                                m[8], m[9], m[10], m[11], m[12], m[13], m[14],
                                                m[15]));
    }
    Imf::FrameBuffer fb;
    // OutputFile does not convert pixel types: half channels get a half copy of their plane.
    std::vector<std::vector<half>> half_planes;
    half_planes.reserve(channels.size());
    for (const ExrChannel& c : channels) {
      header.channels().insert(c.name, Imf::Channel(c.half ? Imf::HALF : Imf::FLOAT));
      if (c.half) {
        auto& plane = half_planes.emplace_back(size_t(width) * size_t(height));
        for (size_t i = 0; i < plane.size(); ++i) plane[i] = half(c.data[i * c.stride]);
        fb.insert(c.name, Imf::Slice(Imf::HALF, (char*)plane.data(), sizeof(half),
                                     sizeof(half) * size_t(width)));
      } else {
        fb.insert(c.name, Imf::Slice(Imf::FLOAT, (char*)c.data, sizeof(float) * c.stride,
                                     sizeof(float) * c.stride * size_t(width)));
      }
    }
    {
      Imf::OutputFile file(tmp.c_str(), header, 1);
      file.setFrameBuffer(fb);
      file.writePixels(height);
    }
  } catch (const std::exception& e) {
    std::remove(tmp.c_str());
    return Error{path + ": cannot write EXR: " + e.what()};
  }
  std::string err;
  if (!commit_temporary(tmp, path, err)) return Error{err};
  return true;
}

Result<ExrImage> read_exr(const std::string& path) {
  try {
    Imf::InputFile file(path.c_str(), 1);
    const Imf::Header& h = file.header();
    const Imath::Box2i dw = h.dataWindow();
    ExrImage img;
    img.width = dw.max.x - dw.min.x + 1;
    img.height = dw.max.y - dw.min.y + 1;
    Imf::FrameBuffer fb;
    for (auto it = h.channels().begin(); it != h.channels().end(); ++it) {
      auto& plane = img.channels[it.name()];
      plane.assign(size_t(img.width) * img.height, 0.0f);
      if (it.channel().type == Imf::HALF) img.half_channels[it.name()] = "half";
      char* base = (char*)(plane.data() - dw.min.x - size_t(dw.min.y) * img.width);
      fb.insert(it.name(), Imf::Slice(Imf::FLOAT, base, sizeof(float), sizeof(float) * img.width));
    }
    file.setFrameBuffer(fb);
    file.readPixels(dw.min.y, dw.max.y);
    for (auto it = h.begin(); it != h.end(); ++it) {
      const std::string name = it.name();
      if (auto* s = dynamic_cast<const Imf::StringAttribute*>(&it.attribute()))
        name == "capDate" ? void(img.attributes.cap_date = s->value())
                          : void(img.attributes.strings[name] = s->value());
      else if (auto* f = dynamic_cast<const Imf::FloatAttribute*>(&it.attribute()))
        img.attributes.floats[name] = f->value();
      else if (auto* d = dynamic_cast<const Imf::DoubleAttribute*>(&it.attribute()))
        img.attributes.doubles[name] = d->value();
      else if (auto* i = dynamic_cast<const Imf::IntAttribute*>(&it.attribute()))
        img.attributes.ints[name] = i->value();
      else if (auto* m = dynamic_cast<const Imf::M44fAttribute*>(&it.attribute())) {
        std::vector<float> v(16);
        for (int r = 0; r < 4; ++r)
          for (int c = 0; c < 4; ++c) v[r * 4 + c] = m->value()[r][c];
        if (name == "worldToCamera") img.attributes.world_to_camera = v;
      }
    }
    if (Imf::hasFramesPerSecond(h)) {
      const Imf::Rational& r = Imf::framesPerSecond(h);
      img.attributes.frames_per_second = double(r);
    }
    return img;
  } catch (const std::exception& e) {
    return Error{path + ": cannot read EXR: " + e.what()};
  }
}

}  // namespace frameless
