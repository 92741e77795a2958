// The prefetch policy of the BVH walks (prefetch_policy.h).
#include "core/accel/prefetch_policy.h"

#include <unistd.h>

#include <cstdlib>

namespace frameless {

size_t l2_cache_bytes() {
  static const size_t bytes = [] {
    const long b = sysconf(_SC_LEVEL2_CACHE_SIZE);
    return b > 0 ? size_t(b) : size_t(1) << 20;  // what the system does not report: a typical core's
  }();
  return bytes;
}

bool prefetch_wanted(size_t tree_bytes) {
  static const int forced = [] {
    const char* e = std::getenv("FRAMELESS_PREFETCH");
    return e && (e[0] == '0' || e[0] == '1') && e[1] == 0 ? e[0] - '0' : -1;
  }();
  return forced >= 0 ? forced == 1 : tree_bytes > kPrefetchTreeToL2 * l2_cache_bytes();
}

}  // namespace frameless
