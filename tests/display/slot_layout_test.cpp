// The display's storage layout (display/slot_image.h): its image lies along the Hilbert curve,
// each of the engine's 64-pixel chunks a run of places, with exact maps between pixels, places
// and the engine's slots.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdlib>
#include <memory>
#include <vector>

#include "display/slot_image.h"
#include "frameless/partition.h"

namespace frameless::test {
namespace {

std::shared_ptr<const std::vector<uint32_t>> engine_order(int w, int h, int threads, PixelOrder order) {
  PartitionConfig c;
  c.width = w, c.height = h, c.threads = threads, c.order = order;
  return std::make_shared<const std::vector<uint32_t>>(slot_order(make_partition(c)));
}

TEST(SlotLayout, MapsPixelsPlacesAndEngineSlotsBothWays) {
  for (const auto& [w, h] : {std::pair{100, 60}, std::pair{33, 7}, std::pair{1, 1}}) {
    const auto order = engine_order(w, h, 3, PixelOrder::hilbert_shuffled);
    const LayoutPtr l = make_layout(order, w, h);
    const size_t n = size_t(w) * size_t(h);
    ASSERT_EQ(l->pixel_of.size(), n);
    std::vector<int> seen(n, 0);
    for (size_t place = 0; place < n; ++place) {
      ++seen[l->pixel_of[place]];
      EXPECT_EQ(l->slot_of[l->pixel_of[place]], place);
    }
    EXPECT_EQ(std::count(seen.begin(), seen.end(), 1), ptrdiff_t(n)) << "every pixel has one place";
    for (size_t s = 0; s < n; ++s) {
      EXPECT_EQ(l->pixel_of[l->place_of_engine_slot[s]], (*order)[s]) << "engine slot " << s;
      EXPECT_EQ(l->engine_slot_of[(*order)[s]], s);
    }
  }
  EXPECT_EQ(make_layout(nullptr, 4, 4), nullptr);
}

// What the layout is for: the engine's chunks stay runs (a tick's blend writes runs), and a
// pixel's neighbours lie near it (reprojection moves pixels a few pixels). The engine's own slot
// order, a shuffle of the chunks, fails the second.
TEST(SlotLayout, ChunksAreRunsAndNeighboursAreNear) {
  const int w = 320, h = 180, threads = 2;
  const auto order = engine_order(w, h, threads, PixelOrder::hilbert_shuffled);
  const LayoutPtr l = make_layout(order, w, h);
  const size_t n = size_t(w) * size_t(h);
  size_t breaks = 0;
  for (size_t s = 1; s < n; ++s) breaks += l->place_of_engine_slot[s] != l->place_of_engine_slot[s - 1] + 1;
  EXPECT_LE(breaks, n / 64 + size_t(threads)) << "one break a chunk at most";
  // The share of horizontal neighbours more than 4096 places apart (two pages of pixels): along
  // the curve only the edges of its large blocks; in slot order every edge between two chunks.
  const auto far_share = [&](const std::vector<uint32_t>& place_of_pixel) {
    size_t far = 0, pairs = 0;
    for (int y = 0; y < h; ++y)
      for (int x = 0; x + 1 < w; ++x, ++pairs) {
        const size_t p = size_t(y) * size_t(w) + size_t(x);
        far += std::abs(int64_t(place_of_pixel[p + 1]) - int64_t(place_of_pixel[p])) > 4096;
      }
    return double(far) / double(pairs);
  };
  EXPECT_LT(far_share(l->slot_of), 0.03);
  EXPECT_GT(far_share(l->engine_slot_of), 0.06) << "the engine's order scatters neighbours";
}

// A layout change of the engine (another thread count) keeps every pixel's place: only the map
// from the engine's slots changes.
TEST(SlotLayout, PlacesDependOnTheSizeAlone) {
  const LayoutPtr a = make_layout(engine_order(64, 48, 2, PixelOrder::hilbert_shuffled), 64, 48);
  const LayoutPtr b = make_layout(engine_order(64, 48, 5, PixelOrder::scanline), 64, 48);
  EXPECT_EQ(a->pixel_of, b->pixel_of);
  EXPECT_NE(a->place_of_engine_slot, b->place_of_engine_slot);
}

}  // namespace
}  // namespace frameless::test
