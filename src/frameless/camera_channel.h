// Epoch-numbered camera mailbox: the input side publishes, render threads poll; any thread.
#pragma once
#include <atomic>
#include <cstdint>

#include "core/scene/camera.h"

namespace frameless {

// Single-slot sequence-locked camera. publish() never waits for readers; concurrent publishers
// are serialised by a tiny spin flag (publishing is rare). Readers never block a publisher.
class CameraChannel {
 public:
  explicit CameraChannel(const Camera& initial = {});

  // Stores `camera` and returns its epoch (1 for the initial camera, then +1 per publish).
  uint32_t publish(const Camera& camera);
  // Stores `camera` under a given epoch (a cluster client mirrors its master's numbering, which
  // may skip epochs); returns 0 and changes nothing unless epoch > epoch().
  uint32_t publish_as(const Camera& camera, uint32_t epoch);
  // Epoch of the newest camera (cheap: one relaxed-acquire load).
  uint32_t epoch() const { return epoch_.load(std::memory_order_acquire); }
  // Consistent copy of the newest camera and its epoch.
  Camera read(uint32_t* epoch = nullptr) const;

 private:
  uint32_t store(const Camera& camera, uint32_t epoch);  // epoch 0: the next one

  std::atomic<uint32_t> seq_{0};
  std::atomic<uint32_t> epoch_{1};
  std::atomic<float> data_[10];  // eye xyz, look xyz, up xyz, fov
  std::atomic_flag writing_ = ATOMIC_FLAG_INIT;
};

}  // namespace frameless
