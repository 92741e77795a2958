// Marching tetrahedra over the cells whose macrocell holds the isovalue.
#include "core/volume/marching_tetrahedra.h"

#include <algorithm>

#include "core/volume/isosurface.h"
#include "core/volume/trilinear.h"

namespace frameless {
namespace {

// The cube's corners (x + 2y + 4z) of its six tetrahedra around the diagonal 0-7.
constexpr int kTets[6][4] = {{0, 1, 3, 7}, {0, 3, 2, 7}, {0, 2, 6, 7}, {0, 6, 4, 7}, {0, 4, 5, 7}, {0, 5, 1, 7}};

struct Builder {
  const VolumeGrid& g;
  float iso;
  bool inside_above;
  IsoMesh out;

  Vec3 normal(const Vec3& p) const {
    const Vec3 grad = trilinear_gradient(g, p);
    const float len = glm::length(grad);
    return len > 0.0f ? (inside_above ? -grad : grad) / len : Vec3(0.0f, 0.0f, 1.0f);
  }

  // The triangle (a, b, c) wound so that its face normal points out of the inside.
  void emit(Vec3 a, Vec3 b, Vec3 c, const Vec3& outward) {
    if (glm::dot(glm::cross(b - a, c - a), outward) < 0.0f) std::swap(b, c);
    for (const Vec3& p : {a, b, c}) {
      out.positions.push_back(p);
      out.normals.push_back(normal(p));
    }
  }

  void tetrahedron(const Vec3 (&p)[4], const float (&v)[4]) {
    int in[4], out_[4], ni = 0, no = 0;
    for (int k = 0; k < 4; ++k) {
      const bool inside = inside_above ? v[k] > iso : v[k] < iso;
      (inside ? in[ni++] : out_[no++]) = k;
    }
    if (ni == 0 || no == 0) return;
    const auto cut = [&](int a, int b) {  // the crossing on edge a-b
      const float t = (iso - v[a]) / (v[b] - v[a]);
      return p[a] + std::clamp(t, 0.0f, 1.0f) * (p[b] - p[a]);
    };
    // Outward: from the inside corners' mean towards the outside corners' mean.
    Vec3 ci(0.0f), co(0.0f);
    for (int k = 0; k < ni; ++k) ci += p[in[k]];
    for (int k = 0; k < no; ++k) co += p[out_[k]];
    const Vec3 outward = co / float(no) - ci / float(ni);
    if (ni == 1 || no == 1) {  // one corner apart: a triangle around it
      const int lone = ni == 1 ? in[0] : out_[0];
      const int* rest = ni == 1 ? out_ : in;
      emit(cut(lone, rest[0]), cut(lone, rest[1]), cut(lone, rest[2]), outward);
    } else {  // two and two: a quad
      const Vec3 a = cut(in[0], out_[0]), b = cut(in[0], out_[1]), c = cut(in[1], out_[1]), d = cut(in[1], out_[0]);
      emit(a, b, c, outward);
      emit(a, c, d, outward);
    }
  }

  void cell(int x, int y, int z) {
    Vec3 cp[8];
    float cv[8];
    with_voxels(g, [&](const auto& v) { v.corners(x, y, z, cv); });
    float lo = kInfinity, hi = -kInfinity;
    for (int c = 0; c < 8; ++c) {
      cp[c] = Vec3(float(x + (c & 1)), float(y + ((c >> 1) & 1)), float(z + ((c >> 2) & 1)));
      lo = std::min(lo, cv[c]);
      hi = std::max(hi, cv[c]);
    }
    if (!(lo <= iso && iso <= hi)) return;
    for (const auto& t : kTets) {
      const Vec3 p[4] = {cp[t[0]], cp[t[1]], cp[t[2]], cp[t[3]]};
      const float v[4] = {cv[t[0]], cv[t[1]], cv[t[2]], cv[t[3]]};
      tetrahedron(p, v);
    }
  }
};

}  // namespace

IsoMesh marching_tetrahedra(const VolumeGrid& g, const Macrocells& m, float iso, bool inside_above,
                            const ParallelFor& pf) {
  std::vector<Builder> parts(size_t(m.mz), Builder{g, iso, inside_above, {}});  // one per z-slab
  parallel_for_each(pf, size_t(m.mz), [&](size_t cz) {
    Builder& b = parts[cz];
    for (int cy = 0; cy < m.my; ++cy)
      for (int cx = 0; cx < m.mx; ++cx) {
        const size_t i = m.index(cx, cy, int(cz));
        if (!(m.lo[i] <= iso && iso <= m.hi[i])) continue;
        for (int z = int(cz) * m.size; z < std::min((int(cz) + 1) * m.size, g.nz - 1); ++z)
          for (int y = cy * m.size; y < std::min((cy + 1) * m.size, g.ny - 1); ++y)
            for (int x = cx * m.size; x < std::min((cx + 1) * m.size, g.nx - 1); ++x) b.cell(x, y, z);
      }
  });
  IsoMesh all;
  for (Builder& b : parts) {
    all.positions.insert(all.positions.end(), b.out.positions.begin(), b.out.positions.end());
    all.normals.insert(all.normals.end(), b.out.normals.begin(), b.out.normals.end());
  }
  return all;
}

}  // namespace frameless
