// Optional per-thread record of pixel updates for the statistics of issue 5; written by one
// render thread into preallocated storage, read when that thread is quiescent.
#pragma once
#include <cstdint>
#include <vector>

namespace frameless {

// One pixel update. A thread's records are in update order: record k is its k-th update since
// the log was (re)started, so the index is the thread's update counter.
struct UpdateRecord {
  uint32_t pixel = 0;         // y * width + x
  uint32_t epoch = 0;         // camera epoch the update used
  uint32_t display_tick = 0;  // display interval index when it was taken (Engine::note_display_tick)
  float time = 0.0f;          // engine seconds (virtual in deterministic mode)
};
static_assert(sizeof(UpdateRecord) == 16);

// Preallocated storage; once full, further updates are counted in `overflow` and not stored.
struct UpdateLog {
  std::vector<UpdateRecord> records;  // size() = records kept (capacity fixed at start)
  uint64_t overflow = 0;              // updates that did not fit
};

}  // namespace frameless
