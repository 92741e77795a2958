// In-place binned-SAH builder of the 8-wide BVH over spheres (bvh_build_spheres.h). The split
// rules follow bvh_build.cpp; what differs is memory: no PrimRef array (bounds are recomputed
// from the sphere), the sphere and material arrays are partitioned together in place, each
// range carries the bounds of its centres (gathered while partitioning, so no extra pass), and
// nodes go to 4 MiB blocks, mapped on demand and freed as the final array is assembled.
#include "core/bvh_build_spheres.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <functional>
#include <memory>
#include <new>

#if defined(__SSE2__)
#include <immintrin.h>
#endif

#if defined(__unix__) || defined(__APPLE__)
#include <sys/mman.h>
#define FRAMELESS_NODE_MMAP 1
#endif

namespace frameless {
namespace {

// Past this node level splits become object medians (as in build_bvh8), bounding the depth.
constexpr int kSahDepthLimit = 32;
constexpr int kMaxBins = 64;
// Above kParallelMin spheres the tree is built as a top part plus subtree tasks (whether or not
// there is an executor, so the layout never depends on it); kMinTask is the smallest task size
// limit; with an executor, top splits of at least kParallelBinMin spheres bin in parallel chunks
// of kBinChunk spheres.
constexpr uint32_t kParallelMin = 65536;
constexpr uint32_t kMinTask = 16384;
constexpr uint32_t kParallelBinMin = 1u << 18;
constexpr uint32_t kBinChunk = 1u << 16;
// Ranges up to this size are split by exact SAH over sorted centres instead of bins.
constexpr uint32_t kSmallSplit = 32;

using ParallelFor = std::function<void(size_t, const std::function<void(size_t)>&)>;

struct Box {
  Vec3 lo{kInfinity};
  Vec3 hi{-kInfinity};
  void grow(const Vec3& l, const Vec3& h) {
    lo = glm::min(lo, l);
    hi = glm::max(hi, h);
  }
  void grow(const Vec3& p) { grow(p, p); }
  void grow(const Box& b) { grow(b.lo, b.hi); }
  float half_area() const {
    const Vec3 d = hi - lo;
    if (!(d.x >= 0.0f && d.y >= 0.0f && d.z >= 0.0f)) return 0.0f;
    return d.x * d.y + d.y * d.z + d.z * d.x;
  }
};

// Four floats (x, y, z and a spare lane) for the per-sphere work of binning and partitioning:
// SSE where there is SSE, plain floats otherwise, with the same results (min/max return their
// second operand when unordered, as minps/maxps do).
#if defined(__SSE2__)
struct F4 {
  __m128 v;
};
inline F4 load4(const float* p) { return {_mm_loadu_ps(p)}; }
inline F4 splat4(float x) { return {_mm_set1_ps(x)}; }
inline F4 operator+(F4 a, F4 b) { return {_mm_add_ps(a.v, b.v)}; }
inline F4 operator-(F4 a, F4 b) { return {_mm_sub_ps(a.v, b.v)}; }
inline F4 min4(F4 a, F4 b) { return {_mm_min_ps(a.v, b.v)}; }
inline F4 max4(F4 a, F4 b) { return {_mm_max_ps(a.v, b.v)}; }
inline F4 abs_w4(F4 a) {  // |a.w| in every lane
  const __m128 w = _mm_shuffle_ps(a.v, a.v, _MM_SHUFFLE(3, 3, 3, 3));
  return {_mm_andnot_ps(_mm_set1_ps(-0.0f), w)};
}
inline bool xyz_zero4(F4 a) {
  return (_mm_movemask_ps(_mm_cmpeq_ps(a.v, _mm_setzero_ps())) & 7) == 7;
}
inline void store4(float* p, F4 a) { _mm_storeu_ps(p, a.v); }
// Bin of each lane: (c - lo) * scale clamped to [0, kmax] (NaN to 0), truncated.
inline void bin4(F4 c, F4 lo, F4 scale, float kmax, int* out) {
  const __m128 k = _mm_mul_ps(_mm_sub_ps(c.v, lo.v), scale.v);
  const __m128 kc = _mm_min_ps(_mm_max_ps(k, _mm_setzero_ps()), _mm_set1_ps(kmax));
  _mm_storeu_si128(reinterpret_cast<__m128i*>(out), _mm_cvttps_epi32(kc));
}
#else
struct F4 {
  float v[4];
};
inline F4 load4(const float* p) { return {{p[0], p[1], p[2], p[3]}}; }
inline F4 splat4(float x) { return {{x, x, x, x}}; }
#define FRAMELESS_F4_OP(name, expr)                                   \
  inline F4 name(F4 a, F4 b) {                                        \
    F4 r;                                                             \
    for (int i = 0; i < 4; ++i) r.v[i] = expr;                        \
    return r;                                                         \
  }
FRAMELESS_F4_OP(operator+, a.v[i] + b.v[i])
FRAMELESS_F4_OP(operator-, a.v[i] - b.v[i])
FRAMELESS_F4_OP(min4, a.v[i] < b.v[i] ? a.v[i] : b.v[i])
FRAMELESS_F4_OP(max4, a.v[i] > b.v[i] ? a.v[i] : b.v[i])
#undef FRAMELESS_F4_OP
inline F4 abs_w4(F4 a) { return splat4(std::abs(a.v[3])); }
inline bool xyz_zero4(F4 a) { return a.v[0] == 0.0f && a.v[1] == 0.0f && a.v[2] == 0.0f; }
inline void store4(float* p, F4 a) {
  for (int i = 0; i < 4; ++i) p[i] = a.v[i];
}
inline void bin4(F4 c, F4 lo, F4 scale, float kmax, int* out) {
  for (int i = 0; i < 4; ++i) {
    float k = (c.v[i] - lo.v[i]) * scale.v[i];
    k = k > 0.0f ? k : 0.0f;
    out[i] = int(k < kmax ? k : kmax);
  }
}
#endif

static_assert(sizeof(Sphere) == 4 * sizeof(float), "Sphere must be x, y, z, radius");

// Bounds of one sphere, as Accel::build makes them for build_bvh8: centre +- |radius|, or a point
// at the origin when any bound is not finite (x - x is 0 exactly for finite x).
inline void sphere_box(const Sphere& s, F4& lo, F4& hi) {
  float xyzr[4];
  std::memcpy(xyzr, &s, sizeof xyzr);  // one 16-byte load
  const F4 v = load4(xyzr);
  const F4 r = abs_w4(v);
  lo = v - r;
  hi = v + r;
  if (!xyz_zero4((lo - lo) + (hi - hi))) lo = hi = splat4(0.0f);
}

inline F4 f4(const Vec3& v) {
  const float f[4] = {v.x, v.y, v.z, 0.0f};
  return load4(f);
}

inline Vec3 xyz(F4 a) {
  float f[4];
  store4(f, a);
  return Vec3(f[0], f[1], f[2]);
}

// Running bounds in F4 form.
struct Box4 {
  F4 lo = splat4(kInfinity), hi = splat4(-kInfinity);
  void grow(F4 l, F4 h) {
    lo = min4(lo, l);
    hi = max4(hi, h);
  }
  Box box() const {
    Box b;
    b.lo = xyz(lo);
    b.hi = xyz(hi);
    return b;
  }
  float half_area() const { return box().half_area(); }
};

struct Range {
  uint32_t begin = 0, end = 0;
  Box box;   // bounds of the spheres
  Box cbox;  // bounds of the doubled centres lo + hi (what the bins are laid over)
  uint32_t count() const { return end - begin; }
};

struct BinSet {
  F4 lo[3][kMaxBins], hi[3][kMaxBins];
  uint32_t count[3][kMaxBins];
  explicit BinSet(int k_bins) {
    for (int a = 0; a < 3; ++a)
      for (int k = 0; k < k_bins; ++k) {
        lo[a][k] = splat4(kInfinity);
        hi[a][k] = splat4(-kInfinity);
        count[a][k] = 0;
      }
  }
  void merge(const BinSet& o, int k_bins) {
    for (int a = 0; a < 3; ++a)
      for (int k = 0; k < k_bins; ++k) {
        lo[a][k] = min4(lo[a][k], o.lo[a][k]);
        hi[a][k] = max4(hi[a][k], o.hi[a][k]);
        count[a][k] += o.count[a][k];
      }
  }
  Box box(int a, int k) const {
    Box b;
    b.lo = xyz(lo[a][k]);
    b.hi = xyz(hi[a][k]);
    return b;
  }
};

// Node storage of one subtree: fixed blocks that never move (references stay valid while
// children are added), mapped on demand so untouched pages are never resident, and unmapped as
// soon as they have been copied out.
class NodeArena {
 public:
  static constexpr size_t kBlockNodes = 16384;  // 4 MiB
  NodeArena() = default;
  NodeArena(const NodeArena&) = delete;
  NodeArena& operator=(const NodeArena&) = delete;
  ~NodeArena() {
    for (Bvh8Node* b : blocks_) free_block(b);
  }

