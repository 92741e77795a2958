// The core owns no threads: work that may fan out takes the caller's executor. It runs body(i)
// for every i in [0, n), possibly concurrently, and returns when all are done; empty: serial.
#pragma once
#include <cstddef>
#include <functional>

namespace frameless {

using ParallelFor = std::function<void(size_t n, const std::function<void(size_t)>& body)>;

inline void parallel_for_each(const ParallelFor& pf, size_t n, const std::function<void(size_t)>& body) {
  if (pf) {
    pf(n, body);
  } else {
    for (size_t i = 0; i < n; ++i) body(i);
  }
}

}  // namespace frameless
