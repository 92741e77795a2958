// Textures (image and procedural solid), read-only after load and sampled from any thread.
// Image texels are decoded once per file (core/io/image_io.h) and shared by every material that
// names the file.
#pragma once
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include <glm/mat4x4.hpp>

#include "core/base/types.h"

namespace frameless {

inline constexpr uint32_t kNoTexture = 0xffffffffu;

// Decoded image: 8-bit texels as stored in the file (PNG, JPEG) or 32-bit float (OpenEXR);
// 1..4 channels interleaved, rows top to bottom (row 0 is v = 1 in texture space).
struct Image {
  std::string path;
  int width = 0;
  int height = 0;
  int channels = 0;             // 1 grey, 2 grey+alpha, 3 RGB, 4 RGBA
  std::vector<uint8_t> ldr;     // width*height*channels bytes (PNG/JPEG), or empty
  std::vector<float> hdr;       // width*height*channels floats (EXR), or empty
  bool has_alpha() const { return channels == 2 || channels == 4; }
};

enum class TextureKind : uint8_t { kImage, kChecker, kNoise, kTurbulence, kMarble, kWood };
enum class TextureWrap : uint8_t { kRepeat, kClamp };

// One use of an image, or one procedural solid texture, with its parameters.
struct Texture {
  TextureKind kind = TextureKind::kImage;
  // Image: texels, wrap mode, whether the 8-bit texels are sRGB-encoded colour (decoded to
  // linear) or linear data (alpha, normal and bump maps), and the UV transform uv' = uv*scale+offset.
  std::shared_ptr<const Image> image;
  TextureWrap wrap = TextureWrap::kRepeat;
  bool srgb = true;
  Vec2 uv_scale{1.0f};
  Vec2 uv_offset{0.0f};
  // Solid textures: evaluated at to_texture * p (world point; object space bakes the object's
  // inverse transform in), blending color_a and color_b.
  glm::mat4 to_texture{1.0f};
  Vec3 color_a{0.9f};
  Vec3 color_b{0.1f};
  float frequency = 1.0f;    // noise/checker cells per unit of texture space
  int octaves = 6;           // turbulence, marble, wood
  float amplitude = 5.0f;    // marble: turbulence weight in the sine; wood: ring distortion
};

// Where a texture is looked up: surface UV and world position of the shading point.
struct TexturePoint {
  Vec2 uv{0.0f};
  Vec3 p{0.0f};
};

// RGBA in linear units (alpha 1 when the image has none); bilinear for images. Never NaN/Inf:
// non-finite EXR texels read as 0.
Vec4 sample_texture(const Texture& tex, const TexturePoint& at);

// Perlin's improved noise (2002) in [-1, 1] and turbulence sum |noise| over octaves.
float perlin_noise(const Vec3& p);
// An sRGB-encoded byte as a linear value (IEC 61966-2-1; the table image textures use).
float srgb8_to_linear(uint8_t b);
float turbulence(const Vec3& p, int octaves);

}  // namespace frameless