  uint32_t add() {
    if (size_ == blocks_.size() * kBlockNodes) blocks_.push_back(new_block());
    const uint32_t i = uint32_t(size_++);
    clear_node(at(i));
    return i;
  }
  Bvh8Node& at(uint32_t i) { return blocks_[i / kBlockNodes][i % kBlockNodes]; }
  size_t size() const { return size_; }

  // Appends the nodes to out with `offset` added to their inner-node references, releasing each
  // block once copied.
  void drain_into(std::vector<Bvh8Node>& out, uint32_t offset) {
    for (size_t b = 0; b < blocks_.size(); ++b) {
      const size_t n = std::min(kBlockNodes, size_ - b * kBlockNodes);
      for (size_t i = 0; i < n; ++i) {
        Bvh8Node node = blocks_[b][i];
        for (int c = 0; c < kBvhWidth; ++c)
          if (node.info[c] == 0 && node.bounds[0][c] <= node.bounds[1][c]) node.child[c] += offset;
        out.push_back(node);
      }
      free_block(blocks_[b]);
      blocks_[b] = nullptr;
    }
    blocks_.clear();
    size_ = 0;
  }

 private:
  static Bvh8Node* new_block() {
#if defined(FRAMELESS_NODE_MMAP)
    void* p = mmap(nullptr, kBlockNodes * sizeof(Bvh8Node), PROT_READ | PROT_WRITE,
                   MAP_PRIVATE | MAP_ANONYMOUS, -1, 0);
    if (p == MAP_FAILED) throw std::bad_alloc();
    return static_cast<Bvh8Node*>(p);
#else
    return static_cast<Bvh8Node*>(::operator new(kBlockNodes * sizeof(Bvh8Node),
                                                 std::align_val_t(alignof(Bvh8Node))));
#endif
  }
  static void free_block(Bvh8Node* b) {
    if (!b) return;
#if defined(FRAMELESS_NODE_MMAP)
    munmap(b, kBlockNodes * sizeof(Bvh8Node));
#else
    ::operator delete(b, std::align_val_t(alignof(Bvh8Node)));
#endif
  }

