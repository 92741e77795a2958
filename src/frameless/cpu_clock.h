// CPU time of the calling thread (CLOCK_THREAD_CPUTIME_ID); any thread. A system call (tens of
// nanoseconds through the vDSO at best): call it per batch or per tick, never per sample.
#pragma once
#include <time.h>

#include <cstdint>

namespace frameless {

inline uint64_t thread_cpu_ns() {
  timespec ts{};
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts);
  return uint64_t(ts.tv_sec) * 1000000000ull + uint64_t(ts.tv_nsec);
}

inline double thread_cpu_seconds() { return double(thread_cpu_ns()) * 1e-9; }

}  // namespace frameless
