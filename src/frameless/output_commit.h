// One process-wide lock around multi-file output commits (a capture's frame files and the
// manifest that lists them). A fatal path that ends the process at once (the cluster's
// MPI_Abort) takes it first, so it never cuts a commit in half: files and index always agree.
#pragma once

#include <mutex>

namespace frameless {

// Held by a writer from its first file of a commit until the index lists them (or they are gone).
std::mutex& output_commit_mutex();

// Called by a fatal path right before the process ends: waits for a commit in progress to finish;
// held until the process is gone, no new commit starts.
[[nodiscard]] std::unique_lock<std::mutex> freeze_output_commits();

}  // namespace frameless
