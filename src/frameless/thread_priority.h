// Render threads step aside for interactive work: lower_thread_priority(n) raises the calling
// thread's nice value by n (Linux: nice is per thread; raising it needs no privilege), so a
// display thread or a window that wakes gets a core at once instead of waiting out a render
// thread's time slice. Best effort: elsewhere, or if the system refuses, nothing changes.
#pragma once

#if defined(__linux__)
#include <sys/resource.h>
#include <sys/syscall.h>
#include <unistd.h>

#include <cerrno>
#endif

namespace frameless {

inline void lower_thread_priority(int n) {
#if defined(__linux__)
  if (n <= 0) return;
  const id_t tid = id_t(syscall(SYS_gettid));
  errno = 0;
  const int now = getpriority(PRIO_PROCESS, tid);  // -1 is a valid nice value: errno tells
  if (errno != 0) return;
  (void)setpriority(PRIO_PROCESS, tid, now + n > 19 ? 19 : now + n);
#else
  (void)n;
#endif
}

}  // namespace frameless
