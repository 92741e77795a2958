// The equirectangular environment: texel lookup, and sampling by a marginal distribution over rows
// and a conditional one over each row's columns (texels weighted by luminance x sin(theta)).
#include "core/scene/environment.h"

#include <algorithm>
#include <cmath>

namespace frameless {
namespace {

inline float luminance(const Vec3& c) { return 0.2126f * c.x + 0.7152f * c.y + 0.0722f * c.z; }

// Index i with cdf[i-1] <= u < cdf[i] (cdf[-1] = 0) among n entries, and u's place inside it.
int pick(const float* cdf, int n, float u, float& frac) {
  const int i = int(std::min<ptrdiff_t>(std::upper_bound(cdf, cdf + n, u) - cdf, n - 1));
  const float lo = i > 0 ? cdf[i - 1] : 0.0f, hi = cdf[i];
  frac = hi > lo ? std::clamp((u - lo) / (hi - lo), 0.0f, 0x1.fffffep-1f) : 0.5f;
  return i;
}

}  // namespace

Result<std::shared_ptr<const EnvironmentMap>> EnvironmentMap::make(const Image& image, float rotate,
                                                                     float scale) {
  auto env = std::make_shared<EnvironmentMap>();
  const int w = image.width, h = image.height;
  if (w < 1 || h < 1 || image.channels < 1) return Error{image.path + ": empty environment image"};
  if (w > kMaxWidth || h > kMaxHeight)
    return Error{image.path + ": " + std::to_string(w) + "x" + std::to_string(h) +
                 " is too large for an environment map (at most " + std::to_string(kMaxWidth) + "x" +
                 std::to_string(kMaxHeight) + ")"};
  env->width_ = w;
  env->height_ = h;
  env->rotate_ = rotate;
  env->texels_.resize(size_t(w) * size_t(h));
  const int colour = image.has_alpha() ? image.channels - 1 : image.channels;
  for (size_t i = 0; i < env->texels_.size(); ++i) {
    float c[3];
    for (int k = 0; k < 3; ++k) {
      const size_t at = i * size_t(image.channels) + size_t(std::min(k, colour - 1));
      c[k] = !image.hdr.empty() ? image.hdr[at] : srgb8_to_linear(image.ldr[at]);
      if (!std::isfinite(c[k]) || c[k] < 0.0f)
        return Error{image.path + ": texel " + std::to_string(i % size_t(w)) + "," +
                     std::to_string(i / size_t(w)) + " is " + (std::isfinite(c[k]) ? "negative" : "not finite") +
                     " (an environment holds radiance >= 0)"};
    }
    env->texels_[i] = Vec3(c[0], c[1], c[2]) * scale;
  }
  env->weight_.resize(env->texels_.size());
  env->row_cdf_.resize(size_t(h));
  env->col_cdf_.resize(env->texels_.size());
  std::vector<double> row(size_t(h), 0.0);
  for (int y = 0; y < h; ++y) {
    const double sin_t = std::sin(kPi * (double(y) + 0.5) / double(h));
    double run = 0.0;
    for (int x = 0; x < w; ++x) {
      const size_t i = size_t(y) * size_t(w) + size_t(x);
      const double wt = double(luminance(env->texels_[i])) * sin_t;
      env->weight_[i] = float(wt);
      run += wt;
      env->col_cdf_[i] = float(run);
    }
    for (int x = 0; x < w; ++x) {  // normalise the row (uniform when it is black)
      float& c = env->col_cdf_[size_t(y) * size_t(w) + size_t(x)];
      c = run > 0.0 ? float(double(c) / run) : float(double(x + 1) / double(w));
    }
    env->col_cdf_[size_t(y) * size_t(w) + size_t(w - 1)] = 1.0f;
    row[size_t(y)] = run;
    env->total_ += run;
  }
  double run = 0.0;
  for (int y = 0; y < h; ++y) {
    run += row[size_t(y)];
    env->row_cdf_[size_t(y)] = env->total_ > 0.0 ? float(run / env->total_) : float(double(y + 1) / h);
  }
  env->row_cdf_.back() = 1.0f;
  for (float& wt : env->weight_) wt = env->total_ > 0.0 ? float(double(wt) / env->total_) : 0.0f;
  return std::shared_ptr<const EnvironmentMap>(std::move(env));
}

void EnvironmentMap::uv(const Vec3& d, float& u, float& v) const {
  float phi = std::atan2(d.x, -d.z) - rotate_;
  u = phi * (0.5f / kPi);
  u -= std::floor(u);
  v = std::acos(std::clamp(d.y, -1.0f, 1.0f)) * (1.0f / kPi);
}

Vec3 EnvironmentMap::radiance(const Vec3& d) const {
  float u, v;
  uv(d, u, v);
  const int x = std::min(int(u * float(width_)), width_ - 1);
  const int y = std::min(int(v * float(height_)), height_ - 1);
  return texels_[size_t(y) * size_t(width_) + size_t(x)];
}

float EnvironmentMap::pdf(const Vec3& d) const {
  if (black()) return 0.0f;
  float u, v;
  uv(d, u, v);
  const int x = std::min(int(u * float(width_)), width_ - 1);
  const int y = std::min(int(v * float(height_)), height_ - 1);
  const float sin_t = std::sqrt(std::max(0.0f, 1.0f - d.y * d.y));
  if (!(sin_t > 0.0f)) return 0.0f;
  // Uniform inside the texel in (u, v); dOmega = 2 pi^2 sin(theta) du dv.
  const float p_uv = weight_[size_t(y) * size_t(width_) + size_t(x)] * float(width_) * float(height_);
  return p_uv / (2.0f * kPi * kPi * sin_t);
}

bool EnvironmentMap::sample(float u1, float u2, Vec3& d, float& pdf_out) const {
  if (black()) return false;
  float fy, fx;
  const int y = pick(row_cdf_.data(), height_, u1, fy);
  const int x = pick(col_cdf_.data() + size_t(y) * size_t(width_), width_, u2, fx);
  const float v = (float(y) + fy) / float(height_), u = (float(x) + fx) / float(width_);
  const float theta = v * kPi, phi = u * 2.0f * kPi + rotate_;
  const float st = std::sin(theta);
  d = Vec3(st * std::sin(phi), std::cos(theta), -st * std::cos(phi));
  pdf_out = pdf(d);
  return pdf_out > 0.0f && std::isfinite(pdf_out);
}

}  // namespace frameless
