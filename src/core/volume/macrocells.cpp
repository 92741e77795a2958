// Macrocell ranges, one z-slab of macrocells per task of the caller's executor.
#include "core/volume/macrocells.h"

#include <algorithm>
#include <bit>

namespace frameless {

Macrocells build_macrocells(const VolumeGrid& g, int size, const ParallelFor& pf) {
  Macrocells m;
  m.size = int(std::bit_floor(unsigned(std::max(size, 1))));  // a power of two: the walks shift
  size = m.size;
  m.mx = (g.nx - 2) / size + 1;  // cells: n - 1 per side
  m.my = (g.ny - 2) / size + 1;
  m.mz = (g.nz - 2) / size + 1;
  const size_t count = size_t(m.mx) * size_t(m.my) * size_t(m.mz);
  m.lo.assign(count, kInfinity);
  m.hi.assign(count, -kInfinity);
  with_voxels(g, [&](const auto& v) {
    const auto slab = [&](int c) {  // macrocells with z index c
      const int z0 = c * size, z1 = std::min(g.nz - 1, z0 + size);
      for (int z = z0; z <= z1; ++z)
        for (int y = 0; y < g.ny; ++y) {
          // A voxel on a macrocell boundary belongs to both neighbours.
          const int by0 = std::max(0, (y - 1) / size), by1 = std::min(m.my - 1, y / size);
          for (int b = 0; b < m.mx; ++b) {
            const int x0 = b * size, x1 = std::min(g.nx - 1, x0 + size);
            float lo = v(x0, y, z), hi = lo;
            for (int x = x0 + 1; x <= x1; ++x) {
              lo = std::min(lo, v(x, y, z));
              hi = std::max(hi, v(x, y, z));
            }
            for (int by = by0; by <= by1; ++by) {
              const size_t i = m.index(b, by, c);
              m.lo[i] = std::min(m.lo[i], lo);
              m.hi[i] = std::max(m.hi[i], hi);
            }
          }
        }
    };
    parallel_for_each(pf, size_t(m.mz), [&](size_t c) { slab(int(c)); });  // slabs write apart
  });
  return m;
}

}  // namespace frameless
