// The remote exchange: pixel states rendered by another process (a cluster client's render
// threads, received by the master's communication thread) checked and published into this
// engine's slots as its own render threads publish theirs; and the hook that lets the remote
// side follow deterministic ticks.
#include <cmath>
#include <mutex>
#include <stdexcept>
#include <string>

#include "frameless/engine.h"
#include "frameless/engine_impl.h"

namespace frameless {

void Engine::set_remote_advance(std::function<void(uint64_t, double)> fn) {
  impl_->remote_advance = std::move(fn);
}

void Engine::ingest(const RemoteBatch& b) {
  Impl& e = *impl_;
  std::lock_guard<std::mutex> lock(e.layout_mutex);  // the layout (slots, counters) stays put
  auto bad = [&](const std::string& what) {
    throw std::invalid_argument("remote thread " + std::to_string(b.thread) + ": " + what);
  };
  if (e.cfg.mode != RenderMode::frameless) bad("updates need frameless mode");
  if (b.thread < 0 || b.thread >= e.threads) bad("no such render thread");
  if (owns_thread(e.cfg, b.thread)) bad("this process renders that thread itself");
  const ThreadCounters& c = e.counters[b.thread];
  if (b.updates < c.updates.load(std::memory_order_relaxed) ||
      b.samples < c.samples.load(std::memory_order_relaxed) ||
      b.dropped < c.dropped.load(std::memory_order_relaxed))
    bad("counters went backwards");
  const size_t first = e.thread_first_slot[size_t(b.thread)];
  const size_t end = e.thread_first_slot[size_t(b.thread) + 1];
  const uint32_t newest = e.channel.epoch();
  for (const RemoteSlot& r : b.slots) {
    const PixelSnapshot& s = r.state;
    if (r.slot < first || r.slot >= end) bad("slot " + std::to_string(r.slot) + " is not its own");
    if (s.epoch < 1 || s.epoch > newest) bad("camera epoch " + std::to_string(s.epoch) + " out of range");
    if (s.count < 1) bad("a published pixel without samples");
    bool finite = std::isfinite(s.variance) && s.variance >= 0.0f && std::isfinite(s.time);
    for (int k = 0; k < 3; ++k) finite = finite && std::isfinite(s.sample[k]) && std::isfinite(s.mean[k]);
    if (!finite) bad("non-finite value in slot " + std::to_string(r.slot));
  }
  for (const RemoteSlot& r : b.slots) {
    // A state computed elsewhere, published as a render thread publishes its own.
    const PixelSnapshot& s = r.state;
    const double mean[3] = {s.mean[0], s.mean[1], s.mean[2]};  // read back as the same floats
    // read_pixel() gives float(m2 / (count - 1)): this m2 gives the same float back.
    const double m2 = s.count > 1 ? double(s.variance) * double(s.count - 1) : 0.0;
    publish_state(e.states[r.slot], s.count, s.epoch, mean, m2, s.sample, s.time, [&] {
      e.levels[(*e.display_order)[r.slot]].store(s.levels, std::memory_order_relaxed);
    });
  }
  ThreadCounters& w = e.counters[b.thread];
  w.samples.store(b.samples, std::memory_order_relaxed);
  w.dropped.store(b.dropped, std::memory_order_relaxed);
  w.busy_ns.store(b.busy_ns, std::memory_order_relaxed);
  w.updates.store(b.updates, std::memory_order_release);  // last: collect() reads it first
}

}  // namespace frameless
