// Joining the cluster from a command.
#include "tools/cluster_join.h"

#include <thread>

#include "tools/common_options.h"

namespace frameless::cli {

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
  if (config.mode != RenderMode::frameless)  // every rank sees the same flags: all stop here
    return report_error("cluster: conventional mode is not distributed yet; run frameless mode");
  int threads = config.threads;
  if (threads <= 0) threads = int(std::max(1u, std::thread::hardware_concurrency()));
  const std::string verdict =
      session->handshake(load_error, scene ? cluster::scene_fingerprint(*scene) : 0, threads);
  if (!verdict.empty()) return report_error("cluster: " + verdict);  // printed by rank 0 only
  if (session->clients() < 1) return report_error("cluster: no clients");
  if (!session->master()) return session->serve(*scene, config, camera);
  config = session->master_config(config);
  return -1;
}

}  // namespace frameless::cli
