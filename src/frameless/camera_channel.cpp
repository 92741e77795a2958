// Sequence-locked camera mailbox.
#include "frameless/camera_channel.h"

namespace frameless {

CameraChannel::CameraChannel(const Camera& initial) {
  const float v[10] = {initial.eye.x,  initial.eye.y,  initial.eye.z, initial.look.x,
                       initial.look.y, initial.look.z, initial.up.x,  initial.up.y,
                       initial.up.z,   initial.fov_deg};
  for (int i = 0; i < 10; ++i) data_[i].store(v[i], std::memory_order_relaxed);
}

uint32_t CameraChannel::publish(const Camera& c) { return store(c, 0); }

uint32_t CameraChannel::publish_as(const Camera& c, uint32_t epoch) { return store(c, epoch); }

uint32_t CameraChannel::store(const Camera& c, uint32_t epoch) {
  // Publishers are rare (input events); they only wait for each other, never for readers.
  while (writing_.test_and_set(std::memory_order_acquire)) {
  }
  const uint32_t current = epoch_.load(std::memory_order_relaxed);
  if (epoch != 0 && epoch <= current) {  // epochs only grow: an old or repeated camera is ignored
    writing_.clear(std::memory_order_release);
    return 0;
  }
  const float v[10] = {c.eye.x, c.eye.y, c.eye.z, c.look.x, c.look.y,
                       c.look.z, c.up.x, c.up.y, c.up.z, c.fov_deg};
  const uint32_t s = seq_.load(std::memory_order_relaxed);
  seq_.store(s + 1, std::memory_order_relaxed);
  std::atomic_thread_fence(std::memory_order_release);
  for (int i = 0; i < 10; ++i) data_[i].store(v[i], std::memory_order_relaxed);
  const uint32_t e = epoch != 0 ? epoch : current + 1;
  epoch_.store(e, std::memory_order_relaxed);
  seq_.store(s + 2, std::memory_order_release);
  writing_.clear(std::memory_order_release);
  return e;
}

Camera CameraChannel::read(uint32_t* epoch) const {
  float v[10];
  uint32_t e;
  for (;;) {
    const uint32_t s0 = seq_.load(std::memory_order_acquire);
    if (s0 & 1u) continue;
    for (int i = 0; i < 10; ++i) v[i] = data_[i].load(std::memory_order_relaxed);
    e = epoch_.load(std::memory_order_relaxed);
    std::atomic_thread_fence(std::memory_order_acquire);
    if (seq_.load(std::memory_order_relaxed) == s0) break;
  }
  if (epoch) *epoch = e;
  Camera c;
  c.eye = {v[0], v[1], v[2]};
  c.look = {v[3], v[4], v[5]};
  c.up = {v[6], v[7], v[8]};
  c.fov_deg = v[9];
  return c;
}

}  // namespace frameless
