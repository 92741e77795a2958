// Closed-loop sampling (after Adaptive Frameless Rendering, Dayal et al. 2005): the display asks
// for the runs of pixels it guessed or saw change fast (reprojection's cracks and disocclusions,
// what may have moved, colours that jump), and each render thread, still walking its own pixels
// in order, interleaves one asked-for run after every batch of its walk. A run is kRunLength
// consecutive slots of one thread's list (a coherent packet). Every pixel is still visited
// within twice its thread's list length of updates: the walk gets at least half of them.
//
// Exchange, race-free without a lock on the render path: the display sets a run's flag (relaxed)
// and then bumps the generation (release); a render thread that sees a new generation at its
// camera pick-up (acquire) scans its own runs' flags and queues them, clearing its part of each
// flag (an atomic and: a run may span two threads' lists); it announces each run it renders in
// its ring (entries relaxed, head release), from which the display learns which slots changed
// out of walk order.
#pragma once
#include <atomic>
#include <cstdint>
#include <memory>

namespace frameless {

inline constexpr uint32_t kRunLength = 8;  // slots per asked-for run (one packet with jitter off)

// A render thread's announcements of the runs it rendered out of walk order (one producer, the
// thread; one consumer, the display's collect()).
struct alignas(64) PriorityRing {
  static constexpr uint64_t kCapacity = 4096;
  std::atomic<uint64_t> head{0};  // runs announced since start
  std::unique_ptr<std::atomic<uint32_t>[]> first_slot{new std::atomic<uint32_t>[kCapacity]()};
  void push(uint32_t slot) {
    const uint64_t h = head.load(std::memory_order_relaxed);
    first_slot[h % kCapacity].store(slot, std::memory_order_relaxed);
    head.store(h + 1, std::memory_order_release);
  }
};

// A run's flag holds a bit per part of it still asked for. A run inside one thread's list is one
// part; a run across lists (they need not start on a run boundary) has a part in each, named by
// whether it begins before that list and goes on after it, and each thread clears only its own.
inline constexpr uint8_t kAskedAllParts = 0x0F;
inline uint8_t run_part_bit(bool begins_before_list, bool goes_on_after_list) {
  return uint8_t(1u << ((begins_before_list ? 1u : 0u) | (goes_on_after_list ? 2u : 0u)));
}

// The flags the display sets, one per run of slots, and the generation that says some were set.
struct WantedRuns {
  std::unique_ptr<std::atomic<uint8_t>[]> flags;
  size_t runs = 0;
  std::atomic<uint64_t> generation{0};
  void reset(size_t slots) {
    runs = (slots + kRunLength - 1) / kRunLength;
    flags.reset(new std::atomic<uint8_t>[runs]());
  }
  // Display thread: ask for the run holding `slot` (call publish() once after a batch of asks).
  void want(size_t slot) {
    std::atomic<uint8_t>& f = flags[slot / kRunLength];
    if (f.load(std::memory_order_relaxed) != kAskedAllParts) f.store(kAskedAllParts, std::memory_order_relaxed);
  }
  void publish() { generation.fetch_add(1, std::memory_order_release); }
};

}  // namespace frameless
