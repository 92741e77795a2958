// Texture sampling (bilinear images, procedural solids) and Perlin's improved noise. Called per
// shading hit from every render thread: no allocation, no locks, nothing mutable.
#include "core/scene/texture.h"

#include <algorithm>
#include <array>
#include <cmath>

namespace frameless {
namespace {

// Ken Perlin's reference permutation of 0..255 ("Improving Noise", SIGGRAPH 2002).
constexpr std::array<uint8_t, 256> kPermutation = {
    151, 160, 137, 91,  90,  15,  131, 13,  201, 95,  96,  53,  194, 233, 7,   225, 140, 36,
    103, 30,  69,  142, 8,   99,  37,  240, 21,  10,  23,  190, 6,   148, 247, 120, 234, 75,
    0,   26,  197, 62,  94,  252, 219, 203, 117, 35,  11,  32,  57,  177, 33,  88,  237, 149,
    56,  87,  174, 20,  125, 136, 171, 168, 68,  175, 74,  165, 71,  134, 139, 48,  27,  166,
    77,  146, 158, 231, 83,  111, 229, 122, 60,  211, 133, 230, 220, 105, 92,  41,  55,  46,
    245, 40,  244, 102, 143, 54,  65,  25,  63,  161, 1,   216, 80,  73,  209, 76,  132, 187,
    208, 89,  18,  169, 200, 196, 135, 130, 116, 188, 159, 86,  164, 100, 109, 198, 173, 186,
    3,   64,  52,  217, 226, 250, 124, 123, 5,   202, 38,  147, 118, 126, 255, 82,  85,  212,
    207, 206, 59,  227, 47,  16,  58,  17,  182, 189, 28,  42,  223, 183, 170, 213, 119, 248,
    152, 2,   44,  154, 163, 70,  221, 153, 101, 155, 167, 43,  172, 9,   129, 22,  39,  253,
    19,  98,  108, 110, 79,  113, 224, 232, 178, 185, 112, 104, 218, 246, 97,  228, 251, 34,
    242, 193, 238, 210, 144, 12,  191, 179, 162, 241, 81,  51,  145, 235, 249, 14,  239, 107,
    49,  192, 214, 31,  181, 199, 106, 157, 184, 84,  204, 176, 115, 121, 50,  45,  127, 4,
    150, 254, 138, 236, 205, 93,  222, 114, 67,  29,  24,  72,  243, 141, 128, 195, 78,  66,
    215, 61,  156, 180};

// A mistyped entry would repeat a value: check at compile time that it is a permutation.
constexpr bool is_permutation_of_bytes() {
  std::array<bool, 256> seen{};
  for (uint8_t v : kPermutation) {
    if (seen[v]) return false;
    seen[v] = true;
  }
  return true;
}
static_assert(is_permutation_of_bytes());

// Doubled so that p[p[x] + y] never needs a wrap (indices reach 511).
constexpr std::array<uint8_t, 512> kPerm = [] {
  std::array<uint8_t, 512> p{};
  for (int i = 0; i < 512; ++i) p[size_t(i)] = kPermutation[size_t(i & 255)];
  return p;
}();

inline float fade(float t) { return t * t * t * (t * (t * 6.0f - 15.0f) + 10.0f); }

inline float lerp(float t, float a, float b) { return a + t * (b - a); }

// Dot product with one of the 12 cube-edge directions (1,1,0)...(0,-1,-1) picked by the low four
// hash bits; 16 codes for 12 directions, so four of them appear twice.
inline float grad(int hash, float x, float y, float z) {
  const int h = hash & 15;
  const float u = h < 8 ? x : y;
  const float v = h < 4 ? y : (h == 12 || h == 14 ? x : z);
  return ((h & 1) ? -u : u) + ((h & 2) ? -v : v);
}

// Splits c into a lattice cell in [0, 255] and the offset in it. Noise has period 256, so the
// reduction (exact in float) keeps huge coordinates from overflowing an int.
inline int lattice(float& c) {
  c -= 256.0f * std::floor(c * (1.0f / 256.0f));
  const float f = std::floor(c);
  c -= f;
  return int(f) & 255;
}

// sRGB-encoded byte to linear, IEC 61966-2-1.
const std::array<float, 256> kSrgbToLinear = [] {
  std::array<float, 256> t{};
  for (int i = 0; i < 256; ++i) {
    const double c = i / 255.0;
    t[size_t(i)] = float(c <= 0.04045 ? c / 12.92 : std::pow((c + 0.055) / 1.055, 2.4));
  }
  return t;
}();

inline Vec4 texel(const Image& img, int x, int y, bool srgb) {
  const size_t i = (size_t(y) * size_t(img.width) + size_t(x)) * size_t(img.channels);
  float c[4];
  if (!img.hdr.empty()) {
    for (int k = 0; k < img.channels; ++k) c[k] = img.hdr[i + size_t(k)];
  } else {
    const uint8_t* b = img.ldr.data() + i;
    const bool has_alpha = img.has_alpha();
    const int colour = has_alpha ? img.channels - 1 : img.channels;
    for (int k = 0; k < colour; ++k) c[k] = srgb ? kSrgbToLinear[b[k]] : b[k] * (1.0f / 255.0f);
    if (has_alpha) c[colour] = b[colour] * (1.0f / 255.0f);  // alpha is always linear
  }
  switch (img.channels) {
    case 1: return Vec4(c[0], c[0], c[0], 1.0f);
    case 2: return Vec4(c[0], c[0], c[0], c[1]);
    case 3: return Vec4(c[0], c[1], c[2], 1.0f);
    default: return Vec4(c[0], c[1], c[2], c[3]);
  }
}

// Texel coordinate t (texel centres at integers) of a texture coordinate s over n texels, as the
// two neighbours and the weight of the second.
struct Taps {
  int i0, i1;
  float w1;
};

inline Taps repeat_taps(float s, int n) {
  s -= std::floor(s);  // fractional part, in [0, 1] (1 only by rounding of tiny negatives)
  const float t = s * float(n) - 0.5f;
  const float f = std::floor(t);
  int i0 = int(f);  // in [-1, n - 1]
  int i1 = i0 + 1;
  if (i0 < 0) i0 = n - 1;
  if (i1 >= n) i1 = 0;
  return {i0, i1, t - f};
}

inline Taps clamp_taps(float s, int n) {
  const float t = std::clamp(std::clamp(s, 0.0f, 1.0f) * float(n) - 0.5f, 0.0f, float(n - 1));
  const float f = std::floor(t);
  const int i0 = int(f);
  return {i0, std::min(i0 + 1, n - 1), t - f};
}

Vec4 sample_image(const Texture& tex, const Vec2& uv) {
  const Image* img = tex.image.get();
  if (!img || img->width <= 0 || img->height <= 0) return Vec4(0.0f, 0.0f, 0.0f, 1.0f);
  Vec2 st = uv * tex.uv_scale + tex.uv_offset;
  if (!std::isfinite(st.x)) st.x = 0.0f;
  if (!std::isfinite(st.y)) st.y = 0.0f;
  // Row 0 is v = 1 (OBJ convention), so rows count down from the top: s = 1 - v.
  Taps tx, ty;
  if (tex.wrap == TextureWrap::kRepeat) {
    tx = repeat_taps(st.x, img->width);
    ty = repeat_taps(-st.y, img->height);  // 1 - v, modulo 1
  } else {
    tx = clamp_taps(st.x, img->width);
    ty = clamp_taps(1.0f - st.y, img->height);
  }
  const Vec4 a = texel(*img, tx.i0, ty.i0, tex.srgb), b = texel(*img, tx.i1, ty.i0, tex.srgb);
  const Vec4 c = texel(*img, tx.i0, ty.i1, tex.srgb), d = texel(*img, tx.i1, ty.i1, tex.srgb);
  const Vec4 top = a + (b - a) * tx.w1, bottom = c + (d - c) * tx.w1;
  return top + (bottom - top) * ty.w1;
}

// Parity of floor(c) without an int conversion (safe for any magnitude); 0 for non-finite c.
inline int floor_parity(float c) {
  if (!std::isfinite(c)) return 0;
  const float f = std::floor(c);
  return f - 2.0f * std::floor(f * 0.5f) != 0.0f ? 1 : 0;
}

inline Vec4 blend(const Texture& tex, float t) {
  t = std::isfinite(t) ? std::clamp(t, 0.0f, 1.0f) : 0.0f;
  return Vec4(tex.color_b + (tex.color_a - tex.color_b) * t, 1.0f);
}

}  // namespace

float perlin_noise(const Vec3& p) {
  if (!std::isfinite(p.x) || !std::isfinite(p.y) || !std::isfinite(p.z)) return 0.0f;
  float x = p.x, y = p.y, z = p.z;
  const int X = lattice(x), Y = lattice(y), Z = lattice(z);
  const float u = fade(x), v = fade(y), w = fade(z);
  const int A = kPerm[size_t(X)] + Y, AA = kPerm[size_t(A)] + Z, AB = kPerm[size_t(A + 1)] + Z;
  const int B = kPerm[size_t(X + 1)] + Y, BA = kPerm[size_t(B)] + Z,
            BB = kPerm[size_t(B + 1)] + Z;
  const float n =
      lerp(w,
           lerp(v, lerp(u, grad(kPerm[size_t(AA)], x, y, z), grad(kPerm[size_t(BA)], x - 1, y, z)),
                lerp(u, grad(kPerm[size_t(AB)], x, y - 1, z),
                     grad(kPerm[size_t(BB)], x - 1, y - 1, z))),
           lerp(v,
                lerp(u, grad(kPerm[size_t(AA + 1)], x, y, z - 1),
                     grad(kPerm[size_t(BA + 1)], x - 1, y, z - 1)),
                lerp(u, grad(kPerm[size_t(AB + 1)], x, y - 1, z - 1),
                     grad(kPerm[size_t(BB + 1)], x - 1, y - 1, z - 1))));
  return std::clamp(n, -1.0f, 1.0f);  // peaks reach about 1.001: keep the documented range
}

float turbulence(const Vec3& p, int octaves) {
  float sum = 0.0f, scale = 1.0f;
  for (int i = 0; i < octaves; ++i, scale *= 2.0f) sum += std::abs(perlin_noise(p * scale)) / scale;
  return sum;
}

Vec4 sample_texture(const Texture& tex, const TexturePoint& at) {
  if (tex.kind == TextureKind::kImage) return sample_image(tex, at.uv);
  const Vec3 q = Vec3(tex.to_texture * Vec4(at.p, 1.0f)) * tex.frequency;
  switch (tex.kind) {
    case TextureKind::kChecker: {
      const int parity = floor_parity(q.x) ^ floor_parity(q.y) ^ floor_parity(q.z);
      return Vec4(parity ? tex.color_b : tex.color_a, 1.0f);
    }
    case TextureKind::kNoise: return blend(tex, 0.5f * (perlin_noise(q) + 1.0f));
    case TextureKind::kTurbulence: return blend(tex, turbulence(q, tex.octaves));
    case TextureKind::kMarble:
      return blend(tex, 0.5f * (1.0f + std::sin(q.x + tex.amplitude * turbulence(q, tex.octaves))));
    case TextureKind::kWood: {
      const float r = std::sqrt(q.x * q.x + q.z * q.z) + tex.amplitude * 0.1f * perlin_noise(q);
      // Smooth periodic ring profile: colour a at the ring centre, b between rings.
      const float t = r - std::floor(r);
      return blend(tex, 0.5f + 0.5f * std::cos(2.0f * kPi * t));
    }
    default: return Vec4(0.0f, 0.0f, 0.0f, 1.0f);
  }
}

float srgb8_to_linear(uint8_t b) { return kSrgbToLinear[b]; }

}  // namespace frameless
