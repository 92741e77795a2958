// Finds the slots a client changed since its last batch.
#include "cluster/change_collector.h"

#include <algorithm>
#include <stdexcept>

namespace frameless::cluster {

ChangeCollector::ChangeCollector(const Engine& engine, int first_thread, int threads)
    : first_thread_(first_thread), threads_(threads) {
  thread_first_slot_.assign(1, 0);
  for (const std::vector<uint32_t>& list : engine.partition().pixels)
    thread_first_slot_.push_back(thread_first_slot_.back() + list.size());
  sent_seq_.assign(thread_first_slot_.back(), 0);
}

std::vector<RemoteBatch> ChangeCollector::take(Engine& engine) {
  const EngineStats s = engine.stats();
  std::vector<RemoteBatch> out(static_cast<size_t>(threads_));
  for (int i = 0; i < threads_; ++i) {
    const int t = first_thread_ + i;
    const ThreadStats& ts = s.threads.at(size_t(t));
    out[size_t(i)].thread = t;
    out[size_t(i)].updates = ts.updates;
    out[size_t(i)].samples = ts.samples;
    out[size_t(i)].dropped = ts.dropped;
    out[size_t(i)].busy_ns = uint64_t(ts.busy_seconds * 1e9);
  }
  out_ = &out;
  engine.collect(cursor_, *this);
  out_ = nullptr;
  return out;
}

void ChangeCollector::begin(const CollectResult& r) {
  levels_ = r.levels;
  slot_pixel_ = r.slot_pixel.get();
  if (!slot_pixel_ || slot_pixel_->size() != sent_seq_.size())
    throw std::logic_error("cluster client: the engine's layout changed under the collector");
}

void ChangeCollector::slots(size_t first, const PixelState* states, size_t count) {
  for (size_t i = 0; i < count; ++i) {
    const size_t slot = first + i;
    PixelSnapshot snap;
    while (!read_pixel(states[i], snap)) {
    }  // a torn read only lasts while the owner writes: try again
    if (snap.seq == sent_seq_[slot] || snap.epoch == 0) continue;
    const auto it = std::upper_bound(thread_first_slot_.begin(), thread_first_slot_.end(), slot);
    const int t = int(it - thread_first_slot_.begin()) - 1;
    if (t < first_thread_ || t >= first_thread_ + threads_) continue;  // not rendered here
    sent_seq_[slot] = snap.seq;
    snap.levels = levels_[(*slot_pixel_)[slot]].load(std::memory_order_relaxed);
    (*out_)[size_t(t - first_thread_)].slots.push_back({uint32_t(slot), snap});
  }
}

}  // namespace frameless::cluster
