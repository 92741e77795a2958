// A command joining the cluster when mpirun started it (`mpirun -np N frameless capture ...`):
// rank 0 becomes the master and goes on with the command; ranks 1..N-1 serve as clients.
#pragma once
#include <memory>
#include <string>

#include "cluster/cluster.h"
#include "frameless/engine_config.h"

namespace frameless::bench {

// The cluster's command-line options (used only under mpirun; tools/cluster_flags.h names them).
struct ClusterJoinOptions {
  std::string wire = "exact";
  double batch_ms = 4.0;
  int prefetch = 0;
};

struct ClusterJoin {
  std::unique_ptr<cluster::Session> session;  // null: a single process (no mpirun, or -np 1)
  ClusterJoinOptions requested;               // set before join()
  cluster::ClusterOptions options;            // from `requested`, by join()

  // Starts MPI when launched by mpirun with 2+ ranks; false (error set) when it cannot.
  bool start(std::string& error);
  // After loading the scene (null with load_error when it failed): the handshake, then a client
  // serves until the master stops it. Returns -1 when this process goes on with the command (a
  // single process or the master, whose `config` now spans the cluster), else its exit code.
  int join(const Scene* scene, const std::string& load_error, EngineConfig& config, const Camera& camera);
  bool master() const { return session && session->master(); }
};

}  // namespace frameless::bench
