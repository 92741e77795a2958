// A test UpdateSink that turns each collection into a list of (pixel, snapshot) pairs, each
// pixel at most once per new sample: what a display would blend, without the display.
#pragma once
#include <vector>

#include "frameless/engine.h"

namespace frameless::testing {

struct CollectedPixel {
  uint32_t pixel = 0;  // y * width + x
  PixelSnapshot state;
};

class CollectingSink final : public UpdateSink {
 public:
  std::vector<CollectedPixel> updates;  // this collection's new samples
  uint64_t contended = 0;               // slots skipped because the owner kept writing them

  void begin(const CollectResult& r) override {
    updates.clear();
    order_ = r.slot_pixel;
    const size_t n = size_t(r.width) * size_t(r.height);
    if (r.reset || last_seq_.size() != n) last_seq_.assign(n, 0);
  }
  void slots(size_t first, const PixelState* states, size_t count) override {
    PixelSnapshot s;
    for (size_t i = 0; i < count; ++i) {
      if (!read_pixel(states[i], s)) {
        ++contended;
        continue;
      }
      const uint32_t pixel = order_ ? (*order_)[first + i] : uint32_t(first + i);
      if (s.epoch == 0 || s.seq == last_seq_[pixel]) continue;
      last_seq_[pixel] = s.seq;
      updates.push_back({pixel, s});
    }
  }
  void frame(const std::vector<PixelSnapshot>& pixels) override {
    for (size_t i = 0; i < pixels.size(); ++i)
      if (pixels[i].epoch != 0) updates.push_back({uint32_t(i), pixels[i]});
  }

 private:
  std::shared_ptr<const std::vector<uint32_t>> order_;
  std::vector<uint32_t> last_seq_;  // per pixel: sequence number last collected
};

}  // namespace frameless::testing
