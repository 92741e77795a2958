// The cone visitor of soft shadows (Accel::visit_cone): every BVH leaf whose box, grown by the
// cone's radius, the cone's axis enters; the leaves' primitives are the visitor's to test.
#include <algorithm>

#if defined(__AVX2__)
#include <immintrin.h>
#endif

#include "core/accel/accel_impl.h"

namespace frameless {
namespace {

// Mask of the eight children whose boxes, grown by the cone's radius at the box's far end along
// the axis, the axis ray enters within [0, tmax]. A point of the box inside the cone lies within
// that radius of the axis at its own depth, so it lies in the grown box on the axis: conservative.
inline uint32_t cone_children(const Bvh8Node& n, const Ray& ray, const BoxRay& r, float tan_half,
                              float tmax) {
#if defined(__AVX2__)
  const __m256 zero = _mm256_setzero_ps();
  __m256 far_t = zero;  // largest depth along the axis of any box corner
  for (int a = 0; a < 3; ++a) {
    const __m256 o = _mm256_set1_ps(ray.org[a]), d = _mm256_set1_ps(ray.dir[a]);
    const __m256 lo = _mm256_mul_ps(_mm256_sub_ps(_mm256_load_ps(n.bounds[2 * a]), o), d);
    const __m256 hi = _mm256_mul_ps(_mm256_sub_ps(_mm256_load_ps(n.bounds[2 * a + 1]), o), d);
    far_t = _mm256_add_ps(far_t, _mm256_max_ps(lo, hi));
  }
  // Boxes wholly behind the apex are out; so are empty slots (lo > hi), whose far_t can be +inf.
  const __m256 in_front =
      _mm256_and_ps(_mm256_cmp_ps(far_t, zero, _CMP_GE_OQ),
                    _mm256_cmp_ps(_mm256_load_ps(n.bounds[0]), _mm256_load_ps(n.bounds[1]), _CMP_LE_OQ));
  // The rounding of far_t and of the slab test is covered by a relative margin.
  const __m256 grow = _mm256_add_ps(
      _mm256_mul_ps(_mm256_set1_ps(tan_half * 1.0001f),
                    _mm256_min_ps(far_t, _mm256_set1_ps(tmax))),
      _mm256_set1_ps(1e-30f));
  __m256 tn = zero, tf = _mm256_set1_ps(tmax);
  for (int a = 0; a < 3; ++a) {
    const __m256 o = _mm256_set1_ps(r.org[a]);
    // Entry plane moves against the direction of travel, exit plane with it.
    const bool neg = r.near[a] & 1;
    const __m256 g = neg ? _mm256_sub_ps(zero, grow) : grow;
    const __m256 near_plane = _mm256_sub_ps(_mm256_load_ps(n.bounds[r.near[a]]), g);
    const __m256 far_plane = _mm256_add_ps(_mm256_load_ps(n.bounds[r.near[a] ^ 1]), g);
    tn = _mm256_max_ps(_mm256_mul_ps(_mm256_sub_ps(near_plane, o), _mm256_set1_ps(r.inv[a])), tn);
    tf = _mm256_min_ps(_mm256_mul_ps(_mm256_sub_ps(far_plane, o), _mm256_set1_ps(r.inv_far[a])), tf);
  }
  const __m256 hit = _mm256_and_ps(_mm256_cmp_ps(tn, tf, _CMP_LE_OQ), in_front);
  return uint32_t(_mm256_movemask_ps(hit));
#else
  uint32_t mask = 0;
  for (int i = 0; i < kBvhWidth; ++i) {
    if (n.bounds[0][i] > n.bounds[1][i]) continue;  // empty slot
    float far_t = 0.0f;  // largest depth along the axis of any box corner
    for (int a = 0; a < 3; ++a)
      far_t += std::max((n.bounds[2 * a][i] - ray.org[a]) * ray.dir[a],
                        (n.bounds[2 * a + 1][i] - ray.org[a]) * ray.dir[a]);
    if (!(far_t >= 0.0f)) continue;  // wholly behind the apex
    const float grow = tan_half * std::min(far_t, tmax) * 1.0001f + 1e-30f;
    float tn = 0.0f, tf = tmax;
    for (int a = 0; a < 3; ++a) {
      const float lo = n.bounds[2 * a][i] - grow, hi = n.bounds[2 * a + 1][i] + grow;
      const float near_plane = r.near[a] & 1 ? hi : lo, far_plane = r.near[a] & 1 ? lo : hi;
      tn = std::max(tn, (near_plane - r.org[a]) * r.inv[a]);  // NaN keeps tn
      tf = std::min(tf, (far_plane - r.org[a]) * r.inv_far[a]);
    }
    mask |= uint32_t(tn <= tf) << i;
  }
  return mask;
#endif
}

}  // namespace

bool Accel::visit_cone(const Ray& ray, float tan_half, ConeVisitor& visitor) const {
  const Impl& im = *impl_;
  if (im.grid) return im.grid->visit_cone(ray, tan_half, visitor);
  if (!im.geom || im.nodes.empty()) return true;
  const BoxRay br = make_box_ray(ray);
  const float tmax = ray.tmax * kRobustFar;
  const uint32_t nt = im.geom->num_triangles();
  struct Entry {
    uint32_t ref, info;
  } stack[kStackSize];
  int sp = 0;
  stack[sp++] = {0, 0};
  while (sp > 0) {
    const Entry e = stack[--sp];
    if (e.info == 0) {
      const Bvh8Node& node = im.nodes[e.ref];
      uint32_t mask = cone_children(node, ray, br, tan_half, tmax);
      while (mask) {
        const uint32_t j = uint32_t(__builtin_ctz(mask));
        mask &= mask - 1;
        stack[sp++] = {node.child[j], node.info[j]};
      }
    } else if (e.info & kPatchLeafBit) {
      if (!visitor.leaf(im.geom->first_patch() + e.ref, e.info & kLeafCountMask)) return false;
    } else if (e.info & kSphereLeafBit) {
      if (!visitor.leaf(nt + e.ref, e.info & kLeafCountMask)) return false;
    } else {
      if (!visitor.leaf(e.ref, e.info)) return false;
    }
  }
  return true;
}

}  // namespace frameless
