// Client side of the pixel stream: which of this process's slots changed since the last batch.
// An UpdateSink over the client's own engine (the display thread's interface, so the same
// counter-driven runs are scanned) that keeps the sequence number each slot was last sent at.
#pragma once
#include <cstdint>
#include <vector>

#include "frameless/engine.h"

namespace frameless::cluster {

class ChangeCollector final : public UpdateSink {
 public:
  // `engine` renders threads [first_thread, first_thread + threads) of its partition.
  ChangeCollector(const Engine& engine, int first_thread, int threads);

  // Collects from `engine` and returns one batch per owned thread (counters read before the
  // scan, so every change they count is in the batch or a later one).
  std::vector<RemoteBatch> take(Engine& engine);

  void begin(const CollectResult& result) override;
  void slots(size_t first, const PixelState* states, size_t count) override;
  void frame(const std::vector<PixelSnapshot>&) override {}

 private:
  int first_thread_, threads_;
  std::vector<size_t> thread_first_slot_;  // of the whole partition, plus the end
  std::vector<uint32_t> sent_seq_;         // per slot of the engine
  UpdateCursor cursor_;
  const std::atomic<uint8_t>* levels_ = nullptr;
  const std::vector<uint32_t>* slot_pixel_ = nullptr;
  std::vector<RemoteBatch>* out_ = nullptr;
};

}  // namespace frameless::cluster
