// Whether a tree's walks ask for the children they enter ahead of time. Prefetching hides the
// misses of a tree much bigger than the core's own cache, and only costs instructions on one
// whose hot part stays there (benchmarks.md, section 28). Any thread.
#pragma once
#include <cstddef>

namespace frameless {

// Bytes of a core's L2 cache as the system reports it (1 MiB when it reports none).
size_t l2_cache_bytes();

// Tree bytes per byte of L2 above which walks prefetch: measured on an Intel Xeon with 2 MiB of
// L2, the bunny's 4.8 MB tree walks faster without (primary rays +7 %, median of 8 rounds) and
// the 44 MB tree of `soup:300000` with (+3 to +7 %, 4 rounds).
inline constexpr size_t kPrefetchTreeToL2 = 4;

// Whether walks of a tree of `tree_bytes` (nodes, leaf triangles, blocks) prefetch: when it is
// more than kPrefetchTreeToL2 times the L2 cache. FRAMELESS_PREFETCH=0 or 1 in the environment
// decides instead (a clean A/B in one binary).
bool prefetch_wanted(size_t tree_bytes);

}  // namespace frameless