  std::vector<Bvh8Node*> blocks_;
  size_t size_ = 0;
};

void set_child_box(Bvh8Node& node, int i, const Box& b) {
  for (int a = 0; a < 3; ++a) {
    node.bounds[2 * a][i] = b.lo[a];
    node.bounds[2 * a + 1][i] = b.hi[a];
  }
}

class Builder {
 public:
  // pf: executor for chunked binning of large ranges (top of the tree only), or null.
  Builder(Sphere* spheres, uint16_t* materials, const AccelConfig& config, const ParallelFor* pf)
      : s_(spheres),
        m_(materials),
        max_leaf_(uint32_t(std::clamp(config.max_leaf_size, 1, kMaxLeafSize))),
        bins_(std::clamp(config.sah_bins, 2, kMaxBins)),
        pf_(pf) {}

  bool leaf_ok(const Range& r) const { return r.count() <= max_leaf_; }

  // Bounds and centre bounds of [begin, end), in parallel chunks when allowed.
  Range make_range(uint32_t begin, uint32_t end) const {
    Range r;
    r.begin = begin;
    r.end = end;
    const uint32_t n = end - begin;
    if (pf_ && n >= kParallelBinMin) {
      const size_t chunks = (n + kBinChunk - 1) / kBinChunk;
      std::vector<Range> part(chunks);
      (*pf_)(chunks, [&](size_t c) {
        const uint32_t b = begin + uint32_t(c) * kBinChunk;
        bounds_of(b, std::min(end, b + kBinChunk), part[c]);
      });
      for (const Range& p : part) {
        r.box.grow(p.box);
        r.cbox.grow(p.cbox);
      }
    } else {
      bounds_of(begin, end, r);
    }
    return r;
  }

