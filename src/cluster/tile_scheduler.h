// OpenRT's task distribution for conventional frames across the cluster (seed 002, section 3):
// jobs are handed out on demand (clients ask for as many as they want prefetched), the same job
// goes to the same client frame after frame (spatio-temporal coherence), a client that runs dry
// steals from the longest queue, and the next frame's jobs go out while the current frame
// finishes (asynchronous rendering: at most two frames in flight). Job j of a frame becomes
// ready when job j of the previous frame came back, because a pixel continues from its previous
// state. Pure bookkeeping, no MPI and no engine: the tests drive it directly.
#pragma once
#include <cstdint>
#include <deque>
#include <utility>
#include <vector>

namespace frameless::cluster {

class TileScheduler {
 public:
  struct Assignment {
    int client = 0;
    uint64_t serial = 0;
    uint32_t job = 0;
    bool handoff = false;  // another client rendered this job last: its pixel states go along
    bool stolen = false;   // taken from another client's queue
  };

  TileScheduler(uint32_t jobs, int clients);

  // Begins frame `serial` (the next one; see may_begin_next()).
  void begin_frame(uint64_t serial);
  // The newest frame has every job handed out and the one before it is complete.
  bool may_begin_next() const;
  // Client c asks for n more jobs (added to what it asked for before).
  void want(int client, uint32_t n);
  // Job `job` of frame `serial` came back from `client`: true when that frame is now complete.
  // Throws std::invalid_argument when that client does not hold that job of that frame.
  bool complete(int client, uint64_t serial, uint32_t job);
  // Hands ready jobs to clients that want some, one at a time round robin; appends to `out`.
  void dispatch(std::vector<Assignment>& out);

  uint64_t newest() const { return newest_; }
  uint32_t jobs() const { return jobs_; }
  uint64_t handed_out() const { return handed_total_; }
  uint64_t steals() const { return steals_; }
  uint64_t handoffs() const { return handoffs_; }

 private:
  using Ready = std::pair<uint64_t, uint32_t>;  // frame serial, job
  void make_ready(uint64_t serial, uint32_t job);
  bool take(int client, Ready& r, bool& stolen);
  uint32_t& remaining(uint64_t serial) { return remaining_[serial & 1]; }

  uint32_t jobs_;
  int clients_;
  uint64_t newest_ = 0;
  uint32_t handed_newest_ = 0;        // jobs of the newest frame handed out
  uint32_t remaining_[2] = {0, 0};    // jobs not yet back, by serial parity (two frames in flight)
  std::vector<int> holder_;           // per job: the client that rendered it last (-1: none)
  std::vector<uint64_t> done_;        // per job: the newest frame it came back for
  std::vector<int> out_at_;           // per job: the client holding it now (-1: none)
  std::vector<uint64_t> out_serial_;  // per job: the frame it is out for
  std::vector<std::deque<Ready>> queues_;  // per client: ready jobs it rendered last
  std::deque<Ready> unowned_;         // ready jobs nobody rendered yet
  std::vector<uint32_t> want_;
  int next_client_ = 0;               // round robin start
  uint64_t handed_total_ = 0, steals_ = 0, handoffs_ = 0;
};

}  // namespace frameless::cluster
