// Flags of joining the cluster: see cluster_flags.h.
#include "tools/cluster_flags.h"

namespace frameless::cli {

void add_cluster_flags(CLI::App& app, ClusterJoinOptions& cluster) {
  app.add_option("--cluster-wire", cluster.wire,
                 "under mpirun: pixel records exact (45 B, bit-exact display) or rgbe (27 B, "
                 "OpenRT-style quantised colour; wall clock only)")
      ->capture_default_str();
  app.add_option("--cluster-batch-ms", cluster.batch_ms, "under mpirun: a client sends its changes this often")
      ->capture_default_str();
  app.add_option("--cluster-prefetch", cluster.prefetch,
                 "under mpirun, conventional mode: pieces each client holds ahead (0: two per render thread)")
      ->capture_default_str();
}

}  // namespace frameless::cli
