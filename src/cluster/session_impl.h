// Internal state of cluster::Session shared by session.cpp (handshake, client) and
// master_link.cpp (the master's communication); not a public interface.
#pragma once
#include <atomic>
#include <memory>
#include <mutex>
#include <unordered_map>
#include <thread>
#include <vector>

#include "cluster/cluster.h"
#include "cluster/mpi_link.h"
#include "cluster/tile_scheduler.h"
#include "cluster/wire.h"

namespace frameless::cluster {

// A client mirrors what changed on the master (camera, world, instances), checked first.
void apply_changes(Engine& engine, const Scene& scene, const Control& m);

struct Session::Impl {
  std::unique_ptr<MpiLink> link;
  int threads_per_client = 0;  // agreed in the handshake
  bool serving = false;        // master: clients serve and wait for the stop order

  // Master side.
  Engine* engine = nullptr;
  const Scene* scene = nullptr;
  std::thread comm;  // wall clock: the communication thread
  std::atomic<bool> comm_stop{false};
  // What the clients already have (written by whichever thread drives MPI at the time).
  uint32_t sent_camera_epoch = 1;
  uint32_t sent_world_epoch = 1;
  uint32_t sent_instances_epoch = 1;
  std::vector<Affine> sent_transforms;
  mutable std::mutex stats_mutex;
  ClusterStats stats;

  // Conventional mode (conventional_master.cpp): OpenRT's tiles on demand.
  struct OutPiece {
    int client = 0;
    uint32_t job = 0;  // ~0: a deterministic piece
    FramePiece piece;
  };
  ClusterOptions options;
  std::unique_ptr<TileScheduler> scheduler;
  std::unordered_map<uint64_t, OutPiece> out_pieces;  // handed out, not back yet
  uint64_t next_piece_id = 1;
  uint64_t sent_frame_serial = 0;  // the newest frame spec the clients have
  std::vector<uint64_t> client_idle_ns, client_request_ns, client_requests;  // from their results

  // The differential control message for what changed since the last one (may be empty): the
  // newest camera, world and instances, or (conventional) what frame `serial` sees.
  Control changes();
  Control frame_changes(uint64_t serial);
  void add_moves(Control& c, uint32_t epoch, const std::shared_ptr<const InstanceTop>& top);
  bool has_changes(const Control& c) const {
    return c.camera || !c.world.empty() || !c.moves.empty();
  }
  void send_all(const Control& c);
  // Receives and ingests one update message if one waits; returns its tick, or nothing.
  std::optional<uint64_t> receive_updates(int source);
  void comm_main();
  void release_clients();  // master: stop order to every client, then their goodbyes
  void advance_round(uint64_t tick, double seconds);
  // Conventional mode, master: the communication loop, one deterministic stretch of a frame,
  // and the pieces a Results message brings (checked against what was handed out).
  void conventional_comm_main();
  void conventional_round(const FrameSpec& spec, const FramePiece& piece);
  void take_results(int from, const std::vector<uint8_t>& bytes);
  void send_pieces(std::vector<TileScheduler::Assignment>& assigned);
  void begin_frames_and_dispatch();
  // Conventional mode, client: renders the pieces it is handed until the master says stop.
  void serve_conventional(const Scene& scene, EngineConfig c, const Camera& camera);
  [[noreturn]] void fail(const std::string& line);
};

}  // namespace frameless::cluster
