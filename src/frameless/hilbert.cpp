// Generalized Hilbert curve after Jakub Cervený's "gilbert" construction (BSD-2): split the
// rectangle along its major axis into two halves (when much longer than wide) or into three
// sub-rectangles (otherwise), choosing even splits so the pieces join by unit steps.
#include "frameless/hilbert.h"

#include <cstdlib>

namespace frameless {
namespace {

int sgn(int v) { return (v > 0) - (v < 0); }
// Python's floor division (the construction relies on it for negative extents).
int floor_half(int v) { return v >= 0 ? v / 2 : -((-v + 1) / 2); }

struct Emitter {
  int width;
  std::vector<uint32_t>& out;
  void put(int x, int y) { out.push_back(uint32_t(y) * uint32_t(width) + uint32_t(x)); }
};

// Fills the rectangle with corner (x, y), major axis (ax, ay) and minor axis (bx, by).
void generate(Emitter& e, int x, int y, int ax, int ay, int bx, int by) {
  const int w = std::abs(ax + ay);
  const int h = std::abs(bx + by);
  const int dax = sgn(ax), day = sgn(ay);  // unit major direction
  const int dbx = sgn(bx), dby = sgn(by);  // unit minor direction
  if (h == 1) {
    for (int i = 0; i < w; ++i, x += dax, y += day) e.put(x, y);
    return;
  }
  if (w == 1) {
    for (int i = 0; i < h; ++i, x += dbx, y += dby) e.put(x, y);
    return;
  }
  int ax2 = floor_half(ax), ay2 = floor_half(ay);
  int bx2 = floor_half(bx), by2 = floor_half(by);
  const int w2 = std::abs(ax2 + ay2);
  const int h2 = std::abs(bx2 + by2);
  if (2 * w > 3 * h) {
    // Long rectangle: two halves along the major axis; prefer an even first half.
    if ((w2 % 2) && w > 2) ax2 += dax, ay2 += day;
    generate(e, x, y, ax2, ay2, bx, by);
    generate(e, x + ax2, y + ay2, ax - ax2, ay - ay2, bx, by);
  } else {
    // Up, across, back down: the standard Hilbert step; prefer an even minor split.
    if ((h2 % 2) && h > 2) bx2 += dbx, by2 += dby;
    generate(e, x, y, bx2, by2, ax2, ay2);
    generate(e, x + bx2, y + by2, ax, ay, bx - bx2, by - by2);
    generate(e, x + (ax - dax) + (bx2 - dbx), y + (ay - day) + (by2 - dby), -bx2, -by2,
             -(ax - ax2), -(ay - ay2));
  }
}

}  // namespace

void append_hilbert_order(int width, int height, std::vector<uint32_t>& out) {
  if (width <= 0 || height <= 0) return;
  out.reserve(out.size() + size_t(width) * size_t(height));
  Emitter e{width, out};
  if (width >= height)
    generate(e, 0, 0, width, 0, 0, height);
  else
    generate(e, 0, 0, 0, height, width, 0);
}

std::vector<uint32_t> hilbert_order(int width, int height) {
  std::vector<uint32_t> out;
  append_hilbert_order(width, height, out);
  return out;
}

}  // namespace frameless
