// Epoch-numbered mailbox for what moves (dynamic objects, lights, materials): the application
// side publishes, render threads poll at the update percentage like the camera; any thread.
#pragma once
#include <atomic>
#include <cstdint>
#include <memory>
#include <vector>

namespace frameless {

// A fixed-size float record behind a sequence lock (the camera channel's protocol at any size).
// publish() never waits for readers; concurrent publishers are serialised by a spin flag.
// Readers never block a publisher and never write: a torn read is retried.
class WorldChannel {
 public:
  explicit WorldChannel(const std::vector<float>& initial);

  size_t size() const { return n_; }
  // Stores data[0, n) (n must equal size(), else nothing happens and 0 is returned) and
  // returns its epoch (1 for the initial record, then +1 per publish).
  uint32_t publish(const float* data, size_t n);
  uint32_t epoch() const { return epoch_.load(std::memory_order_acquire); }
  // Consistent copy of the newest record into out (resized to size()); returns its epoch.
  uint32_t read(std::vector<float>& out) const;

 private:
  size_t n_;
  std::unique_ptr<std::atomic<float>[]> data_;
  std::atomic<uint32_t> seq_{0};
  std::atomic<uint32_t> epoch_{1};
  std::atomic_flag writing_ = ATOMIC_FLAG_INIT;
};

}  // namespace frameless