  // Splits a node's range into at most eight children (same policy as build_bvh8): the largest
  // child that cannot be a leaf is split first; free slots then go to splitting leaves.
  int collect_children(const Range& r, int level, Range* ch) {
    int n = 1;
    ch[0] = r;
    while (n < kBvhWidth) {
      int best = -1;
      float best_area = -1.0f;
      for (int pass = 0; pass < 2 && best < 0; ++pass)
        for (int i = 0; i < n; ++i) {
          const bool want = pass == 0 ? !leaf_ok(ch[i]) : ch[i].count() > 1;
          if (want && ch[i].box.half_area() > best_area)
            best = i, best_area = ch[i].box.half_area();
        }
      if (best < 0) break;
      Range left, right;
      split(ch[best], level, left, right);
      ch[best] = left;
      ch[n++] = right;
    }
    return n;
  }

  // Builds the subtree of r (not a leaf) into arena; returns its node index there.
  uint32_t build(NodeArena& arena, const Range& r, int level) {
    const uint32_t index = uint32_t(arena.add());
    depth = std::max(depth, level);
    Range ch[kBvhWidth];
    const int n = collect_children(r, level, ch);
    for (int i = 0; i < n; ++i) {
      set_child_box(arena.at(index), i, ch[i].box);
      if (leaf_ok(ch[i])) {
        arena.at(index).child[i] = ch[i].begin;
        arena.at(index).info[i] = uint8_t(ch[i].count() | kSphereLeafBit);
        ++leaves;
      } else {
        const uint32_t c = build(arena, ch[i], level + 1);
        arena.at(index).child[i] = c;
      }
    }
    return index;
  }

  int depth = 0;
  size_t leaves = 0;

 private:
  void swap(uint32_t i, uint32_t j) const {
    std::swap(s_[i], s_[j]);
    if (m_) std::swap(m_[i], m_[j]);
  }

  static Vec3 centre2(const Sphere& s) {
    F4 lo, hi;
    sphere_box(s, lo, hi);
    return xyz(lo + hi);
  }

  void bounds_of(uint32_t begin, uint32_t end, Range& r) const {
    Box4 box, cbox;
    for (uint32_t i = begin; i < end; ++i) {
      F4 lo, hi;
      sphere_box(s_[i], lo, hi);
      box.grow(lo, hi);
      const F4 c = lo + hi;
      cbox.grow(c, c);
    }
    r.box = box.box();
    r.cbox = cbox.box();
  }

  void finish(const Range& r, uint32_t mid, Range& left, Range& right) const {
    left = make_range(r.begin, mid);
    right = make_range(mid, r.end);
  }

