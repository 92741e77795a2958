// The light slab's table lookup (quadrilinear) and the ray-box test that places it in a scene.
#include "core/scene/lightfield.h"

#include <Imath/half.h>

#include <algorithm>
#include <cmath>

namespace frameless {
namespace {

// One axis: the two nodes around coordinate c in [-1, 1] and the weight of the second; false
// outside the range.
bool axis_nodes(float c, uint32_t n, uint32_t& i0, uint32_t& i1, float& w) {
  if (!(c >= -1.0f && c <= 1.0f)) return false;
  const float f = std::clamp((c + 1.0f) * 0.5f * float(n) - 0.5f, 0.0f, float(n - 1));
  i0 = std::min(uint32_t(f), n - 1);
  i1 = std::min(i0 + 1, n - 1);
  w = f - float(i0);
  return true;
}

}  // namespace

Vec4Color LightField::texel(uint32_t i, uint32_t j, uint32_t s, uint32_t t) const {
  const uint16_t* p = rgba.data() + texel_offset(i, j, s, t);
  return Vec4Color{Vec3(imath_half_to_float(p[0]), imath_half_to_float(p[1]), imath_half_to_float(p[2])),
                   imath_half_to_float(p[3])};
}

Vec4Color LightField::lookup(float u, float v, float s, float t) const {
  uint32_t i[2], j[2], a[2], b[2];
  float wu, wv, ws, wt;
  if (!axis_nodes(u, nu, i[0], i[1], wu) || !axis_nodes(v, nv, j[0], j[1], wv) ||
      !axis_nodes(s, ns, a[0], a[1], ws) || !axis_nodes(t, nt, b[0], b[1], wt))
    return {};
  Vec4Color out;
  for (int k = 0; k < 16; ++k) {
    const int ki = k & 1, kj = (k >> 1) & 1, ka = (k >> 2) & 1, kb = (k >> 3) & 1;
    const float w = (ki ? wu : 1.0f - wu) * (kj ? wv : 1.0f - wv) * (ka ? ws : 1.0f - ws) * (kb ? wt : 1.0f - wt);
    if (w == 0.0f) continue;
    const Vec4Color c = texel(i[ki], j[kj], a[ka], b[kb]);
    out.rgb += w * c.rgb;
    out.alpha += w * c.alpha;
  }
  return out;
}

std::string check_lightfield(const LightField& lf) {
  if (lf.nu == 0 || lf.nv == 0 || lf.ns == 0 || lf.nt == 0) return "every resolution must be at least 1";
  if (lf.nu > 1024 || lf.nv > 1024 || lf.ns > 8192 || lf.nt > 8192)
    return "resolution too large (uv at most 1024 x 1024, st at most 8192 x 8192)";
  if (uint64_t(lf.width()) * lf.height() > (uint64_t(1) << 31)) return "more than 2^31 texels";
  if (lf.rgba.size() != size_t(lf.width()) * lf.height() * 4) return "table size does not match its resolution";
  for (size_t k = 0; k < lf.rgba.size(); k += 4) {
    const float r = imath_half_to_float(lf.rgba[k]), g = imath_half_to_float(lf.rgba[k + 1]),
                b = imath_half_to_float(lf.rgba[k + 2]), a = imath_half_to_float(lf.rgba[k + 3]);
    if (!(std::isfinite(r) && std::isfinite(g) && std::isfinite(b) && r >= 0.0f && g >= 0.0f && b >= 0.0f))
      return "texel " + std::to_string(k / 4) + ": colour must be finite and non-negative";
    if (!(a >= 0.0f && a <= 1.0f)) return "texel " + std::to_string(k / 4) + ": alpha must lie in [0, 1]";
  }
  const glm::mat3& m = lf.slab_to_model.m;
  const float det = glm::determinant(m);
  if (!std::isfinite(det) || std::abs(det) < 1e-20f || !std::isfinite(lf.slab_to_model.t.x + lf.slab_to_model.t.y + lf.slab_to_model.t.z))
    return "slab frame must be finite and invertible";
  return "";
}

LightfieldObject place_lightfield(std::shared_ptr<const LightField> table, const Affine& transform) {
  LightfieldObject o;
  o.to_world.m = transform.m * table->slab_to_model.m;
  o.to_world.t = transform.m * table->slab_to_model.t + transform.t;
  o.to_slab.m = glm::inverse(o.to_world.m);
  o.to_slab.t = -(o.to_slab.m * o.to_world.t);
  o.lo = Vec3(kInfinity);
  o.hi = Vec3(-kInfinity);
  for (int c = 0; c < 8; ++c) {
    const Vec3 w = o.to_world.point(Vec3((c & 1) ? 1.0f : -1.0f, (c & 2) ? 1.0f : -1.0f, (c & 4) ? 1.0f : -1.0f));
    o.lo = glm::min(o.lo, w);
    o.hi = glm::max(o.hi, w);
  }
  o.table = std::move(table);
  return o;
}

bool lightfield_along(const LightfieldObject& object, const Ray& ray, float t_end, LightfieldHit& hit) {
  // An affine map keeps a line's parameter: the slab-frame ray has the same t.
  const Vec3 o = object.to_slab.point(ray.org), d = object.to_slab.vector(ray.dir);
  if (!(d.z < 0.0f)) return false;  // the slab stores light travelling towards -z only
  float t0 = -kInfinity, t1 = kInfinity;
  for (int k = 0; k < 3; ++k) {
    if (d[k] == 0.0f) {
      if (o[k] < -1.0f || o[k] > 1.0f) return false;
      continue;
    }
    const float a = (-1.0f - o[k]) / d[k], b = (1.0f - o[k]) / d[k];
    t0 = std::max(t0, std::min(a, b));
    t1 = std::min(t1, std::max(a, b));
  }
  if (!(t0 <= t1) || t0 < ray.tmin || !(t0 < std::min(t_end, ray.tmax))) return false;
  // The line's crossings of the uv plane (z = 1) and the st plane (z = 0).
  const float tu = (1.0f - o.z) / d.z, ts = -o.z / d.z;
  const Vec3 puv = o + tu * d, pst = o + ts * d;
  hit.t = t0;
  hit.color = object.table->lookup(puv.x, puv.y, pst.x, pst.y);
  return hit.color.alpha > 0.0f || max_component(hit.color.rgb) > 0.0f;
}

}  // namespace frameless
