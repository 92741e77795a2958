// Partition: per-thread counts within one chunk; disjoint union covering the image.
#include "frameless/partition.h"

#include <gtest/gtest.h>

#include <cstdlib>

#include <algorithm>

namespace frameless {
namespace {

// Empty string when the partition is valid.
std::string problems(const Partition& p, int chunk) {
  std::vector<uint8_t> seen(size_t(p.width) * size_t(p.height), 0);
  size_t lo = SIZE_MAX, hi = 0;
  for (const auto& list : p.pixels) {
    lo = std::min(lo, list.size());
    hi = std::max(hi, list.size());
    for (uint32_t i : list) {
      if (i >= seen.size()) return "pixel out of range";
      if (seen[i]++) return "pixel owned twice";
    }
  }
  if (std::count(seen.begin(), seen.end(), 0)) return "pixel unowned";
  if (hi - lo > size_t(chunk)) return "unbalanced";
  return "";
}

TEST(Partition, BalancedDisjointCover) {
  for (PixelOrder order : {PixelOrder::hilbert_shuffled, PixelOrder::hilbert, PixelOrder::scanline,
                           PixelOrder::random})
    for (auto [w, h] : {std::pair{1, 1}, {7, 3}, {64, 64}, {333, 77}, {200, 150}})
      for (int threads : {1, 2, 3, 7, 16})
        for (int chunk : {1, 5, 64, 1000}) {
          const Partition p = make_partition({w, h, threads, chunk, order, 42});
          ASSERT_EQ(int(p.pixels.size()), threads);
          EXPECT_EQ(problems(p, chunk), "") << to_string(order) << " " << w << "x" << h << " t"
                                            << threads << " c" << chunk;
        }
}

// The render loop ends a packet at each chunk start, found by walking chunk lengths: they must
// tile every list exactly, and each chunk must be a run of the Hilbert line (consecutive pixels
// of one unshuffled chunk sit next to each other in the image).
TEST(Partition, ChunkLengthsTileEveryList) {
  for (auto [w, h] : {std::pair{7, 3}, {64, 64}, {333, 77}, {200, 150}})
    for (int threads : {1, 2, 3, 7})
      for (int chunk : {1, 5, 64}) {
        const Partition p = make_partition({w, h, threads, chunk, PixelOrder::hilbert_shuffled, 42});
        int short_chunks = 0;
        for (int t = 0; t < threads; ++t) {
          const auto& list = p.pixels[size_t(t)];
          size_t pos = 0;
          while (pos < list.size()) {
            const size_t len = p.chunk_length(t, pos);
            ASSERT_GT(len, 0u);
            short_chunks += len < size_t(chunk);
            for (size_t k = pos + 1; k < pos + len && k < list.size(); ++k) {
              const int dx = int(list[k] % uint32_t(w)) - int(list[k - 1] % uint32_t(w));
              const int dy = int(list[k] / uint32_t(w)) - int(list[k - 1] / uint32_t(w));
              ASSERT_LE(std::abs(dx) + std::abs(dy), 2) << w << "x" << h << " c" << chunk;
            }
            pos += len;
          }
          EXPECT_EQ(pos, list.size()) << w << "x" << h << " t" << threads << " c" << chunk;
        }
        EXPECT_EQ(short_chunks, (w * h) % chunk != 0 ? 1 : 0) << w << "x" << h << " c" << chunk;
      }
}

TEST(Partition, ShuffleIsSeededAndChangesOrder) {
  const PartitionConfig c{64, 48, 3, 16, PixelOrder::hilbert_shuffled, 7};
  EXPECT_EQ(make_partition(c).pixels, make_partition(c).pixels);
  PartitionConfig other = c;
  other.seed = 8;
  EXPECT_NE(make_partition(c).pixels, make_partition(other).pixels);
  PartitionConfig plain = c;
  plain.order = PixelOrder::hilbert;
  EXPECT_NE(make_partition(c).pixels, make_partition(plain).pixels);
}

TEST(Partition, ValidatorBitesOnBadPartitions) {
  Partition p = make_partition({16, 16, 2, 4, PixelOrder::hilbert, 1});
  Partition dup = p;
  dup.pixels[0].push_back(dup.pixels[1][0]);
  EXPECT_NE(problems(dup, 4), "");
  Partition skewed = p;
  for (int k = 0; k < 8; ++k) {
    skewed.pixels[0].push_back(skewed.pixels[1].back());
    skewed.pixels[1].pop_back();
  }
  EXPECT_EQ(problems(skewed, 4), "unbalanced");
}

TEST(Partition, ParsesOrderNames) {
  EXPECT_EQ(parse_pixel_order("hilbert-shuffled"), PixelOrder::hilbert_shuffled);
  EXPECT_EQ(parse_pixel_order("scanline"), PixelOrder::scanline);
  EXPECT_FALSE(parse_pixel_order("zigzag"));
}

}  // namespace
}  // namespace frameless
