// `frameless bench cluster`: its flags; the benchmark is bench::run_cluster
// (src/bench/bench_cluster.h).
#include <memory>

#include "bench/bench_cluster.h"
#include "tools/cluster_flags.h"
#include "tools/command_registry.h"
#include "tools/tool_options.h"

namespace frameless::cli {
namespace {

const bool bench_cluster_registered = register_command(
    "bench", "cluster",
    "Frameless across Open MPI ranks: updates/s, wire bytes, master CPU, RTT, latency, scaling",
    [](CLI::App& app) {
      auto a = std::make_shared<bench::ClusterBenchOptions>();
      app.add_option("scene", a->scene, "built-in name, .json scene or model")->capture_default_str();
      add_shadow_flags(app, a->shadows);
      add_cluster_flags(app, a->cluster);
      app.add_option("--size", a->size, "image size WxH")->capture_default_str();
      app.add_option("--threads", a->threads, "render threads per client (and of the one process)")
          ->capture_default_str();
      app.add_option("--clients", a->clients, "measure jobs of 1..N clients (mpirun -np 2..N+1)")
          ->capture_default_str();
      app.add_option("--seconds", a->seconds, "seconds per throughput measurement")->capture_default_str();
      app.add_option("--mode", a->mode, "frameless, or conventional (OpenRT's pieces on demand)")
          ->capture_default_str();
      app.add_flag("--json", a->json, "print JSON");
      app.add_flag("--one", a->one, "one job: run under mpirun; rank 0 prints its JSON");
      app.footer("Runs mpirun itself (localhost, --oversubscribe). For other machines run one job:\n"
                 "  mpirun --hostfile hosts -np 5 frameless bench cluster --one default");
      return [a] { return bench::run_cluster(*a); };
    });

}  // namespace
}  // namespace frameless::cli
