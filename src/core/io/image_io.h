// Image files for textures: PNG, JPEG, OpenEXR and Radiance HDR decoded into core/scene/texture.h's Image, and
// the cache that shares them between materials (loading thread).
#pragma once
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include "core/base/error.h"
#include "core/scene/texture.h"

namespace frameless {

// Decodes a PNG, JPEG, OpenEXR or Radiance HDR file (by content, not extension). Refuses images larger than
// kMaxTexturePixels before allocating. Errors name the file and what is wrong, on one line.
inline constexpr uint64_t kMaxTexturePixels = uint64_t(1) << 26;  // 64 Mpixel (8192 x 8192)
Result<std::shared_ptr<const Image>> load_image(const std::string& path);
Result<std::shared_ptr<const Image>> decode_image(const std::string& bytes, const std::string& path);

// Shares decoded images between materials by canonical path (loading thread only).
class ImageCache {
 public:
  Result<std::shared_ptr<const Image>> get(const std::string& path);
  size_t size() const { return images_.size(); }

 private:
  std::vector<std::pair<std::string, std::shared_ptr<const Image>>> images_;
};

}  // namespace frameless
