// The prefetch policy of the BVH walks (prefetch_policy.h).
#include "core/accel/prefetch_policy.h"

#include <unistd.h>

#include <cstdlib>

namespace frameless {

size_t last_level_cache_bytes() {
  static const size_t bytes = [] {
    for (const int name : {_SC_LEVEL3_CACHE_SIZE, _SC_LEVEL2_CACHE_SIZE}) {
      const long b = sysconf(name);
      if (b > 0) return size_t(b);
    }
    return size_t(32) << 20;  // what the system does not report: a typical server's share
  }();
  return bytes;
}

bool prefetch_wanted(size_t tree_bytes) {
  static const int forced = [] {
    const char* e = std::getenv("FRAMELESS_PREFETCH");
    return e && (e[0] == '0' || e[0] == '1') && e[1] == 0 ? e[0] - '0' : -1;
  }();
  return forced >= 0 ? forced == 1 : tree_bytes > last_level_cache_bytes();
}

}  // namespace frameless