  // Reorders [begin, end) so that position k holds the sphere whose doubled centre on `axis`
  // would be there after sorting, with no larger one before it and no smaller one after it.
  // Three-way quickselect (runs of equal keys end it at once), pivot the median of three
  // positions drawn from a fixed hash of the range (no sorted-input worst case).
  void select(uint32_t begin, uint32_t end, uint32_t k, int axis) const {
    auto key = [&](uint32_t i) { return centre2(s_[i])[axis]; };
    uint64_t h = (uint64_t(begin) << 32) ^ end ^ 0x9e3779b97f4a7c15ull;
    while (end - begin > 16) {
      const uint32_t n = end - begin;
      float p3[3];
      for (float& p : p3) {
        h ^= h >> 33;
        h *= 0xff51afd7ed558ccdull;
        h ^= h >> 29;
        p = key(begin + uint32_t(h % n));
      }
      const float pivot = std::max(std::min(p3[0], p3[1]), std::min(std::max(p3[0], p3[1]), p3[2]));
      uint32_t lt = begin, i = begin, gt = end;
      while (i < gt) {
        const float v = key(i);
        if (v < pivot) swap(lt++, i++);
        else if (v > pivot) swap(i, --gt);
        else ++i;
      }
      if (k < lt) end = lt;
      else if (k >= gt) begin = gt;
      else return;
    }
    for (uint32_t i = begin + 1; i < end; ++i)  // insertion sort of the last few
      for (uint32_t j = i; j > begin && key(j) < key(j - 1); --j) swap(j, j - 1);
  }

  void bin(uint32_t begin, uint32_t end, const Box& cb, const float* scale, BinSet& out) const {
    const F4 cb_lo = f4(cb.lo);
    const F4 sc = f4(Vec3(scale[0], scale[1], scale[2]));
    const float kmax = float(bins_ - 1);
    for (uint32_t i = begin; i < end; ++i) {
      F4 lo, hi;
      sphere_box(s_[i], lo, hi);
      alignas(16) int k[4];
      bin4(lo + hi, cb_lo, sc, kmax, k);
      for (int a = 0; a < 3; ++a) {
        out.lo[a][k[a]] = min4(out.lo[a][k[a]], lo);
        out.hi[a][k[a]] = max4(out.hi[a][k[a]], hi);
        ++out.count[a][k[a]];
      }
    }
  }

  // Exact SAH for a small range (n <= kSmallSplit, centres not all equal): every split between
  // neighbours in centre order on every axis with an extent is costed; the range is then
  // reordered along the best axis. Past the SAH depth limit: the median on the widest axis.
  // Sorting is by rank (a stable counting of smaller keys: no data-dependent branches).
  void split_small(const Range& r, int level, int axis, Range& left, Range& right) const {
    const uint32_t n = r.count();
    F4 lo[kSmallSplit], hi[kSmallSplit];
    alignas(32) float c[3][kSmallSplit];
    for (uint32_t i = 0; i < n; ++i) {
      sphere_box(s_[r.begin + i], lo[i], hi[i]);
      alignas(16) float f[4];
      store4(f, lo[i] + hi[i]);
      for (int a = 0; a < 3; ++a) c[a][i] = f[a];
    }
    uint8_t order[3][kSmallSplit];
    auto sort_axis = [&](int a) {
      const float* key = c[a];
      for (uint32_t i = 0; i < n; ++i) {
        const float ki = key[i];
        uint32_t rank = 0;
        for (uint32_t j = 0; j < n; ++j) rank += (key[j] < ki) | ((key[j] == ki) & (j < i));
        order[a][rank] = uint8_t(i);
      }
    };
    const Vec3 extent = r.cbox.hi - r.cbox.lo;
    float best_cost = kInfinity;
    int best_axis = -1;
    uint32_t best_i = 0;
    for (int a = 0; a < 3; ++a) {
      if (!(extent[a] > 0.0f) || (level > kSahDepthLimit && a != axis)) continue;
      sort_axis(a);
      if (level > kSahDepthLimit) {
        best_axis = a, best_i = n / 2;
        break;
      }
      const uint8_t* o = order[a];
      float right_area[kSmallSplit];
      Box4 acc;
      for (uint32_t i = n - 1; i > 0; --i) {
        acc.grow(lo[o[i]], hi[o[i]]);
        right_area[i] = acc.half_area();
      }
      acc = Box4();
      for (uint32_t i = 1; i < n; ++i) {
        acc.grow(lo[o[i - 1]], hi[o[i - 1]]);
        const float cost = acc.half_area() * float(i) + right_area[i] * float(n - i);
        if (cost < best_cost) best_cost = cost, best_axis = a, best_i = i;
      }
    }
    if (best_axis < 0) {  // no finite cost (overflowing boxes): median on the widest axis
      best_axis = axis;
      best_i = n / 2;
      sort_axis(axis);
    }
    const uint8_t* o = order[best_axis];
    Sphere tmp_s[kSmallSplit];
    uint16_t tmp_m[kSmallSplit];
    for (uint32_t i = 0; i < n; ++i) {
      tmp_s[i] = s_[r.begin + o[i]];
      if (m_) tmp_m[i] = m_[r.begin + o[i]];
    }
    Box4 box[2], cbox[2];
    for (uint32_t i = 0; i < n; ++i) {
      s_[r.begin + i] = tmp_s[i];
      if (m_) m_[r.begin + i] = tmp_m[i];
      const int side = i < best_i ? 0 : 1;
      box[side].grow(lo[o[i]], hi[o[i]]);
      const F4 ci = lo[o[i]] + hi[o[i]];
      cbox[side].grow(ci, ci);
    }
    left.begin = r.begin;
    left.end = right.begin = r.begin + best_i;
    right.end = r.end;
    left.box = box[0].box();
    left.cbox = cbox[0].box();
    right.box = box[1].box();
    right.cbox = cbox[1].box();
  }

