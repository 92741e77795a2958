// The discontinuity buffer: a same-surface box filter of igi's demodulated indirect light.
#include "display/discontinuity_buffer.h"

#include <algorithm>
#include <cmath>

namespace frameless {
namespace {

constexpr float kMinNormalDot = 0.9f;  // about 25 degrees
constexpr float kMaxPlaneSlope = 0.1f;  // |n . d| / |d|: about 6 degrees off the tangent plane

// The albedo divided out, with dark channels left alone (nothing to divide out of them).
inline Vec3 divisor(const PointGuide& g) {
  Vec3 a = unpack_albedo(g.albedo);
  for (int c = 0; c < 3; ++c) a[c] = a[c] > 0.02f ? a[c] : 1.0f;
  return a;
}

}  // namespace

// The test of same_surface() on unpacked normals.
inline bool same_plane(const Vec3& na, const Vec3& pa, const Vec3& nb, const Vec3& pb) {
  if (glm::dot(na, nb) < kMinNormalDot) return false;
  const Vec3 d = pb - pa;
  const float h = glm::dot(na, d);
  return h * h <= kMaxPlaneSlope * kMaxPlaneSlope * glm::dot(d, d);  // |n . d| <= slope |d|, no root
}

bool same_surface(const PointGuide& a, const PointGuide& b) {
  if (!guided_surface(a) || !guided_surface(b)) return false;
  return same_plane(unpack_normal(a.normal), a.p, unpack_normal(b.normal), b.p);
}

// One neighbour offset of the window for pixels [x0, x1) of a row: pixel row + x against its
// neighbour qrow + x. Restrict-qualified arrays and a select instead of a branch: vectorized.
void window_row(float* const* f, size_t row, size_t qrow, int x0, int x1, float* __restrict sr,
                float* __restrict sg, float* __restrict sb, float* __restrict used) {
  const float* __restrict nx = f[0];
  const float* __restrict ny = f[1];
  const float* __restrict nz = f[2];
  const float* __restrict px = f[3];
  const float* __restrict py = f[4];
  const float* __restrict pz = f[5];
  const float* __restrict er = f[6];
  const float* __restrict eg = f[7];
  const float* __restrict eb = f[8];
  constexpr float kSlope2 = kMaxPlaneSlope * kMaxPlaneSlope;
  for (int x = x0; x < x1; ++x) {  // the pixel itself passes: d = 0, dot(n, n) = 1
    const size_t i = row + size_t(x), q = qrow + size_t(x);
    const float dxp = px[q] - px[i], dyp = py[q] - py[i], dzp = pz[q] - pz[i];
    const float hgt = nx[i] * dxp + ny[i] * dyp + nz[i] * dzp;
    const float cosn = nx[i] * nx[q] + ny[i] * ny[q] + nz[i] * nz[q];
    const float wgt = cosn >= kMinNormalDot && hgt * hgt <= kSlope2 * (dxp * dxp + dyp * dyp + dzp * dzp) ? 1.0f : 0.0f;
    sr[x] += wgt * er[q];
    sg[x] += wgt * eg[q];
    sb[x] += wgt * eb[q];
    used[x] += wgt;
  }
}

void filter_discontinuity(DisplayImage& img, const std::vector<PointGuide>& guides,
                          const std::vector<Vec3>& indirect, int n, DiscontinuityBuffers& b) {
  const int w = img.width, h = img.height;
  const size_t count = img.pixels();
  if (n < 2 || guides.size() != count || indirect.size() != count || count == 0) return;
  // Structure of arrays (normal, point, demodulated light), so that the window's loops over a row
  // vectorize; a zero normal marks a pixel on no surface (its dot with any normal is 0).
  enum { kNx, kNy, kNz, kPx, kPy, kPz, kR, kG, kB, kAr, kAg, kAb, kFields };
  b.fields.resize(kFields * count);
  float* f[kFields];
  for (int k = 0; k < kFields; ++k) f[k] = b.fields.data() + size_t(k) * count;
  for (size_t i = 0; i < count; ++i) {
    const bool s = guided_surface(guides[i]);
    const Vec3 nn = s ? unpack_normal(guides[i].normal) : Vec3(0.0f);
    const Vec3 a = s ? divisor(guides[i]) : Vec3(1.0f);
    for (int c = 0; c < 3; ++c) {
      f[kNx + c][i] = nn[c];
      f[kPx + c][i] = guides[i].p[c];
      f[kR + c][i] = s ? indirect[i][c] / a[c] : 0.0f;
      f[kAr + c][i] = a[c];
    }
  }
  b.row.resize(4 * size_t(w));
  float *sr = b.row.data(), *sg = sr + w, *sb = sg + w, *used = sb + w;
  const int lo = n / 2;  // the window [x - lo, x - lo + n) holds each of the n classes once
  for (int y = 0; y < h; ++y) {
    const size_t row = size_t(y) * size_t(w);
    std::fill(b.row.begin(), b.row.end(), 0.0f);
    for (int qy = std::max(0, y - lo); qy < std::min(h, y - lo + n); ++qy)
      for (int dx = -lo; dx < n - lo; ++dx) {
        const size_t qrow = size_t(qy) * size_t(w) + size_t(dx);  // may wrap: used from x0 on
        const int x0 = std::max(0, -dx), x1 = std::min(w, w - dx);
        window_row(f, row, qrow, x0, x1, sr, sg, sb, used);
      }
    for (int x = 0; x < w; ++x) {
      const size_t i = row + size_t(x);
      if (used[x] < 1.0f) continue;  // on no surface
      const float inv = 1.0f / used[x];
      const float filtered[3] = {sr[x] * inv * f[kAr][i], sg[x] * inv * f[kAg][i], sb[x] * inv * f[kAb][i]};
      for (int c = 0; c < 3; ++c) {
        const float v = img.rgb[3 * i + c] - indirect[i][c] + filtered[c];
        if (std::isfinite(v)) img.rgb[3 * i + c] = std::max(0.0f, v);
      }
    }
  }
}

}  // namespace frameless
