// Frameless across machines on Open MPI (seed 002, OpenRT's distribution; docs/cluster.md).
// Rank 0 is the master: the application, camera input, the display thread and every output; its
// engine renders nothing itself and holds the whole cluster's partition, into which a
// communication thread writes what the clients send. Ranks 1..N-1 are clients: each loads the
// same scene and renders its share of the render threads (EngineConfig::owned_*), streaming the
// pixels it changed in batches and taking camera, world and instance changes as differential
// updates. A single process (no mpirun, or -np 1) never touches this library's MPI side.
#pragma once
#include <atomic>
#include <cstdint>
#include <memory>
#include <string>
#include <thread>

#include "cluster/wire.h"
#include "core/scene/scene.h"
#include "frameless/engine.h"

namespace frameless::cluster {

class MpiLink;

// Whether this process was started as one rank of a job with 2+ ranks (mpirun -np N).
bool launched();

// A fingerprint of what a rank loaded (counts, bounds, camera): ranks must agree on it.
uint64_t scene_fingerprint(const Scene& scene);

// Wire and batching options (the command line's --cluster-* flags).
struct ClusterOptions {
  double batch_ms = 4.0;                   // a client sends what changed this often (wall clock)
  WireFormat wire = WireFormat::exact;     // pixel records: exact, or rgbe (wall clock only)
  int prefetch = 0;                        // conventional: pieces a client holds (0: 2 per thread)
};

// Traffic and timing counters of the master's communication (bench cluster reads them).
struct ClusterStats {
  uint64_t messages = 0;       // update messages received
  uint64_t bytes = 0;          // their bytes
  uint64_t pixel_records = 0;  // pixel states they carried
  uint64_t controls = 0;       // control messages sent (per client)
  double comm_cpu_seconds = 0; // the communication thread's CPU time
  // Conventional mode: pieces handed out, of them stolen from another client's queue and handed
  // over with their pixel states; the clients' render threads' time waiting for a piece and
  // their requests' round trips (ask -> pieces, waiting for work included).
  uint64_t pieces = 0, steals = 0, handoffs = 0;
  double client_idle_seconds = 0, request_seconds = 0;
  uint64_t requests = 0;
};

class Session {
 public:
  // Starts MPI (only when launched()); throws std::runtime_error when it cannot.
  Session();
  ~Session();  // master: stops the clients if still attached; every rank: MPI_Finalize
  Session(const Session&) = delete;
  Session& operator=(const Session&) = delete;

  int rank() const;
  int size() const;
  bool master() const { return rank() == 0; }
  int clients() const { return size() - 1; }

  // Every rank once, after loading the scene (`error`: why it could not; empty: it can). The
  // master checks builds, scenes and thread counts; returns "" when all ranks can go on, else
  // one line naming the rank (every rank gets the same verdict; the master prints it).
  std::string handshake(const std::string& error, uint64_t fingerprint, int threads);

  // The master's engine settings for per-client settings `c`: every client's threads in one
  // partition, none rendered here.
  EngineConfig master_config(EngineConfig c) const;

  // Client: renders its share until the master says stop; returns the exit code.
  int serve(const Scene& scene, EngineConfig per_client, const Camera& camera, const ClusterOptions& o = {});

  // Master: connects `engine` (made with master_config, started) to the clients. Wall clock:
  // starts the communication thread; deterministic: installs the advance round (render, then
  // ingest). Conventional mode hands out the frames' pieces on demand (docs/cluster.md).
  void attach(Engine& engine, const Scene& scene, const ClusterOptions& o = {});
  // Master: tells every client to stop, waits for their goodbyes, stops the communication thread.
  void detach();
  ClusterStats stats() const;

  // Master: one small request/reply round trip to `client` in seconds (bench cluster); only
  // while detached.
  double ping(int client);

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace frameless::cluster
