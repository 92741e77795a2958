// The display thread's own image, stored along the generalized Hilbert curve (SlotLayout): the
// layout, the per-tick change lists, and the export into the public DisplayImage layers (pixel
// order). Display thread only.
#pragma once
#include <cstdint>
#include <cstring>
#include <memory>
#include <vector>

#include "display/display_image.h"
#include "display/display_pixel.h"
#include "display/reproject.h"
#include "display/stream_copy.h"

namespace frameless {

constexpr uint64_t kHistory = 8;       // ticks of change lists kept (buffers and consumers catch up from them)

// Where the display keeps each pixel, and the engine's slot order it receives updates in. The
// display stores its image along the generalized Hilbert curve (frameless/hilbert.h), not in the
// engine's slot order: the engine's 64-pixel chunks are runs of that curve, so each chunk's slots
// are still 64 consecutive places (a tick's blend and its copies stay runs), while the engine's
// shuffle of the chunks would scatter a pixel's neighbours over the whole image (reprojection
// moves each pixel a few pixels: along the curve it reads places nearby). "Slot" below means the
// display's place; the engine's slots are named so.
struct SlotLayout {
  std::shared_ptr<const std::vector<uint32_t>> engine_order;  // engine slot -> pixel (shared with the engine)
  std::vector<uint32_t> pixel_of;                             // place -> pixel (the curve)
  std::vector<uint32_t> slot_of;                              // pixel -> place
  std::vector<uint32_t> place_of_engine_slot;                 // engine slot -> place
  std::vector<uint32_t> engine_slot_of;                       // pixel -> engine slot
};
using LayoutPtr = std::shared_ptr<const SlotLayout>;  // null: place, engine slot and pixel coincide

// A run of consecutive places changed in one tick.
struct SlotRun {
  uint32_t first = 0;
  uint32_t count = 0;
};

// What the last kHistory ticks changed: tick t's slot runs in runs[t % kHistory], or full[...]
// when it changed (or cleared, or re-laid out) the whole image, or moved[...] when a reprojection
// moved what every place shows while the records (which stay in place) changed only in the runs.
// Ticks before `newest` are recorded.
struct ChangeHistory {
  std::vector<SlotRun> runs[kHistory];
  bool full[kHistory] = {};
  bool moved[kHistory] = {};
  uint64_t newest = 0;

  // Whether an image holding ticks before `have` can be brought to ticks before `now` from runs.
  bool covers(uint64_t have, uint64_t now) const { return covers_records(have, now) && !moved_in(have, now); }
  // The same for the records alone: what each place shows may have moved since.
  bool covers_records(uint64_t have, uint64_t now) const {
    if (have == 0 || have > now || now > newest || have + kHistory < newest) return false;
    for (uint64_t t = have; t < now; ++t)
      if (full[t % kHistory]) return false;
    return true;
  }

 private:
  bool moved_in(uint64_t have, uint64_t now) const {
    for (uint64_t t = have; t < now; ++t)
      if (moved[t % kHistory]) return true;
    return false;
  }
};

// The display thread's image: the DisplayImage layers interleaved per pixel in two arrays (what
// each place shows, and its newest update's record), stored by place.
struct PixelImage {
  int width = 0;
  int height = 0;
  LayoutPtr layout;
  std::vector<DisplayPixel> px;   // what each place shows (reprojection moves it)
  std::vector<PlaceRecord> rec;   // each place's newest update (stays in place)
  FrameInfo info;
  ChangeHistory history;  // the display's change history when this image was published
  // Denoising (BlendConfig::denoise): each pixel's guides at this tick, in pixel order (empty:
  // show the image unfiltered), and the filter's passes.
  std::vector<PointGuide> guides;
  int denoise_iterations = 0;
  // igi's discontinuity buffer (BlendConfig::discontinuity): each pixel's mean indirect light,
  // in pixel order, and the interleaving window n (0: off). It reads the same guides.
  std::vector<Vec3> indirect;
  int discontinuity = 0;

