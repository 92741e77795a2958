// Whether a tree's walks ask for the children they enter ahead of time. Prefetching hides the
// misses of a tree bigger than the last-level cache and only costs instructions on one that fits
// (benchmarks.md, section 28). Any thread.
#pragma once
#include <cstddef>

namespace frameless {

// Bytes of the last-level cache the system reports (32 MiB when it reports none).
size_t last_level_cache_bytes();

// Whether walks of a tree of `tree_bytes` (nodes, leaf triangles, blocks) prefetch: when it is
// larger than the last-level cache. FRAMELESS_PREFETCH=0 or 1 in the environment decides
// instead (a clean A/B in one binary).
bool prefetch_wanted(size_t tree_bytes);

}  // namespace frameless
