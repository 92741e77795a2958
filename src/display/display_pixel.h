// The display thread's per-pixel structs (by place): what a pixel shows and the record of its
// newest update, and the marks reprojection leaves; see DisplayImage for the layers' meaning.
#pragma once
#include <cstdint>
#include <vector>

namespace frameless {

// What one displayed pixel shows, as the display thread keeps it (by place): its colour and the
// camera epoch of the update it came from. Reprojection moves it with the content: 16 bytes, so a
// move reads and writes half as much as the whole record would.
struct DisplayPixel {
  float rgb[3] = {0.0f, 0.0f, 0.0f};
  uint32_t epoch = 0;
};
static_assert(sizeof(DisplayPixel) == 16, "four pixels per cache line");

// What the display knows of the newest update blended at a place: its time, sample count,
// variance and reflection/refraction levels (the DisplayImage layers of those names). It describes
// the engine's pixel there, which does not move, so reprojection leaves it in place.
struct PlaceRecord {
  float last_update = -1.0f;
  uint32_t count = 0;
  float variance = 0.0f;
  uint8_t levels = 0;
  uint8_t unused[3] = {0, 0, 0};
};
static_assert(sizeof(PlaceRecord) == 16, "four records per cache line");

// What reprojection left in a pixel (one byte per slot): its content was moved there from
// another pixel, copied from a neighbour to close a crack, guessed for a disocclusion, or shows
// something that may have moved since. The last three are guesses: the next sample replaces them.
enum PixelMark : uint8_t {
  kMarkNone = 0,
  kMarkMoved = 1,
  kMarkFilled = 2,
  kMarkDisoccluded = 4,
  kMarkStale = 8,
  kMarkUnknown = 16,  // a disocclusion with nothing nearby to guess from: it shows its old content
};
inline constexpr uint8_t kMarkGuess = kMarkFilled | kMarkDisoccluded | kMarkStale;

// How many displayed pixels show each camera epoch (the coverage figure), for the newest kRing
// epochs (older ones are never the newest). Display thread.
struct EpochCensus {
  static constexpr uint32_t kRing = 4096;
  std::vector<uint32_t> tag, count;

  void clear() {
    tag.assign(kRing, 0);
    count.assign(kRing, 0);
  }
  void add(uint32_t e, uint32_t pixels = 1) {
    if (e == 0) return;
    if (tag[e % kRing] != e) tag[e % kRing] = e, count[e % kRing] = 0;
    count[e % kRing] += pixels;
  }
  // Moves one pixel from epoch `from` to `to`.
  void move(uint32_t from, uint32_t to) {
    if (from == to) return;
    if (from != 0 && tag[from % kRing] == from) --count[from % kRing];
    add(to);
  }
  uint32_t of(uint32_t e) const { return tag.empty() || tag[e % kRing] != e ? 0 : count[e % kRing]; }
};

}  // namespace frameless