  size_t pixels() const { return size_t(width) * size_t(height); }
  // Places [first, first + count) of `src` (same size) copied in: what they show and their records.
  void copy_places(const PixelImage& src, size_t first, size_t count) {
    copy_pixels(src, first, count);
    copy_records(src, first, count);
  }
  // Runs (a tick's few places) go through the caches; whole images stream (stream_copy.h).
  void copy_pixels(const PixelImage& src, size_t first, size_t count) {
    copy(&px[first], &src.px[first], count * sizeof(DisplayPixel));
  }
  void copy_records(const PixelImage& src, size_t first, size_t count) {
    copy(&rec[first], &src.rec[first], count * sizeof(PlaceRecord));
  }
  static void copy(void* dst, const void* src, size_t bytes) {
    if (bytes >= (size_t(1) << 20)) return stream_copy(dst, src, bytes);
    std::memcpy(dst, src, bytes);
  }
  uint32_t pixel_of(size_t slot) const { return layout ? layout->pixel_of[slot] : uint32_t(slot); }
  uint32_t slot_of(size_t pixel) const { return layout ? layout->slot_of[pixel] : uint32_t(pixel); }
  // The engine's slots: where the update of engine slot s is kept, and pixel p's engine slot.
  uint32_t place_of_engine_slot(size_t s) const { return layout ? layout->place_of_engine_slot[s] : uint32_t(s); }
  uint32_t engine_slot_of(size_t pixel) const { return layout ? layout->engine_slot_of[pixel] : uint32_t(pixel); }
  void reset(int w, int h, LayoutPtr l) {
    width = w;
    height = h;
    layout = std::move(l);
    px.assign(pixels(), DisplayPixel{});
    rec.assign(pixels(), PlaceRecord{});
  }
  // With the display's points and marks (which live outside the triple buffer: only the display
  // thread reads them), for reprojection.
  SlotImage slots(std::vector<ViewPoint>& points, std::vector<uint8_t>& marks,
                  const PixelPoint* engine_points = nullptr) {
    return {width,       height,        layout ? layout->pixel_of.data() : nullptr,
            layout ? layout->slot_of.data() : nullptr,
            px.data(),   points.data(), marks.data(), engine_points};
  }
  // The same as a reprojection's source, which reads the pixels only (the newest image stays
  // as it is for its readers).
  SlotImage slots(std::vector<ViewPoint>& points, std::vector<uint8_t>& marks,
                  const PixelPoint* engine_points) const {
    SlotImage s = const_cast<PixelImage*>(this)->slots(points, marks, engine_points);
    return s;
  }
};

// Writes the layers of slot `s` of `src` into pixel i of `dst`.
inline void export_pixel(const PixelImage& src, size_t s, DisplayImage& dst, size_t i) {
  const DisplayPixel& p = src.px[s];
  const PlaceRecord& r = src.rec[s];
  dst.rgb[3 * i] = p.rgb[0];
  dst.rgb[3 * i + 1] = p.rgb[1];
  dst.rgb[3 * i + 2] = p.rgb[2];
  dst.last_update[i] = r.last_update;
  dst.sample_count[i] = r.count;
  dst.variance[i] = r.variance;
  dst.epoch[i] = p.epoch;
  dst.levels[i] = r.levels;
}

// `by_slot` (one entry per slot of `from`) with each pixel's entry moved to its slot under `to`
// (a layout change, same size; null layouts: slot s is pixel s). `engine`: the entries are by
// engine slot (else by the display's place).
template <typename T>
std::vector<T> to_new_slots(const std::vector<T>& by_slot, const SlotLayout* from, const SlotLayout* to,
                            bool engine = false) {
  std::vector<T> out(by_slot.size());
  for (size_t s = 0; s < out.size(); ++s) {
    const uint32_t pixel = !to ? uint32_t(s) : engine ? (*to->engine_order)[s] : to->pixel_of[s];
    out[s] = by_slot[!from ? pixel : engine ? from->engine_slot_of[pixel] : from->slot_of[pixel]];
  }
  return out;
}

// The layout of a width x height image whose engine visits pixels in `order` (null: none).
LayoutPtr make_layout(std::shared_ptr<const std::vector<uint32_t>> order, int width, int height);

// Converts the whole image into the public layer layout. It walks the pixels in order and
// gathers each from its slot: the writes stream, and the reads of a band of rows stay within
// the few hundred kilobytes of the Hilbert chunks that cover it.
void export_image(const PixelImage& src, DisplayImage& dst);

// Brings `out` (public layers, pixel order) up to `img`: patches the slots changed since the
// image it holds (ticks before `synced`) when img's change history covers them, else rebuilds it;
// across reprojections it rebuilds the colour and epoch layers and patches the others.
void sync_public(const PixelImage& img, DisplayImage& out, uint64_t& synced);

// dst <- src with each pixel moved to its slot under `layout` (a layout change, same size).
void remap(const PixelImage& src, PixelImage& dst, LayoutPtr layout);

}  // namespace frameless
