// Render threads' frameless loop: each walks its own shuffled pixel list forever, picks up camera
// and world changes after a set share of its pixels, serves the display's closed-loop requests
// and publishes every update. The per-sample path holds no lock, allocates nothing and makes no
// system call.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <thread>

#include "frameless/adaptive.h"
#include "frameless/pixel_update.h"

namespace frameless {
namespace {

using namespace render_detail;

// Records a pixel update in the thread's update log (statistics runs; off: no log).
inline void log_update(const Engine::Impl& e, FramelessWorker& w, uint32_t idx, float time) {
  if (!w.log) return;
  if (w.log->records.size() < w.log->records.capacity())
    w.log->records.push_back({idx, w.epoch, e.display_tick.load(std::memory_order_relaxed), time});
  else
    ++w.log->overflow;
}

// Picks up the newest world state (dynamic objects, lights, materials, moved instances) if it changed.
void refresh_world(Engine::Impl& e, FramelessWorker& w, double time) {
  if (e.pick_up_instances(w.instances_epoch, w.frame.instances)) {
    w.moving = true;
    w.settle_left = w.pixels->size();
  }
  if (e.world_channel.epoch() == w.world_epoch) return;
  const uint32_t ep = e.world_channel.read(w.world_buf);
  // The channel carries only what the engine published after checking it: it always fits.
  unpack_world(w.world_buf.data(), w.world_buf.size(), w.world);
  evaluate_frame(e.scene, w.world, time, w.frame);
  w.world_epoch = ep;
  w.moving = true;
  w.settle_left = w.pixels->size();
}

// Picks up the newest camera if it changed.
void refresh_camera(Engine::Impl& e, uint32_t& epoch, CameraBasis& basis) {
  if (e.channel.epoch() == epoch) return;
  uint32_t ep = 0;
  const Camera cam = e.channel.read(&ep);
  basis = make_camera_basis(cam, e.partition.width, e.partition.height);
  epoch = ep;
}

// Closed-loop sampling: after the display asked for more runs, queue this thread's (their flags
// are cleared as they are queued; the display may ask again later).
void scan_asked(Engine::Impl& e, FramelessWorker& w, float now) {
  const uint64_t generation = e.wanted.generation.load(std::memory_order_acquire);
  if (generation == w.asked_generation) return;
  w.asked_generation = generation;
  w.asked.erase(w.asked.begin(), w.asked.begin() + std::ptrdiff_t(w.asked_next));
  w.asked_next = 0;
  const size_t first = w.first_slot, end = first + w.pixels->size();
  if (end == first) return;
  for (size_t r = first / kRunLength; r <= (end - 1) / kRunLength; ++r) {
    std::atomic<uint8_t>& f = e.wanted.flags[r];
    // Lists need not start or end on a run boundary: this thread queues and clears its part.
    const size_t run_first = r * kRunLength;
    const uint8_t part = run_part_bit(run_first < first, run_first + kRunLength > end && end < e.pixel_count);
    if (!(f.load(std::memory_order_relaxed) & part)) continue;
    f.fetch_and(uint8_t(~part), std::memory_order_relaxed);
    w.asked.push_back({uint32_t(std::max(r * kRunLength, first) - first), now});
  }
}

// Renders the next asked-for run (up to `budget` updates) as one batch and announces it to the
// display; returns the updates rendered. The walk's position and counters do not move.
uint64_t serve_asked(Engine::Impl& e, FramelessWorker& w, ThreadCounters& ctr, double t, double dt,
                     uint64_t budget) {
  const std::vector<uint32_t>& list = *w.pixels;
  size_t pos0 = 0, len = 0;
  // Runs whose pixels were all updated since the ask was queued (the walk got there first) are
  // dropped: the display asked for a newer sample, and it has one.
  while (w.asked_next < w.asked.size()) {
    const FramelessWorker::AskedRun run = w.asked[w.asked_next++];
    pos0 = run.pos;
    // A run that began in the previous thread's list (thread lists need not start on a run
    // boundary) ends kRunLength slots after its start, not after this list's first slot.
    len = std::min<size_t>({kRunLength - (w.first_slot + pos0) % kRunLength, list.size() - pos0, size_t(budget)});
    bool since = true;  // every pixel of the run updated since it was queued
    for (size_t k = 0; k < len && since; ++k)
      since = e.states[w.first_slot + pos0 + k].time.load(std::memory_order_relaxed) > run.time;
    if (!since) break;
    len = 0;
  }
  if (len == 0) return 0;
  PacketBatch b;
  for (size_t k = 0; k < len; ++k) {
    b.idx[b.n] = list[pos0 + k];
    b.state[b.n] = &e.states[w.first_slot + pos0 + k];
    b.t[b.n] = t + dt * double(k);
    b.frame[b.n] = nullptr;
    ++b.n;
  }
  trace_batch(e, b, w.basis, w.moving ? &w.frame : nullptr, &w.world);
  const History history = w.history();
  for (int k = 0; k < b.n; ++k) {
    finish_update(e, b.idx[k], *b.state[k], w.epoch, float(b.t[k]), ctr, nullptr, history, b.r[k]);
    log_update(e, w, b.idx[k], float(b.t[k]));
  }
  e.priority_rings[w.index].push(uint32_t(w.first_slot + pos0));  // after the publishes
  return len;
}

// The frameless walk over a thread's pixel list: up to PacketBatch::kMax consecutive visits are
// gathered in order, traced together, then published in order, adaptive skips included, so every
// counter and pixel sees the sequence of a one-by-one walk. A batch ends before a camera or world
// pick-up and at the end of the list (no pixel twice).
template <bool kAdaptive>
void run_visits(Engine::Impl& e, FramelessWorker& w, uint64_t count, double t_begin,
                        double dt) {
  const std::vector<uint32_t>& list = *w.pixels;
  const size_t n = list.size();
  if (n == 0) return;
  ThreadCounters& ctr = e.counters[w.index];
  const bool closed_loop = e.wanted.runs != 0;
  PacketBatch b;
  constexpr int kMaxEntries = 64;
  int8_t entries[kMaxEntries];  // visit order: a batch slot, or -1 for an adaptive skip
  int m = 0;
  auto flush = [&] {
    if (b.n > 0) trace_batch(e, b, w.basis, w.moving ? &w.frame : nullptr, &w.world);
    const History history = w.history();
    // Visits, adaptive skips included, count toward the settling pass (one per list position).
    w.settle_left -= std::min<uint64_t>(w.settle_left, uint64_t(m));
    for (int k = 0; k < m; ++k) {
      const int slot = entries[k];
      if (slot >= 0) {
        finish_update(e, b.idx[slot], *b.state[slot], w.epoch, float(b.t[slot]), ctr, nullptr,
                      history, b.r[slot]);
        log_update(e, w, b.idx[slot], float(b.t[slot]));
      }
      // The display derives which pixels changed from this counter: publish after the pixel.
      ctr.updates.store(++w.updates, std::memory_order_release);
    }
    b.n = 0;
    m = 0;
  };
  for (uint64_t i = 0; i < count;) {  // i counts rendered updates (adaptive skips do not count)
    if (w.countdown == 1) flush();  // the pick-up below must follow every gathered visit
    if (--w.countdown == 0) {
      w.countdown = w.interval;
      refresh_camera(e, w.epoch, w.basis);
      refresh_world(e, w, t_begin + dt * double(i));
      if (closed_loop) scan_asked(e, w, float(t_begin + dt * double(i)));
    }
    const size_t pos = w.pos;
    const uint32_t idx = list[pos];
    // A packet never spans two chunks, which lie far apart in the image once shuffled: adaptive
    // skips and asked runs shift the batches off the chunk grid, and a straddling packet costs
    // several times more. A countdown, not a division per visit, finds the chunk starts.
    if (w.chunk_left == 0) {
      if (b.n > 0) flush();
      w.chunk_left = e.partition.chunk_length(w.index, pos);
    }
    --w.chunk_left;
    PixelState& p = e.states[w.first_slot + pos];
    const bool wrapped = ++w.pos == n;
    if (wrapped) w.pos = 0;
    bool skip = false;
    // No pixel skips its settling update: its old statistics may not hold in the changed world.
    if constexpr (kAdaptive)
      skip = w.settle_left == 0 && adaptive_skip(e.cfg.adaptive, p, w.epoch, w.adaptive.skip_run[pos]);
    if (skip) {
      entries[m++] = -1;
    } else {
      b.idx[b.n] = idx;
      b.state[b.n] = &p;
      b.t[b.n] = t_begin + dt * double(i);
      entries[m++] = int8_t(b.n++);
      ++i;
    }
    if (wrapped || b.n == PacketBatch::kMax || m == kMaxEntries) {
      flush();
      // One asked-for run after each batch of the walk: the walk keeps at least half the updates.
      if (closed_loop && w.asked_next < w.asked.size() && i < count)
        i += serve_asked(e, w, ctr, t_begin + dt * double(i), dt, count - i);
    }
  }
  flush();
}

}  // namespace

void frameless_run(Engine::Impl& e, FramelessWorker& w, uint64_t count, double t_begin, double dt) {
  if (e.cfg.adaptive.enabled) {
    if (w.adaptive.skip_run.size() != w.pixels->size()) w.adaptive.skip_run.assign(w.pixels->size(), 0);
    run_visits<true>(e, w, count, t_begin, dt);
  } else {
    run_visits<false>(e, w, count, t_begin, dt);
  }
}

void frameless_thread_main(Engine::Impl& e, int t) {
  enable_flush_to_zero();
  try {
    FramelessWorker& w = e.workers[size_t(t)];
    // Batches of visits share one clock reading; the stop flag is checked between batches.
    constexpr uint64_t kBatch = 16;
    const uint64_t cpu0 = thread_cpu_ns();
    ThreadCounters& ctr = e.counters[t];
    // A sample-rate cap: this thread's share of it, as the time its samples so far should take.
    const int spu = samples_per_update(e.cfg);
    const double share = e.cfg.max_samples_per_s / double(std::max<size_t>(1, e.workers.size()));
    const auto start = std::chrono::steady_clock::now();
    for (uint64_t batch = 1; !e.stop_flag.load(std::memory_order_relaxed); ++batch) {
      frameless_run(e, w, kBatch, e.now(), 0.0);
      // Busy time for the balance statistics: one clock read per 64 batches keeps it off the hot path.
      if (batch % 64 == 0) ctr.busy_ns.store(thread_cpu_ns() - cpu0, std::memory_order_relaxed);
      if (share > 0.0 && batch % 4 == 0) {
        const auto due = start + std::chrono::duration_cast<std::chrono::steady_clock::duration>(
                                     std::chrono::duration<double>(double(batch * kBatch * uint64_t(spu)) / share));
        // In slices of at most 20 ms, so a stop is seen soon whatever the cap.
        while (due > std::chrono::steady_clock::now() + std::chrono::milliseconds(1) &&
               !e.stop_flag.load(std::memory_order_relaxed))
          std::this_thread::sleep_until(std::min(due, std::chrono::steady_clock::now() + std::chrono::milliseconds(20)));
      }
    }
    ctr.busy_ns.store(thread_cpu_ns() - cpu0, std::memory_order_relaxed);
  } catch (const std::exception& ex) {
    e.record_error(std::string("render thread ") + std::to_string(t) + ": " + ex.what());
  } catch (...) {
    e.record_error("render thread " + std::to_string(t) + ": unknown exception");
  }
}

}  // namespace frameless
