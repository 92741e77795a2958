// Sequence-locked world-state mailbox.
#include "frameless/world_channel.h"

namespace frameless {

WorldChannel::WorldChannel(const std::vector<float>& initial)
    : n_(initial.size()), data_(std::make_unique<std::atomic<float>[]>(initial.size())) {
  for (size_t i = 0; i < n_; ++i) data_[i].store(initial[i], std::memory_order_relaxed);
}

uint32_t WorldChannel::publish(const float* data, size_t n) {
  if (n != n_) return 0;
  // Publishers (a simulation, the user dragging) only wait for each other, never for readers.
  while (writing_.test_and_set(std::memory_order_acquire)) {
  }
  const uint32_t s = seq_.load(std::memory_order_relaxed);
  seq_.store(s + 1, std::memory_order_relaxed);
  std::atomic_thread_fence(std::memory_order_release);
  for (size_t i = 0; i < n_; ++i) data_[i].store(data[i], std::memory_order_relaxed);
  const uint32_t e = epoch_.load(std::memory_order_relaxed) + 1;
  epoch_.store(e, std::memory_order_relaxed);
  seq_.store(s + 2, std::memory_order_release);
  writing_.clear(std::memory_order_release);
  return e;
}

uint32_t WorldChannel::read(std::vector<float>& out) const {
  out.resize(n_);
  uint32_t e;
  for (;;) {
    const uint32_t s0 = seq_.load(std::memory_order_acquire);
    if (s0 & 1u) continue;
    for (size_t i = 0; i < n_; ++i) out[i] = data_[i].load(std::memory_order_relaxed);
    e = epoch_.load(std::memory_order_relaxed);
    std::atomic_thread_fence(std::memory_order_acquire);
    if (seq_.load(std::memory_order_relaxed) == s0) break;
  }
  return e;
}

}  // namespace frameless
