// OpenRT's task distribution: affinity, stealing, two frames in flight (tile_scheduler.h).
#include "cluster/tile_scheduler.h"

#include <stdexcept>
#include <string>

namespace frameless::cluster {

TileScheduler::TileScheduler(uint32_t jobs, int clients)
    : jobs_(jobs),
      clients_(clients),
      holder_(jobs, -1),
      done_(jobs, 0),
      out_at_(jobs, -1),
      out_serial_(jobs, 0),
      queues_(size_t(clients)),
      want_(size_t(clients), 0) {
  if (jobs == 0 || clients < 1) throw std::invalid_argument("tile scheduler: needs jobs and clients");
}

bool TileScheduler::may_begin_next() const {
  if (newest_ == 0) return true;
  return handed_newest_ == jobs_ && (newest_ == 1 || remaining_[(newest_ - 1) & 1] == 0);
}

void TileScheduler::begin_frame(uint64_t serial) {
  if (serial != newest_ + 1 || !may_begin_next())
    throw std::logic_error("tile scheduler: frame " + std::to_string(serial) + " out of order");
  newest_ = serial;
  handed_newest_ = 0;
  remaining(serial) = jobs_;
  for (uint32_t j = 0; j < jobs_; ++j)
    if (done_[j] == serial - 1) make_ready(serial, j);  // the rest follow as they come back
}

void TileScheduler::make_ready(uint64_t serial, uint32_t job) {
  (holder_[job] >= 0 ? queues_[size_t(holder_[job])] : unowned_).push_back({serial, job});
}

void TileScheduler::want(int client, uint32_t n) {
  if (client < 0 || client >= clients_) throw std::invalid_argument("tile scheduler: no such client");
  want_[size_t(client)] += n;
}

bool TileScheduler::complete(int client, uint64_t serial, uint32_t job) {
  if (job >= jobs_ || out_at_[job] != client || out_serial_[job] != serial)
    throw std::invalid_argument("job " + std::to_string(job) + " of frame " + std::to_string(serial) +
                                " was not handed to this client");
  out_at_[job] = -1;
  done_[job] = serial;
  if (newest_ > serial) make_ready(serial + 1, job);  // the next frame already began
  return --remaining(serial) == 0;
}

bool TileScheduler::take(int client, Ready& r, bool& stolen) {
  stolen = false;
  std::deque<Ready>& own = queues_[size_t(client)];
  if (!own.empty()) {
    r = own.front();
    own.pop_front();
    return true;
  }
  if (!unowned_.empty()) {
    r = unowned_.front();
    unowned_.pop_front();
    return true;
  }
  // Steal the last (smallest, latest) job of the longest queue.
  size_t best = 0, longest = 0;
  for (size_t c = 0; c < queues_.size(); ++c)
    if (queues_[c].size() > longest) longest = queues_[c].size(), best = c;
  if (longest == 0) return false;
  r = queues_[best].back();
  queues_[best].pop_back();
  stolen = true;
  return true;
}

void TileScheduler::dispatch(std::vector<Assignment>& out) {
  for (bool progress = true; progress;) {
    progress = false;
    for (int k = 0; k < clients_; ++k) {
      const int c = (next_client_ + k) % clients_;
      if (want_[size_t(c)] == 0) continue;
      Ready r;
      bool stolen = false;
      if (!take(c, r, stolen)) return;  // nothing ready for anyone
      const uint32_t j = r.second;
      Assignment a{c, r.first, j, holder_[j] >= 0 && holder_[j] != c, stolen};
      holder_[j] = c;
      out_at_[j] = c;
      out_serial_[j] = r.first;
      --want_[size_t(c)];
      if (r.first == newest_) ++handed_newest_;
      ++handed_total_;
      steals_ += a.stolen;
      handoffs_ += a.handoff;
      out.push_back(a);
      progress = true;
    }
    next_client_ = (next_client_ + 1) % clients_;
  }
}

}  // namespace frameless::cluster
