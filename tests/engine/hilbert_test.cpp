// Generalized Hilbert curve: every pixel once, unit steps except the one parity-forced diagonal.
#include "frameless/hilbert.h"

#include <gtest/gtest.h>

#include <cstdlib>
#include <vector>

namespace frameless {
namespace {

struct Walk {
  bool each_once = true;
  int diagonals = 0;  // steps to a corner neighbour
  int jumps = 0;      // steps to anything that is not a neighbour
};

Walk check(const std::vector<uint32_t>& order, int w, int h) {
  Walk r;
  std::vector<uint8_t> seen(size_t(w) * size_t(h), 0);
  if (order.size() != seen.size()) r.each_once = false;
  for (size_t i = 0; i < order.size(); ++i) {
    if (order[i] >= seen.size() || seen[order[i]]++) r.each_once = false;
    if (i == 0) continue;
    const int dx = std::abs(int(order[i] % w) - int(order[i - 1] % w));
    const int dy = std::abs(int(order[i] / w) - int(order[i - 1] / w));
    if (dx == 1 && dy == 1)
      ++r.diagonals;
    else if (dx + dy != 1)
      ++r.jumps;
  }
  return r;
}

// Parity: a unit-step path alternates checkerboard colours, so it cannot join two same-coloured
// corners of the long side when the long side is odd and the pixel count even.
bool diagonal_allowed(int w, int h) {
  const int lo = std::min(w, h), hi = std::max(w, h);
  return hi % 2 == 1 && lo % 2 == 0;
}

void expect_curve(int w, int h) {
  const Walk r = check(hilbert_order(w, h), w, h);
  EXPECT_TRUE(r.each_once) << w << "x" << h;
  EXPECT_EQ(r.jumps, 0) << w << "x" << h;
  EXPECT_LE(r.diagonals, diagonal_allowed(w, h) ? 1 : 0) << w << "x" << h;
}

TEST(Hilbert, EverySizeUpTo64) {
  for (int w = 1; w <= 64; ++w)
    for (int h = 1; h <= 64; ++h) expect_curve(w, h);
}

TEST(Hilbert, LargeAndDegenerateSizes) {
  for (auto [w, h] : {std::pair{1920, 1080}, {1, 1000}, {1000, 1}, {333, 777}, {4096, 2160}})
    expect_curve(w, h);
}

TEST(Hilbert, DiagonalOccursOnlyWhereParityForcesIt) {
  EXPECT_EQ(check(hilbert_order(4, 5), 4, 5).diagonals, 1);
  EXPECT_EQ(check(hilbert_order(64, 27), 64, 27).diagonals, 0);
}

TEST(Hilbert, CheckerBitesOnScanlineOrder) {
  // Scanline order jumps at every row end: the checks above must notice.
  std::vector<uint32_t> scan(12);
  for (uint32_t i = 0; i < 12; ++i) scan[i] = i;
  EXPECT_GT(check(scan, 4, 3).jumps, 0);
  scan[5] = 4;  // a duplicate
  EXPECT_FALSE(check(scan, 4, 3).each_once);
}

}  // namespace
}  // namespace frameless
