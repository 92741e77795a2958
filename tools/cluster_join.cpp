// Joining the cluster from a command.
#include "tools/cluster_join.h"

#include <thread>

#include "tools/common_options.h"

namespace frameless::cli {

void ClusterFlags::add_to(CLI::App& app) {
  app.add_option("--cluster-wire", wire,
                 "under mpirun: pixel records exact (45 B, bit-exact display) or rgbe (27 B, "
                 "OpenRT-style quantised colour; wall clock only)")
      ->capture_default_str();
  app.add_option("--cluster-batch-ms", batch_ms, "under mpirun: a client sends its changes this often")
      ->capture_default_str();
  app.add_option("--cluster-prefetch", prefetch,
                 "under mpirun, conventional mode: pieces each client holds ahead (0: two per render thread)")
      ->capture_default_str();
}

bool ClusterJoin::start(std::string& error) {
  if (!cluster::launched()) return true;
  try {
    session = std::make_unique<cluster::Session>();
  } catch (const std::exception& ex) {
    error = ex.what();
    return false;
  }
  return true;
}

int ClusterJoin::join(const Scene* scene, const std::string& load_error, EngineConfig& config,
                      const Camera& camera) {
  if (!session) return scene ? -1 : report_error(load_error);
  // Every rank sees the same flags: all stop here.
  if (flags.wire != "exact" && flags.wire != "rgbe")
    return report_error("--cluster-wire: expected exact or rgbe, got '" + flags.wire + "'");
  options.wire = flags.wire == "rgbe" ? cluster::WireFormat::rgbe : cluster::WireFormat::exact;
  options.batch_ms = flags.batch_ms;
  if (options.wire == cluster::WireFormat::rgbe && config.deterministic)
    return report_error("--cluster-wire rgbe: deterministic runs need the exact wire format");
  if (!(options.batch_ms >= 0.1 && options.batch_ms <= 1000))
    return report_error("--cluster-batch-ms: must be 0.1..1000");
  if (flags.prefetch < 0 || flags.prefetch > 4096) return report_error("--cluster-prefetch: must be 0..4096");
  options.prefetch = flags.prefetch;
  int threads = config.threads;
  if (threads <= 0) threads = int(std::max(1u, std::thread::hardware_concurrency()));
  const std::string verdict =
      session->handshake(load_error, scene ? cluster::scene_fingerprint(*scene) : 0, threads);
  if (!verdict.empty()) return report_error("cluster: " + verdict);  // printed by rank 0 only
  if (session->clients() < 1) return report_error("cluster: no clients");
  if (!session->master()) return session->serve(*scene, config, camera, options);
  config = session->master_config(config);
  return -1;
}

}  // namespace frameless::cli
