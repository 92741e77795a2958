// The display image stored along the Hilbert curve: layouts, exports into pixel order, layout changes.
#include "display/slot_image.h"

#include "frameless/hilbert.h"

namespace frameless {

LayoutPtr make_layout(std::shared_ptr<const std::vector<uint32_t>> order, int width, int height) {
  if (!order) return nullptr;
  auto l = std::make_shared<SlotLayout>();
  const size_t n = order->size();
  l->pixel_of = size_t(width) * size_t(height) == n ? hilbert_order(width, height) : *order;
  l->slot_of.resize(n);
  for (size_t s = 0; s < n; ++s) l->slot_of[l->pixel_of[s]] = uint32_t(s);
  l->engine_slot_of.resize(n);
  l->place_of_engine_slot.resize(n);
  for (size_t s = 0; s < n; ++s) {
    l->engine_slot_of[(*order)[s]] = uint32_t(s);
    l->place_of_engine_slot[s] = l->slot_of[(*order)[s]];
  }
  l->engine_order = std::move(order);
  return l;
}

// Converts the whole image into the public layer layout. It walks the pixels in order and
// gathers each from its slot: the writes stream, and the reads of a band of rows stay within
// the few hundred kilobytes of the Hilbert chunks that cover it.
void export_image(const PixelImage& src, DisplayImage& dst) {
  if (dst.width != src.width || dst.height != src.height || dst.epoch.size() != src.pixels() ||
      dst.levels.size() != src.pixels())
    dst.reset(src.width, src.height);
  const size_t n = src.pixels();
  if (src.layout) {
    const uint32_t* slot = src.layout->slot_of.data();
    for (size_t i = 0; i < n; ++i) export_pixel(src, slot[i], dst, i);
  } else {
    for (size_t i = 0; i < n; ++i) export_pixel(src, i, dst, i);
  }
  dst.info = src.info;
}

// Brings `out` (public layers, pixel order) up to `img`: patches the slots changed since the
// image it holds (ticks before `synced`) when img's change history covers them, else rebuilds it.
void sync_public(const PixelImage& img, DisplayImage& out, uint64_t& synced) {
  const uint64_t now = img.info.index + 1;
  if (out.width == img.width && out.height == img.height && img.history.covers(synced, now)) {
    for (uint64_t t = synced; t < now; ++t)
      for (const SlotRun& run : img.history.runs[t % kHistory])
        for (size_t s = run.first, end = size_t(run.first) + run.count; s < end; ++s) {
          // A run is a square of pixels, each layer's lines on as many rows: ask for them ahead.
          if (s + 16 < end) {
            const size_t q = img.pixel_of(s + 16);
            __builtin_prefetch(&out.rgb[3 * q], 1);
            __builtin_prefetch(&out.last_update[q], 1);
            __builtin_prefetch(&out.sample_count[q], 1);
            __builtin_prefetch(&out.variance[q], 1);
            __builtin_prefetch(&out.epoch[q], 1);
            __builtin_prefetch(&out.levels[q], 1);
          }
          export_pixel(img, s, out, img.pixel_of(s));
        }
    out.info = img.info;
  } else {
    export_image(img, out);
  }
  synced = now;
}

// dst <- src with each pixel moved to its slot under `layout` (a layout change, same size).
void remap(const PixelImage& src, PixelImage& dst, LayoutPtr layout) {
  dst.width = src.width;
  dst.height = src.height;
  dst.px = to_new_slots(src.px, src.layout.get(), layout.get());
  dst.rec = to_new_slots(src.rec, src.layout.get(), layout.get());
  dst.layout = std::move(layout);
}

}  // namespace frameless
