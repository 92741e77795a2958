// An image-based environment (settings.environment): an equirectangular radiance map seen by rays
// that escape, and importance-sampled by the path tracer (luminance x sin(theta), piecewise
// constant per texel). Built on the loading thread; read-only while rendering (any thread).
#pragma once
#include <memory>
#include <string>
#include <vector>

#include "core/base/error.h"
#include "core/base/types.h"
#include "core/scene/texture.h"

namespace frameless {

// Row 0 looks straight up (+y); u runs around the y axis, starting at -z and turning towards +x,
// plus `rotate`.
class EnvironmentMap {
 public:
  // Largest map accepted: its sampling tables cost 24 bytes per texel.
  static constexpr int kMaxWidth = 16384, kMaxHeight = 8192;
  // From a decoded image (EXR linear, PNG/JPEG sRGB-decoded), rotated about +y by rotate
  // radians and scaled by scale; an error when a texel is negative or not finite.
  static Result<std::shared_ptr<const EnvironmentMap>> make(const Image& image, float rotate, float scale);

  int width() const { return width_; }
  int height() const { return height_; }
  // Radiance arriving from unit direction d (the texel it falls in).
  Vec3 radiance(const Vec3& d) const;
  // A direction from two uniform numbers with its density per solid angle; false for a black map.
  bool sample(float u1, float u2, Vec3& d, float& pdf) const;
  // The density sample() has at unit direction d.
  float pdf(const Vec3& d) const;
  bool black() const { return total_ <= 0.0; }

 private:
  int width_ = 0, height_ = 0;
  float rotate_ = 0.0f;
  std::vector<Vec3> texels_;    // linear radiance times scale, row-major
  std::vector<float> row_cdf_;  // over rows, weights sum of luminance x sin(theta)
  std::vector<float> col_cdf_;  // per row over its columns (uniform for a black row)
  std::vector<float> weight_;   // per texel: luminance x sin(theta) / total
  double total_ = 0.0;
  void uv(const Vec3& d, float& u, float& v) const;
};

// What an escaping ray brings: the map's radiance, or the constant background without one.
inline Vec3 escaped_radiance(const EnvironmentMap* env, const Vec3& background, const Vec3& d) {
  return env ? env->radiance(d) : background;
}

}  // namespace frameless
