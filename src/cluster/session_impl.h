// Internal state of cluster::Session shared by session.cpp (handshake, client) and
// master_link.cpp (the master's communication); not a public interface.
#pragma once
#include <atomic>
#include <mutex>
#include <thread>
#include <vector>

#include "cluster/cluster.h"
#include "cluster/mpi_link.h"
#include "cluster/wire.h"

namespace frameless::cluster {

struct Session::Impl {
  std::unique_ptr<MpiLink> link;
  int threads_per_client = 0;  // agreed in the handshake
  bool serving = false;        // master: clients serve and wait for the stop order

  // Master side.
  Engine* engine = nullptr;
  std::thread comm;  // wall clock: the communication thread
  std::atomic<bool> comm_stop{false};
  // What the clients already have (written by whichever thread drives MPI at the time).
  uint32_t sent_camera_epoch = 1;
  uint32_t sent_world_epoch = 1;
  uint32_t sent_instances_epoch = 1;
  std::vector<Affine> sent_transforms;
  mutable std::mutex stats_mutex;
  ClusterStats stats;

  // The differential control message for what changed since the last one (may be empty).
  Control changes();
  bool has_changes(const Control& c) const {
    return c.camera || !c.world.empty() || !c.moves.empty();
  }
  void send_all(const Control& c);
  // Receives and ingests one update message if one waits; returns its tick, or nothing.
  std::optional<uint64_t> receive_updates(int source);
  void comm_main();
  void release_clients();  // master: stop order to every client, then their goodbyes
  void advance_round(uint64_t tick, double seconds);
  [[noreturn]] void fail(const std::string& line);
};

}  // namespace frameless::cluster