  // Splits r (at least two spheres) into two non-empty ranges.
  void split(const Range& r, int level, Range& left, Range& right) {
    const uint32_t n = r.count();
    const uint32_t mid = r.begin + n / 2;
    const Vec3 extent = r.cbox.hi - r.cbox.lo;
    const int axis =
        extent.x >= extent.y ? (extent.x >= extent.z ? 0 : 2) : (extent.y >= extent.z ? 1 : 2);
    if (!(extent[axis] > 0.0f) || !std::isfinite(extent[axis]))
      return finish(r, mid, left, right);  // all centres equal: any split is as good
    if (n <= kSmallSplit) return split_small(r, level, axis, left, right);
    if (level > kSahDepthLimit) {
      select(r.begin, r.end, mid, axis);
      return finish(r, mid, left, right);
    }
    const int k_bins = bins_;
    float scale[3];
    for (int a = 0; a < 3; ++a)
      scale[a] = extent[a] > 0.0f ? float(k_bins) * 0.99999f / extent[a] : 0.0f;
    BinSet bins(k_bins);
    if (pf_ && n >= kParallelBinMin) {
      const size_t chunks = (n + kBinChunk - 1) / kBinChunk;
      std::vector<BinSet> part(chunks, BinSet(k_bins));
      (*pf_)(chunks, [&](size_t c) {
        const uint32_t b = r.begin + uint32_t(c) * kBinChunk;
        bin(b, std::min(r.end, b + kBinChunk), r.cbox, scale, part[c]);
      });
      for (const BinSet& p : part) bins.merge(p, k_bins);
    } else {
      bin(r.begin, r.end, r.cbox, scale, bins);
    }
    // SAH sweep: cost of splitting between bins k-1 and k, for every axis.
    float best_cost = kInfinity;
    int best_axis = -1, best_k = 0;
    Box best_left, best_right;
    for (int a = 0; a < 3; ++a) {
      if (!(extent[a] > 0.0f)) continue;
      float right_cost[kMaxBins];
      Box right_box[kMaxBins];
      Box acc;
      uint32_t cnt = 0;
      for (int k = k_bins - 1; k > 0; --k) {
        acc.grow(bins.box(a, k));
        cnt += bins.count[a][k];
        right_cost[k] = cnt ? acc.half_area() * float(cnt) : kInfinity;
        right_box[k] = acc;
      }
      acc = Box();
      cnt = 0;
      for (int k = 1; k < k_bins; ++k) {
        acc.grow(bins.box(a, k - 1));
        cnt += bins.count[a][k - 1];
        if (cnt == 0 || cnt == n) continue;
        const float cost = acc.half_area() * float(cnt) + right_cost[k];
        if (cost < best_cost) {
          best_cost = cost, best_axis = a, best_k = k;
          best_left = acc, best_right = right_box[k];
        }
      }
    }
    if (best_axis < 0) {
      select(r.begin, r.end, mid, axis);
      return finish(r, mid, left, right);
    }
    // In-place partition of spheres and materials together; every sphere is classified once (by
    // the same bin computation as the binning), and its centre joins the centre bounds of its
    // side on the way.
    const F4 cb_lo = f4(r.cbox.lo);
    const F4 sc = f4(Vec3(scale[0], scale[1], scale[2]));
    const float kmax = float(k_bins - 1);
    Box4 side[2];  // centre bounds of the left (0) and right (1) part
    uint32_t m = r.begin;
    for (uint32_t i = r.begin; i < r.end; ++i) {  // branch-free Lomuto partition
      const Sphere si = s_[i];
      F4 lo, hi;
      sphere_box(si, lo, hi);
      const F4 c = lo + hi;
      alignas(16) int k[4];
      bin4(c, cb_lo, sc, kmax, k);
      const uint32_t l = k[best_axis] < best_k ? 1u : 0u;
      side[1 - l].grow(c, c);
      s_[i] = s_[m];
      s_[m] = si;
      if (m_) {
        const uint16_t mi = m_[i];
        m_[i] = m_[m];
        m_[m] = mi;
      }
      m += l;
    }
    const uint32_t i = m;
    Box4& lc = side[0];
    Box4& rc = side[1];
    left.begin = r.begin;
    left.end = i;
    left.box = best_left;
    left.cbox = lc.box();
    right.begin = i;
    right.end = r.end;
    right.box = best_right;
    right.cbox = rc.box();
  }

