// Per-pixel state: written only by the render thread that owns the pixel, read by the display
// thread through a per-pixel sequence lock. Every field is an atomic (relaxed stores are plain
// moves on x86), so the exchange is race-free under ThreadSanitizer without a lock on the writer.
#pragma once
#include <atomic>
#include <cstdint>

#include "core/base/types.h"

namespace frameless {

// The one sequence-lock protocol of the per-pixel exchange (the state, and the point beside it).
// Writer (the owner only): `seq` odd while `store()` runs, then 2 more than before.
template <class Store>
inline uint32_t write_locked(std::atomic<uint32_t>& seq, Store&& store) {
  const uint32_t s = seq.load(std::memory_order_relaxed);
  seq.store(s + 1, std::memory_order_relaxed);
  std::atomic_thread_fence(std::memory_order_release);
  store();
  seq.store(s + 2, std::memory_order_release);
  return s + 2;
}

// Reader: `load()` between two equal even values of `seq`, whose value goes to *at. False if the
// writer kept writing through `max_tries` attempts (what `load()` wrote is then unspecified).
template <class Load>
inline bool read_locked(const std::atomic<uint32_t>& seq, Load&& load, uint32_t* at = nullptr,
                        int max_tries = 64) {
  for (int i = 0; i < max_tries; ++i) {
    const uint32_t s0 = seq.load(std::memory_order_acquire);
    if (s0 & 1u) continue;
    load();
    std::atomic_thread_fence(std::memory_order_acquire);
    if (seq.load(std::memory_order_relaxed) == s0) {
      if (at) *at = s0;
      return true;
    }
  }
  return false;
}

// Exactly 64 bytes, one cache line (layout in docs/engine.md):
//   seq 4 | count 4 | epoch 4 | passes 4 | mean 3x8 | m2 8 | sample 3x4 | time 4
struct alignas(64) PixelState {
  std::atomic<uint32_t> seq{0};     // sequence lock: odd while the owner writes, +2 per publish
  std::atomic<uint32_t> count{0};   // samples since the pixel's current camera epoch began
  std::atomic<uint32_t> epoch{0};   // camera epoch of the newest sample (0: never sampled)
  std::atomic<uint32_t> passes{0};  // pixel updates ever: picks the jitter pair and sample indices
  std::atomic<double> mean[3];      // running mean RGB since the epoch began
  std::atomic<double> m2{0.0};      // Welford sum of squared deviations of luminance (if tracked)
  std::atomic<float> sample[3];     // colour of the newest update (mean of its valid samples)
  std::atomic<float> time{0.0f};    // engine seconds (virtual in deterministic mode) of the newest update

  PixelState() {
    for (int c = 0; c < 3; ++c) {
      mean[c].store(0.0, std::memory_order_relaxed);
      sample[c].store(0.0f, std::memory_order_relaxed);
    }
  }
};
static_assert(sizeof(PixelState) == 64, "per-pixel state must stay one cache line");

// The owner's publish protocol, the one writer of a pixel's state: odd sequence while writing
// (a reader retries on a torn read), every field, `beside()` (what lives next to the state: the
// reflection depth), then the even sequence. Render threads and the cluster master's ingest
// share it. Inline: the per-sample path pays nothing for the call. Returns the published
// sequence number.
template <class Beside>
inline uint32_t publish_state(PixelState& p, uint32_t count, uint32_t epoch, const double mean[3],
                          double m2, const Vec3& sample, float time, Beside&& beside) {
  return write_locked(p.seq, [&] {
    p.count.store(count, std::memory_order_relaxed);
    p.epoch.store(epoch, std::memory_order_relaxed);
    for (int c = 0; c < 3; ++c) {
      p.mean[c].store(mean[c], std::memory_order_relaxed);
      p.sample[c].store(sample[c], std::memory_order_relaxed);
    }
    p.m2.store(m2, std::memory_order_relaxed);
    p.time.store(time, std::memory_order_relaxed);
    beside();
  });
}

// Copies every field of `from` into `to`; control thread only, while no render thread runs.
inline void copy_state(const PixelState& from, PixelState& to) {
  constexpr auto r = std::memory_order_relaxed;
  to.seq.store(from.seq.load(r), r);
  to.count.store(from.count.load(r), r);
  to.epoch.store(from.epoch.load(r), r);
  to.passes.store(from.passes.load(r), r);
  for (int c = 0; c < 3; ++c) {
    to.mean[c].store(from.mean[c].load(r), r);
    to.sample[c].store(from.sample[c].load(r), r);
  }
  to.m2.store(from.m2.load(r), r);
  to.time.store(from.time.load(r), r);
}
static_assert(std::atomic<double>::is_always_lock_free && std::atomic<float>::is_always_lock_free);

// A consistent copy of one pixel's published state (what the display thread blends).
struct PixelSnapshot {
  Vec3 sample{0.0f};     // newest update's colour (finite)
  Vec3 mean{0.0f};       // running mean since the epoch began
  float variance = 0.0f; // unbiased variance of luminance since the epoch began (0 if untracked/n<2)
  uint32_t count = 0;    // samples since the epoch began
  uint32_t epoch = 0;    // camera epoch of the newest sample (0: never sampled)
  float time = 0.0f;     // engine seconds of the newest update
  uint32_t seq = 0;      // the sequence number it was read at (even); changes with every publish
  // Deepest reflection/refraction level of the newest update: conventional frames and
  // Engine::read_pixel carry it (it lives beside the state, frameless/pixel_levels.h).
  uint8_t levels = 0;
};

// Every field of `p` into `out` with relaxed loads (not seq or levels): consistent when the
// caller is the pixel's owner, or inside read_pixel()'s sequence check.
inline void load_state(const PixelState& p, PixelSnapshot& out) {
  out.count = p.count.load(std::memory_order_relaxed);
  out.epoch = p.epoch.load(std::memory_order_relaxed);
  for (int c = 0; c < 3; ++c) {
    out.mean[c] = float(p.mean[c].load(std::memory_order_relaxed));
    out.sample[c] = p.sample[c].load(std::memory_order_relaxed);
  }
  const double m2 = p.m2.load(std::memory_order_relaxed);
  out.variance = out.count > 1 ? float(m2 / double(out.count - 1)) : 0.0f;
  out.time = p.time.load(std::memory_order_relaxed);
}

// Display side: reads `p` without tearing. Retries while the owner writes; returns false (and
// leaves `out` unspecified) if it could not get a stable copy within `max_tries`.
inline bool read_pixel(const PixelState& p, PixelSnapshot& out, int max_tries = 64) {
  return read_locked(p.seq, [&] { load_state(p, out); }, &out.seq, max_tries);
}

}  // namespace frameless
