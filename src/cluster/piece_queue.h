// The queue between a client's communication thread and its render threads (the engine's
// PieceFeed): a lock per piece, never per sample. Wall clock: next() waits for a piece;
// deterministic: it ends the round when the queue is empty.
#pragma once
#include <chrono>
#include <condition_variable>
#include <deque>
#include <memory>
#include <mutex>
#include <vector>

#include "frameless/remote_frames.h"

namespace frameless::cluster {

class PieceQueue final : public PieceFeed {
 public:
  static uint64_t clock_ns() {
    return uint64_t(std::chrono::duration_cast<std::chrono::nanoseconds>(
                        std::chrono::steady_clock::now().time_since_epoch())
                        .count());
  }
  explicit PieceQueue(bool wait) : wait_(wait) {}
  void push(std::unique_ptr<PieceJob> job) {
    std::lock_guard<std::mutex> lock(mutex_);
    queue_.push_back(std::move(job));
    ++held_;
    cv_.notify_one();
  }
  bool next(int, std::unique_ptr<PieceJob>& job) override {
    std::unique_lock<std::mutex> lock(mutex_);
    if (wait_ && queue_.empty() && !closed_) {
      const uint64_t t0 = clock_ns();
      cv_.wait(lock, [&] { return closed_ || !queue_.empty(); });
      idle_ns_ += clock_ns() - t0;
    }
    if (closed_ || queue_.empty()) return false;
    job = std::move(queue_.front());
    queue_.pop_front();
    return true;
  }
  void done(int, std::unique_ptr<PieceJob> job) override {
    std::lock_guard<std::mutex> lock(mutex_);
    finished_.push_back(std::move(job));
  }
  void close() override {
    std::lock_guard<std::mutex> lock(mutex_);
    closed_ = true;
    cv_.notify_all();
  }
  // Finished pieces (no longer held), pieces still held, the threads' waiting time.
  std::vector<std::unique_ptr<PieceJob>> take_finished(size_t& held, uint64_t& idle_ns) {
    std::lock_guard<std::mutex> lock(mutex_);
    std::vector<std::unique_ptr<PieceJob>> out = std::move(finished_);
    finished_.clear();
    held_ -= out.size();
    held = held_;
    idle_ns = idle_ns_;
    return out;
  }

 private:
  const bool wait_;
  std::mutex mutex_;
  std::condition_variable cv_;
  std::deque<std::unique_ptr<PieceJob>> queue_;
  std::vector<std::unique_ptr<PieceJob>> finished_;
  size_t held_ = 0;  // pushed, not yet taken back as finished
  uint64_t idle_ns_ = 0;
  bool closed_ = false;
};


}  // namespace frameless::cluster
