// Joining the cluster from a command.
#include "bench/cluster_join.h"

#include <thread>

#include "bench/bench_options.h"

namespace frameless::bench {

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
  if (requested.wire != "exact" && requested.wire != "rgbe")
    return report_error("--cluster-wire: expected exact or rgbe, got '" + requested.wire + "'");
  options.wire = requested.wire == "rgbe" ? cluster::WireFormat::rgbe : cluster::WireFormat::exact;
  options.batch_ms = requested.batch_ms;
  if (options.wire == cluster::WireFormat::rgbe && config.deterministic)
    return report_error("--cluster-wire rgbe: deterministic runs need the exact wire format");
  if (!(options.batch_ms >= 0.1 && options.batch_ms <= 1000))
    return report_error("--cluster-batch-ms: must be 0.1..1000");
  if (requested.prefetch < 0 || requested.prefetch > 4096) return report_error("--cluster-prefetch: must be 0..4096");
  options.prefetch = requested.prefetch;
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

}  // namespace frameless::bench