  Sphere* s_;
  uint16_t* m_;
  uint32_t max_leaf_;
  int bins_;
  const ParallelFor* pf_;
};

// A subtree below the top of the tree, built into its own arena.
struct Task {
  Range range;
  int level = 0;
  uint32_t parent = 0;  // top node and slot that refer to it
  int slot = 0;
  NodeArena arena;
  int depth = 0;
  size_t leaves = 0;
};

// The top of the tree: nodes whose ranges are larger than max_task, built breadth-first. A wave
// of one node (the root) splits with chunked parallel binning; a wave of several splits its
// nodes in parallel. Inner children of at most max_task spheres become tasks. Node order (breadth
// first, slots in order) does not depend on the executor.
struct Top {
  const AccelConfig& config;
  Sphere* s;
  uint16_t* m;
  const ParallelFor* pf;
  uint32_t max_task;
  std::vector<Bvh8Node> nodes;
  std::vector<std::unique_ptr<Task>> tasks;
  int depth = 0;
  size_t leaves = 0;

  struct Item {
    Range r;
    uint32_t parent = kInvalidId;  // node and slot that refer to it (none for the root)
    int slot = 0;
    Range ch[kBvhWidth];
    int n = 0;
  };

  void build(const Range& root) {
    const uint32_t max_leaf = uint32_t(std::clamp(config.max_leaf_size, 1, kMaxLeafSize));
    std::vector<Item> wave(1);
    wave[0].r = root;
    for (int level = 1; !wave.empty(); ++level) {
      auto split_one = [&](size_t k, const ParallelFor* p) {
        Builder b(s, m, config, p);
        wave[k].n = b.collect_children(wave[k].r, level, wave[k].ch);
      };
      if (wave.size() == 1 || !pf) {
        for (size_t k = 0; k < wave.size(); ++k) split_one(k, pf);
      } else {
        (*pf)(wave.size(), [&](size_t k) { split_one(k, nullptr); });
      }
      std::vector<Item> next;
      for (const Item& it : wave) {
        const uint32_t index = uint32_t(nodes.size());
        nodes.emplace_back();
        clear_node(nodes[index]);
        if (it.parent != kInvalidId) nodes[it.parent].child[it.slot] = index;
        depth = std::max(depth, level);
        for (int i = 0; i < it.n; ++i) {
          const Range& c = it.ch[i];
          set_child_box(nodes[index], i, c.box);
          if (c.count() <= max_leaf) {
            nodes[index].child[i] = c.begin;
            nodes[index].info[i] = uint8_t(c.count() | kSphereLeafBit);
            ++leaves;
          } else if (c.count() <= max_task) {
            auto t = std::make_unique<Task>();
            t->range = c;
            t->level = level + 1;
            t->parent = index;
            t->slot = i;
            tasks.push_back(std::move(t));
          } else {
            next.emplace_back();
            next.back().r = c;
            next.back().parent = index;
            next.back().slot = i;
          }
        }
      }
      wave.swap(next);
    }
  }
};

}  // namespace

Bvh8 build_bvh8_spheres(std::vector<Sphere>& spheres, std::vector<uint16_t>& materials,
                        const AccelConfig& config) {
  Bvh8 out;
  if (spheres.empty()) return out;
  const uint32_t n = uint32_t(spheres.size());
  // A material array of another size is malformed: leave it alone (as Accel::build does).
  uint16_t* mats = materials.size() == spheres.size() ? materials.data() : nullptr;
  // The split into top and tasks depends on n only, so the layout is the same with or without
  // an executor (and whatever order it runs things in).
  const bool big = n > kParallelMin;
  const bool parallel = bool(config.parallel_for) && big;
  const ParallelFor* pf = parallel ? &config.parallel_for : nullptr;

  Top top{config, spheres.data(), mats, pf, big ? std::max(kMinTask, n / 128) : 0xffffffffu,
          {}, {}, 0, 0};
  top.build(Builder(spheres.data(), mats, config, pf).make_range(0, n));

  // Subtrees: largest first (better balance on a dynamic executor), each into its own arena.
  std::vector<size_t> order(top.tasks.size());
  for (size_t k = 0; k < order.size(); ++k) order[k] = k;
  std::stable_sort(order.begin(), order.end(), [&](size_t a, size_t b) {
    return top.tasks[a]->range.count() > top.tasks[b]->range.count();
  });
  auto build_one = [&](size_t k) {
    Task& t = *top.tasks[order[k]];
    Builder b(spheres.data(), mats, config, nullptr);
    b.build(t.arena, t.range, t.level);
    t.depth = b.depth;
    t.leaves = b.leaves;
  };
  if (parallel && top.tasks.size() > 1) {
    config.parallel_for(top.tasks.size(), build_one);
  } else {
    for (size_t k = 0; k < top.tasks.size(); ++k) build_one(k);
  }

  // Assemble: the top nodes (root first), then each task's nodes in task order. The result is
  // reserved exactly and each arena block is released as soon as it is copied.
  size_t total = top.nodes.size();
  for (const auto& t : top.tasks) total += t->arena.size();
  out.nodes.reserve(total);
  out.depth = top.depth;
  out.leaves = top.leaves;
  size_t offset = top.nodes.size();
  for (const auto& t : top.tasks) {
    top.nodes[t->parent].child[t->slot] = uint32_t(offset);
    offset += t->arena.size();
  }
  out.nodes.insert(out.nodes.end(), top.nodes.begin(), top.nodes.end());
  std::vector<Bvh8Node>().swap(top.nodes);
  for (const auto& t : top.tasks) {
    t->arena.drain_into(out.nodes, uint32_t(out.nodes.size()));
    out.depth = std::max(out.depth, t->depth);
    out.leaves += t->leaves;
  }
  return out;
}

}  // namespace frameless
