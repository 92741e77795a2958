// Coherent ray packets through the 8-wide BVH (Wald, Slusallek, Benthin, Wagner 2001): up to
// eight rays share one walk. Each node is culled for the whole packet by interval arithmetic over
// the rays' origins and inverse directions (one 8-wide box test, like a single ray's); leaf boxes
// are then tested per ray, and a leaf's triangles are intersected by all its rays in one AVX2
// pass of the same watertight arithmetic as the single-ray test, so results match bit for bit.
#include <algorithm>
#include <cmath>

#if defined(__AVX2__) && defined(__FMA__)
#include <immintrin.h>
#define FRAMELESS_PACKETS 1
#endif

#include "core/accel/accel_impl.h"
#include "core/accel/instance_top.h"
#include "core/accel/watertight_lanes.h"
#include "core/geometry/intersect_sphere.h"
#include "core/geometry/intersect_triangle.h"

namespace frameless {
namespace {

// Ray by ray: the fallback for packets the SIMD walk does not take.
void intersect_each(const Accel& a, const Ray* rays, int n, Hit* hits, const InstanceTop* top) {
  for (int i = 0; i < n; ++i) {
    hits[i] = Hit{};
    if (!a.intersect(rays[i], hits[i], top)) hits[i] = Hit{};
  }
}
void occluded_each(const Accel& a, const Ray* rays, int n, bool* occ, const InstanceTop* top) {
  for (int i = 0; i < n; ++i) occ[i] = a.occluded(rays[i], top);
}

#if defined(FRAMELESS_PACKETS)

struct PacketEntry {
  uint32_t ref;
  uint32_t info;
  float t;       // packet's entry-distance bound (ordering and culling)
  uint32_t lanes;  // rays whose own box test passed (leaves), or all of them (inner nodes)
};

inline __m256 select3(__m256 x, __m256 y, __m256 z, __m256 is0, __m256 is1) {
  return _mm256_blendv_ps(_mm256_blendv_ps(z, y, is1), x, is0);
}

// Per-ray constants in lanes, plus the packet's interval bounds for the node culling.
struct Packet {
  int n = 0;
  uint32_t all = 0;  // lane mask of the real rays
  __m256 org[3], inv[3], inv_far[3], tmin, tmax_box;
  int near[3];  // bounds row of the entry plane per axis (shared: the packet's signs agree)
  // Interval bounds per axis: origin extremes on the entry and exit sides, inverse-direction
  // extremes for the entry and exit planes.
  float o_near[3], o_far[3], i_lo[3], i_hi[3], if_lo[3], if_hi[3];
  float tmin_all = 0.0f;
  // Triangle test: per-lane axis permutation (masks kx == 0, kx == 1, ...) and shear.
  __m256 kx0, kx1, ky0, ky1, kz0, kz1, neg_sx, neg_sy, sz;
  // The same in scalars, for lanes decided one by one (edges, sparse leaves).
  alignas(32) float o_s[3][8], sx_s[8], sy_s[8], sz_s[8];
  uint32_t kx0_bits, kx1_bits, ky0_bits, ky1_bits, kz0_bits, kz1_bits;
  TriangleRay tri(int i) const {
    TriangleRay t;
    t.kx = (kx0_bits >> i & 1) ? 0 : (kx1_bits >> i & 1) ? 1 : 2;
    t.ky = (ky0_bits >> i & 1) ? 0 : (ky1_bits >> i & 1) ? 1 : 2;
    t.kz = (kz0_bits >> i & 1) ? 0 : (kz1_bits >> i & 1) ? 1 : 2;
    t.sx = sx_s[i], t.sy = sy_s[i], t.sz = sz_s[i];
    t.ox = o_s[t.kx][i], t.oy = o_s[t.ky][i], t.oz = o_s[t.kz][i];
    return t;
  }
};

// 8x8 transpose: eight rows in, eight columns out.
inline void transpose8(__m256 r[8]) {
  __m256 t[8];
  for (int k = 0; k < 4; ++k) {
    t[2 * k] = _mm256_unpacklo_ps(r[2 * k], r[2 * k + 1]);
    t[2 * k + 1] = _mm256_unpackhi_ps(r[2 * k], r[2 * k + 1]);
  }
  __m256 u[8];
  for (int k = 0; k < 2; ++k) {
    u[4 * k + 0] = _mm256_shuffle_ps(t[4 * k], t[4 * k + 2], 0x44);
    u[4 * k + 1] = _mm256_shuffle_ps(t[4 * k], t[4 * k + 2], 0xee);
    u[4 * k + 2] = _mm256_shuffle_ps(t[4 * k + 1], t[4 * k + 3], 0x44);
    u[4 * k + 3] = _mm256_shuffle_ps(t[4 * k + 1], t[4 * k + 3], 0xee);
  }
  for (int k = 0; k < 4; ++k) {
    r[k] = _mm256_permute2f128_ps(u[k], u[k + 4], 0x20);
    r[k + 4] = _mm256_permute2f128_ps(u[k], u[k + 4], 0x31);
  }
}

// Largest spread of the origins along an axis, relative to the scene's size: the interval bound
// sweeps the whole spread along the rays, so origins metres apart in a dense scene would enter
// nearly every box there (shadow rays from pixels that see far-apart surfaces).
constexpr float kMaxSpread = 1.0f / 512.0f;

inline float hmin8(__m256 v) {
  __m128 m = _mm_min_ps(_mm256_castps256_ps128(v), _mm256_extractf128_ps(v, 1));
  m = _mm_min_ps(m, _mm_movehl_ps(m, m));
  return _mm_cvtss_f32(_mm_min_ss(m, _mm_movehdup_ps(m)));
}
inline float hmax8(__m256 v) {
  __m128 m = _mm_max_ps(_mm256_castps256_ps128(v), _mm256_extractf128_ps(v, 1));
  m = _mm_max_ps(m, _mm_movehl_ps(m, m));
  return _mm_cvtss_f32(_mm_max_ss(m, _mm_movehdup_ps(m)));
}

// Sets up the lanes; false when the rays' direction signs disagree on some axis (no shared
// entry plane), in which case the caller goes ray by ray. Idle lanes repeat the last ray, so
// every lane holds finite, meaningful values and the horizontal extremes are the real rays'.
bool make_packet(const Ray* rays, int n, bool triangles, float scene_size, Packet& p) {
  static_assert(sizeof(Ray) == 32, "a ray is one row of the transpose");
  p.n = n;
  p.all = (1u << n) - 1u;
  __m256 c[8];  // rows: the rays; after the transpose, columns: ox oy oz tmin dx dy dz tmax
  for (int i = 0; i < kPacketSize; ++i)
    c[i] = _mm256_loadu_ps(reinterpret_cast<const float*>(rays + (i < n ? i : n - 1)));
  transpose8(c);
  const __m256 dir[3] = {c[4], c[5], c[6]};
  for (int a = 0; a < 3; ++a) {
    const uint32_t neg = uint32_t(_mm256_movemask_ps(dir[a]));
    if (neg != 0 && neg != 0xffu) return false;
    p.near[a] = 2 * a + (neg ? 1 : 0);
  }
  const __m256 tmax_v = c[7];
  p.tmin = c[3];
  // Idle lanes get an empty interval end, so the packet's widest interval is a real ray's.
  const __m256 idle = _mm256_castsi256_ps(_mm256_cmpgt_epi32(
      _mm256_setr_epi32(0, 1, 2, 3, 4, 5, 6, 7), _mm256_set1_epi32(n - 1)));
  p.tmax_box = _mm256_blendv_ps(_mm256_mul_ps(tmax_v, _mm256_set1_ps(kRobustFar)),
                                _mm256_set1_ps(-kInfinity), idle);
  p.tmin_all = hmin8(p.tmin);
  const __m256 sign = _mm256_set1_ps(-0.0f);
  for (int a = 0; a < 3; ++a) {
    p.org[a] = c[a];
    p.inv[a] = _mm256_div_ps(_mm256_set1_ps(1.0f), dir[a]);
    p.inv_far[a] = _mm256_mul_ps(p.inv[a], _mm256_set1_ps(kRobustFar));
    const float omin = hmin8(p.org[a]), omax = hmax8(p.org[a]);
    // Origins far apart (shadow rays from both sides of a silhouette) go ray by ray.
    if (omax - omin > kMaxSpread * scene_size) return false;
    p.i_lo[a] = hmin8(p.inv[a]), p.i_hi[a] = hmax8(p.inv[a]);
    p.if_lo[a] = hmin8(p.inv_far[a]), p.if_hi[a] = hmax8(p.inv_far[a]);
    // Positive direction: the smallest entry distance comes from the largest origin.
    const bool neg = p.near[a] & 1;
    p.o_near[a] = neg ? omin : omax;
    p.o_far[a] = neg ? omax : omin;
  }
  if (!triangles) return true;
  // make_triangle_ray in lanes: kz the largest |component|, (kx, ky) the next two in cyclic
  // order, swapped when the direction along kz is negative.
  const __m256 ax = _mm256_andnot_ps(sign, dir[0]), ay = _mm256_andnot_ps(sign, dir[1]),
               az = _mm256_andnot_ps(sign, dir[2]);
  const __m256 x_gt_y = _mm256_cmp_ps(ax, ay, _CMP_GT_OQ);
  const __m256 z0 = _mm256_and_ps(x_gt_y, _mm256_cmp_ps(ax, az, _CMP_GT_OQ));
  const __m256 z1 = _mm256_andnot_ps(x_gt_y, _mm256_cmp_ps(ay, az, _CMP_GT_OQ));
  const __m256 z2 = _mm256_andnot_ps(_mm256_or_ps(z0, z1), _mm256_castsi256_ps(_mm256_set1_epi32(-1)));
  const __m256 dkz = select3(dir[0], dir[1], dir[2], z0, z1);
  const __m256 swap = _mm256_cmp_ps(dkz, _mm256_setzero_ps(), _CMP_LT_OQ);
  const auto pick = [&](__m256 plain, __m256 swapped) {
    return _mm256_or_ps(_mm256_andnot_ps(swap, plain), _mm256_and_ps(swap, swapped));
  };
  p.kz0 = z0, p.kz1 = z1;
  p.kx0 = pick(z2, z1), p.kx1 = pick(z0, z2);
  p.ky0 = pick(z1, z2), p.ky1 = pick(z2, z0);
  const __m256 dkx = select3(dir[0], dir[1], dir[2], p.kx0, p.kx1);
  const __m256 dky = select3(dir[0], dir[1], dir[2], p.ky0, p.ky1);
  const __m256 sx = _mm256_div_ps(dkx, dkz), sy = _mm256_div_ps(dky, dkz);
  p.sz = _mm256_div_ps(_mm256_set1_ps(1.0f), dkz);
  p.neg_sx = _mm256_xor_ps(sx, sign);
  p.neg_sy = _mm256_xor_ps(sy, sign);
  for (int a = 0; a < 3; ++a) _mm256_store_ps(p.o_s[a], p.org[a]);
  _mm256_store_ps(p.sx_s, sx), _mm256_store_ps(p.sy_s, sy), _mm256_store_ps(p.sz_s, p.sz);
  p.kx0_bits = uint32_t(_mm256_movemask_ps(p.kx0)), p.kx1_bits = uint32_t(_mm256_movemask_ps(p.kx1));
  p.ky0_bits = uint32_t(_mm256_movemask_ps(p.ky0)), p.ky1_bits = uint32_t(_mm256_movemask_ps(p.ky1));
  p.kz0_bits = uint32_t(_mm256_movemask_ps(p.kz0)), p.kz1_bits = uint32_t(_mm256_movemask_ps(p.kz1));
  return true;
}

// Conservative test of the eight child boxes against the whole packet: a box is kept when some
// ray of the packet may enter it within its interval. Every bound is a rounded product of the
// same operands a ray's own test rounds, taken at the extreme operand, so it never exceeds
// (entry) or falls short of (exit) any ray's own value. NaN from 0 * inf ignores the slab.
inline uint32_t packet_children(const Bvh8Node& nd, const Packet& p, float tmax_all, __m256& tn) {
  __m256 tnear[3], tfar[3];
  for (int a = 0; a < 3; ++a) {
    const __m256 dn = _mm256_sub_ps(_mm256_load_ps(nd.bounds[p.near[a]]), _mm256_set1_ps(p.o_near[a]));
    const __m256 df = _mm256_sub_ps(_mm256_load_ps(nd.bounds[p.near[a] ^ 1]), _mm256_set1_ps(p.o_far[a]));
    tnear[a] = _mm256_min_ps(_mm256_mul_ps(dn, _mm256_set1_ps(p.i_lo[a])),
                             _mm256_mul_ps(dn, _mm256_set1_ps(p.i_hi[a])));
    tfar[a] = _mm256_max_ps(_mm256_mul_ps(df, _mm256_set1_ps(p.if_lo[a])),
                            _mm256_mul_ps(df, _mm256_set1_ps(p.if_hi[a])));
  }
  tn = _mm256_max_ps(tnear[0], _mm256_max_ps(tnear[1], _mm256_max_ps(tnear[2], _mm256_set1_ps(p.tmin_all))));
  const __m256 tf = _mm256_min_ps(tfar[0], _mm256_min_ps(tfar[1], _mm256_min_ps(tfar[2], _mm256_set1_ps(tmax_all))));
  return uint32_t(_mm256_movemask_ps(_mm256_cmp_ps(tn, tf, _CMP_LE_OQ)));
}

// Child box i of nd against each ray on its own (the single-ray slab test in lanes).
inline uint32_t lanes_entering(const Bvh8Node& nd, int i, const Packet& p) {
  __m256 tn = p.tmin, tf = p.tmax_box;
  for (int a = 2; a >= 0; --a) {
    const __m256 n = _mm256_set1_ps(nd.bounds[p.near[a]][i]);
    const __m256 f = _mm256_set1_ps(nd.bounds[p.near[a] ^ 1][i]);
    tn = _mm256_max_ps(_mm256_mul_ps(_mm256_sub_ps(n, p.org[a]), p.inv[a]), tn);
    tf = _mm256_min_ps(_mm256_mul_ps(_mm256_sub_ps(f, p.org[a]), p.inv_far[a]), tf);
  }
  return uint32_t(_mm256_movemask_ps(_mm256_cmp_ps(tn, tf, _CMP_LE_OQ)));
}

// The watertight test of intersect_triangle for every lane at once, the same operations in the
// same order. Returns the lanes whose candidate lies in [tmin, tmax_box]; lanes that need the
// double-precision edge decision are returned in `redo` for the scalar test.
inline uint32_t triangle_lanes(const Packet& p, const Vec3& p0, const Vec3& p1, const Vec3& p2,
                               __m256& t, __m256& b1, __m256& b2, uint32_t& redo) {
  const __m256 q0x = _mm256_sub_ps(_mm256_set1_ps(p0.x), p.org[0]);
  const __m256 q0y = _mm256_sub_ps(_mm256_set1_ps(p0.y), p.org[1]);
  const __m256 q0z = _mm256_sub_ps(_mm256_set1_ps(p0.z), p.org[2]);
  const __m256 q1x = _mm256_sub_ps(_mm256_set1_ps(p1.x), p.org[0]);
  const __m256 q1y = _mm256_sub_ps(_mm256_set1_ps(p1.y), p.org[1]);
  const __m256 q1z = _mm256_sub_ps(_mm256_set1_ps(p1.z), p.org[2]);
  const __m256 q2x = _mm256_sub_ps(_mm256_set1_ps(p2.x), p.org[0]);
  const __m256 q2y = _mm256_sub_ps(_mm256_set1_ps(p2.y), p.org[1]);
  const __m256 q2z = _mm256_sub_ps(_mm256_set1_ps(p2.z), p.org[2]);
  const __m256 a_x = select3(q0x, q0y, q0z, p.kx0, p.kx1), a_y = select3(q0x, q0y, q0z, p.ky0, p.ky1),
               a_z = select3(q0x, q0y, q0z, p.kz0, p.kz1);
  const __m256 b_x = select3(q1x, q1y, q1z, p.kx0, p.kx1), b_y = select3(q1x, q1y, q1z, p.ky0, p.ky1),
               b_z = select3(q1x, q1y, q1z, p.kz0, p.kz1);
  const __m256 c_x = select3(q2x, q2y, q2z, p.kx0, p.kx1), c_y = select3(q2x, q2y, q2z, p.ky0, p.ky1),
               c_z = select3(q2x, q2y, q2z, p.kz0, p.kz1);
  const LaneTriangle q{{a_x, a_y, a_z}, {b_x, b_y, b_z}, {c_x, c_y, c_z}};
  return watertight_lanes(q, p.neg_sx, p.neg_sy, p.sz, p.tmin, p.tmax_box, 0xffu, t, b1, b2, redo);
}

template <bool kAnyHit>
void traverse_packet(const Bvh8Node* nodes, const LeafTriangle* leaf_tris, bool prefetch, const Geometry& g,
                     const Accel::AlphaTest& alpha, const Ray* rays, Packet& p, Hit* hits, bool* occ) {
  const Sphere* spheres = g.spheres.data();
  const uint32_t num_tris = g.num_triangles();
  alignas(32) float tmax_box[8];
  _mm256_store_ps(tmax_box, p.tmax_box);
  float tmax_all = hmax8(p.tmax_box);
  uint32_t active = p.all;  // any-hit: rays not yet occluded
  // A lane's new best hit narrows its interval and, through tmax_all, the packet's.
  // (A blend, not a reload of tmax_box: a wide load after a narrow store stalls.)
  auto narrow = [&](int i, float t) {
    tmax_box[i] = t * kRobustFar;
    const __m256 lane = _mm256_castsi256_ps(
        _mm256_cmpeq_epi32(_mm256_set1_epi32(i), _mm256_setr_epi32(0, 1, 2, 3, 4, 5, 6, 7)));
    p.tmax_box = _mm256_blendv_ps(p.tmax_box, _mm256_set1_ps(tmax_box[i]), lane);
    tmax_all = hmax8(p.tmax_box);  // idle lanes hold -inf
  };
  // Records a candidate of lane i (already within its widened interval) if it wins.
  auto offer = [&](int i, float t, float u, float v, uint32_t prim) -> bool {
    const Ray& r = rays[i];
    if (kAnyHit ? !(t <= r.tmax) : !closer_hit(t, prim, hits[i].valid(), hits[i], r.tmax)) return false;
    if (alpha.opaque && !alpha_opaque(alpha, g, prim, r, t, u, v)) return false;
    if constexpr (kAnyHit) {
      occ[i] = true;
      active &= ~(1u << i);
    } else {
      hits[i] = Hit{t, prim, u, v};
      narrow(i, t);
    }
    return true;
  };

  PacketEntry stack[kStackSize + kStackSize / 7 + kBvhWidth];  // a node pushes up to 8, not 7
  int sp = 0;
  stack[sp++] = {0, 0, 0.0f, p.all};
  while (sp > 0) {
    const PacketEntry e = stack[--sp];
    if (e.t > tmax_all) continue;
    uint32_t lanes = e.lanes & active;
    if (lanes == 0) continue;
    if (e.info == 0) {
      const Bvh8Node& nd = nodes[e.ref];
      __m256 tnv;
      uint32_t mask = packet_children(nd, p, tmax_all, tnv);
      alignas(32) float dist[8];
      _mm256_store_ps(dist, tnv);
      // Onto the stack far to near (any-hit too: the nearest box most likely blocks).
      const int base = sp;
      while (mask) {
        const int j = __builtin_ctz(mask);
        mask &= mask - 1;
        uint32_t l = active;
        if (nd.info[j] != 0) {  // a leaf: keep only the rays entering its box
          l &= lanes_entering(nd, j, p);
          if (l == 0) continue;
        }
        if (prefetch) prefetch_child(nodes, leaf_tris, nd, j, nullptr, spheres);
        push_far_to_near(stack, base, sp, PacketEntry{nd.child[j], nd.info[j], dist[j], l});
      }
      continue;
    }
    const uint32_t count = e.info & kLeafCountMask;
    if (e.info & kSphereLeafBit) {
      for (uint32_t k = 0; k < count; ++k)
        for (uint32_t l = lanes & active; l; l &= l - 1) {
          const int i = __builtin_ctz(l);
          float t;
          if (intersect_sphere(rays[i].org, rays[i].dir, spheres[e.ref + k], rays[i].tmin,
                               tmax_box[i], t))
            offer(i, t, 0.0f, 0.0f, num_tris + e.ref + k);
        }
      if (kAnyHit && !active) return;
      continue;
    }
    for (uint32_t k = 0; k < count; ++k) {
      lanes &= active;
      if (!lanes) break;
      const uint32_t prim = e.ref + k;
      const Vec3* tri = leaf_tris[prim].p;
      if (__builtin_popcount(lanes) <= 2) {  // few rays in this leaf: the scalar test is cheaper
        for (uint32_t l = lanes; l; l &= l - 1) {
          const int i = __builtin_ctz(l);
          float t, u, v;
          if (intersect_triangle(p.tri(i), tri[0], tri[1], tri[2], rays[i].tmin,
                                 tmax_box[i], t, u, v))
            offer(i, t, u, v, prim);
        }
        continue;
      }
      __m256 tv = _mm256_setzero_ps(), uv = tv, vv = tv;
      uint32_t redo = 0;
      uint32_t hit_lanes = triangle_lanes(p, tri[0], tri[1], tri[2], tv, uv, vv, redo) & lanes;
      redo &= lanes;
      if (!(hit_lanes | redo)) continue;
      alignas(32) float ts[8], us[8], vs[8];
      _mm256_store_ps(ts, tv), _mm256_store_ps(us, uv), _mm256_store_ps(vs, vv);
      for (uint32_t r = redo; r; r &= r - 1) {  // on an edge: the scalar test decides in double
        const int i = __builtin_ctz(r);
        if (intersect_triangle(p.tri(i), tri[0], tri[1], tri[2], rays[i].tmin,
                               tmax_box[i], ts[i], us[i], vs[i]))
          hit_lanes |= 1u << i;
      }
      for (; hit_lanes; hit_lanes &= hit_lanes - 1) {
        const int i = __builtin_ctz(hit_lanes);
        offer(i, ts[i], us[i], vs[i], prim);
      }
    }
    if (kAnyHit && !active) return;
  }
}

#endif  // FRAMELESS_PACKETS

}  // namespace

#if defined(FRAMELESS_PACKETS)
namespace {
// Sets up the SIMD walk when it applies: a BVH (no grid), no spline patches (their Broyden
// solve is per ray), and a packet that passes make_packet's coherence tests.
bool packet_walk(bool bvh, const Geometry* g, float scene_size, const Ray* rays, int n, Packet& p) {
  return n > 1 && bvh && g && g->num_patches() == 0 &&
         make_packet(rays, n, g->num_triangles() > 0, scene_size, p);
}
}  // namespace
#endif

void Accel::intersect_packet(const Ray* rays, int n, Hit* hits, const InstanceTop* top) const {
  n = std::clamp(n, 0, kPacketSize);
  if (n == 0) return;
#if defined(FRAMELESS_PACKETS)
  const Impl& im = *impl_;
  {
    Packet p;
    if (packet_walk(!im.grid && !im.nodes.empty(), im.geom, im.scene_size, rays, n, p)) {
      for (int i = 0; i < n; ++i) hits[i] = Hit{};
      traverse_packet<false>(im.nodes.data(), im.leaf_tris.data(), im.prefetch, *im.geom, im.alpha, rays, p, hits, nullptr);
      if ((top = top_in_use(top))) intersect_instances_packet(*top, rays, n, hits);
      return;
    }
  }
  if ((top = top_in_use(top)) && n > 1) {
    // The flat geometry ray by ray, the instances' top level together.
    for (int i = 0; i < n; ++i)
      if (!intersect_flat(rays[i], hits[i])) hits[i] = Hit{};
    intersect_instances_packet(*top, rays, n, hits);
    return;
  }
#endif
  intersect_each(*this, rays, n, hits, top);
}

void Accel::occluded_packet(const Ray* rays, int n, bool* occluded, const InstanceTop* top) const {
  n = std::clamp(n, 0, kPacketSize);
  if (n == 0) return;
#if defined(FRAMELESS_PACKETS)
  const Impl& im = *impl_;
  {
    Packet p;
    if (packet_walk(!im.grid && !im.nodes.empty(), im.geom, im.scene_size, rays, n, p)) {
      for (int i = 0; i < n; ++i) occluded[i] = false;
      traverse_packet<true>(im.nodes.data(), im.leaf_tris.data(), im.prefetch, *im.geom, im.alpha, rays, p, nullptr, occluded);
      if ((top = top_in_use(top))) occluded_instances_packet(*top, rays, n, occluded);
      return;
    }
  }
  if ((top = top_in_use(top)) && n > 1) {
    for (int i = 0; i < n; ++i) occluded[i] = occluded_flat(rays[i]);
    occluded_instances_packet(*top, rays, n, occluded);
    return;
  }
#endif
  occluded_each(*this, rays, n, occluded, top);
}

}  // namespace frameless
