// A-trous filtering of the shown image: demodulate by albedo, filter illumination with a 3x3
// B-spline kernel at growing steps, weights from normals, plane distance and luminance noise,
// remodulate.
#include "display/denoise.h"

#include <algorithm>
#include <cmath>

namespace frameless {
namespace {

// The normal weight is (n_p . n_q)^64.
constexpr float kSigmaPlane = 1.0f;      // plane distance in footprints x step
constexpr float kSigmaLuminance = 1.0f;  // luminance difference in standard deviations
constexpr float kKernel[3] = {0.25f, 0.5f, 0.25f};

inline float luminance(const float* c) { return 0.2126f * c[0] + 0.7152f * c[1] + 0.0722f * c[2]; }

}  // namespace

void denoise_image(DisplayImage& img, const std::vector<PointGuide>& guides, int iterations,
                   DenoiseBuffers& b) {
  const int w = img.width, h = img.height;
  const size_t n = img.pixels();
  if (guides.size() != n || n == 0) return;
  b.a.resize(3 * n);
  b.b.resize(3 * n);
  b.var.resize(n);
  b.var2.resize(n);
  b.footprint.resize(n);
  b.normal.resize(n);
  b.albedo.resize(n);
  for (size_t i = 0; i < n; ++i) {
    const bool s = guided_surface(guides[i]);
    b.normal[i] = s ? unpack_normal(guides[i].normal) : Vec3(0.0f);
    Vec3 a = s ? unpack_albedo(guides[i].albedo) : Vec3(1.0f);
    for (int c = 0; c < 3; ++c) a[c] = a[c] > 0.02f ? a[c] : 1.0f;  // nothing to divide out
    b.albedo[i] = a;
    for (int c = 0; c < 3; ++c) b.a[3 * i + c] = img.rgb[3 * i + c] / a[c];
    // Variance of the shown mean's luminance, in illumination units.
    const float la = std::max(0.02f, 0.2126f * a.x + 0.7152f * a.y + 0.0722f * a.z);
    const float count = float(std::max<uint32_t>(1, img.sample_count[i]));
    b.var[i] = std::max(0.0f, img.variance[i]) / count / (la * la);
  }
  // A pixel's footprint: the distance to its nearest 4-neighbour. A pixel on an edge (next to the
  // sky, an emitter, a crease or another surface) may mix both sides into its colour (its samples
  // straddle the edge): footprint 0, so it is neither filtered nor used (a lamp's edge would
  // bleed into the ceiling, a block's into the wall).
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      const size_t i = size_t(y) * size_t(w) + size_t(x);
      float f = kInfinity;
      bool interior = guided_surface(guides[i]);
      const int dx[4] = {-1, 1, 0, 0}, dy[4] = {0, 0, -1, 1};
      for (int k = 0; k < 4 && interior; ++k) {
        const int qx = x + dx[k], qy = y + dy[k];
        if (qx < 0 || qy < 0 || qx >= w || qy >= h) continue;
        const PointGuide& q = guides[size_t(qy) * size_t(w) + size_t(qx)];
        const Vec3 d = q.p - guides[i].p;
        const float len = glm::length(d);
        if (!guided_surface(q) || glm::dot(b.normal[i], unpack_normal(q.normal)) < 0.95f ||
            std::abs(glm::dot(b.normal[i], d)) > 0.25f * len)
          interior = false;
        else
          f = std::min(f, len);
      }
      b.footprint[i] = interior && f < kInfinity && f > 0.0f ? f : 0.0f;
    }
  std::vector<float>*in = &b.a, *out = &b.b;
  for (int it = 0; it < iterations; ++it) {
    const int step = 1 << it;
    for (int y = 0; y < h; ++y)
      for (int x = 0; x < w; ++x) {
        const size_t i = size_t(y) * size_t(w) + size_t(x);
        const float* ci = &(*in)[3 * i];
        if (!guided_surface(guides[i]) || b.footprint[i] <= 0.0f) {
          for (int c = 0; c < 3; ++c) (*out)[3 * i + c] = ci[c];
          b.var2[i] = b.var[i];
          continue;
        }
        const Vec3 np = b.normal[i], pp = guides[i].p;
        const float lp = luminance(ci);
        // Without a variance (an engine that does not track it) only geometry stops the filter.
        const float lum_scale = b.var[i] > 0.0f ? 1.0f / (kSigmaLuminance * std::sqrt(b.var[i]) + 1e-4f) : 0.0f;
        const float plane_scale = 1.0f / (kSigmaPlane * b.footprint[i] * float(step));
        float sum[3] = {0.0f, 0.0f, 0.0f}, wsum = 0.0f, vsum = 0.0f;
        for (int ky = -1; ky <= 1; ++ky) {
          const int qy = y + ky * step;
          if (qy < 0 || qy >= h) continue;
          for (int kx = -1; kx <= 1; ++kx) {
            const int qx = x + kx * step;
            if (qx < 0 || qx >= w) continue;
            const size_t q = size_t(qy) * size_t(w) + size_t(qx);
            if (b.footprint[q] <= 0.0f) continue;
            const float* cq = &(*in)[3 * q];
            float wn = std::max(0.0f, glm::dot(np, b.normal[q]));  // cos^64 by six squarings
            for (int k = 0; k < 6; ++k) wn *= wn;
            const float wgt = kKernel[kx + 1] * kKernel[ky + 1] * wn *
                              std::exp(-std::abs(glm::dot(np, guides[q].p - pp)) * plane_scale -
                                       std::abs(luminance(cq) - lp) * lum_scale);
            for (int c = 0; c < 3; ++c) sum[c] += wgt * cq[c];
            wsum += wgt;
            vsum += wgt * wgt * b.var[q];
          }
        }
        // The centre always weighs in (wn = wp = wl = 1), so wsum > 0.
        for (int c = 0; c < 3; ++c) (*out)[3 * i + c] = sum[c] / wsum;
        b.var2[i] = vsum / (wsum * wsum);
      }
    std::swap(in, out);
    b.var.swap(b.var2);
  }
  for (size_t i = 0; i < n; ++i)
    for (int c = 0; c < 3; ++c) {
      const float v = (*in)[3 * i + c] * b.albedo[i][c];
      img.rgb[3 * i + c] = std::isfinite(v) ? v : img.rgb[3 * i + c];
    }
}

}  // namespace frameless
