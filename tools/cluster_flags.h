// Flags of a command that can join the cluster under mpirun; the joining is bench::ClusterJoin
// (src/bench/cluster_join.h).
#pragma once
#include <CLI/CLI.hpp>

#include "bench/cluster_join.h"

namespace frameless::cli {

using bench::ClusterJoin;
using bench::ClusterJoinOptions;

// --cluster-wire, --cluster-batch-ms and --cluster-prefetch into `cluster`.
void add_cluster_flags(CLI::App& app, ClusterJoinOptions& cluster);

}  // namespace frameless::cli
