// The one place that calls Open MPI: byte messages between ranks of MPI_COMM_WORLD. Every call
// on a process comes from one thread at a time (MPI_THREAD_SERIALIZED): the handshake and
// shutdown from the command's thread, everything between from the communication thread.
#pragma once
#include <algorithm>
#include <chrono>
#include <cstdint>
#include <memory>
#include <thread>
#include <vector>

namespace frameless::cluster {

// Waiting between polls without holding a core: naps double from 20 µs up to 1 ms, and start
// short again after anything happened (every polling loop of the cluster uses it).
class Backoff {
 public:
  void reset() { nap_ = kShortest; }
  void nap() {
    std::this_thread::sleep_for(nap_);
    nap_ = std::min(nap_ * 2, kLongest);
  }

 private:
  static constexpr std::chrono::microseconds kShortest{20}, kLongest{1000};
  std::chrono::microseconds nap_ = kShortest;
};

// Ranks in this job from Open MPI's launch environment (1 when not started by mpirun).
int launched_size();

class MpiLink {
 public:
  MpiLink();   // MPI_Init_thread; throws std::runtime_error when MPI cannot start
  ~MpiLink();  // MPI_Finalize (after every message was answered)
  MpiLink(const MpiLink&) = delete;
  MpiLink& operator=(const MpiLink&) = delete;

  int rank() const { return rank_; }
  int size() const { return size_; }
  void send(int dest, int tag, const std::vector<uint8_t>& bytes);
  // Sends without waiting for the receiver (two ranks sending each other large messages at
  // once would otherwise both block); the bytes are kept until MPI is done with them. poll()
  // and flush() complete what finished.
  void send_async(int dest, int tag, std::vector<uint8_t> bytes);
  // Waits until every send_async() is done.
  void flush();
  size_t sends_in_flight() const { return pending_.size(); }
  // A waiting message with `tag` from `source` (-1: any), into bytes; false when none waits.
  // Throws std::runtime_error for a message larger than kMaxMessageBytes (it is not read).
  bool poll(int source, int tag, std::vector<uint8_t>& bytes, int* from = nullptr);
  // Every rank, together: gathers each rank's bytes at rank 0 (others get an empty vector).
  std::vector<std::vector<uint8_t>> gather(const std::vector<uint8_t>& mine);
  // Every rank, together: rank 0's bytes to all.
  void broadcast(std::vector<uint8_t>& bytes);
  // Ends every rank of the job now (mpirun reports it); for faults that must not hang.
  [[noreturn]] void abort(int code);

  static constexpr int kMaxMessageBytes = 1 << 28;

 private:
  struct Pending;
  void progress();
  int rank_ = 0, size_ = 1;
  std::vector<std::unique_ptr<Pending>> pending_;
};

}  // namespace frameless::cluster
