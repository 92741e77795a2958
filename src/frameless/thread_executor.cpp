#include "frameless/thread_executor.h"

#include <algorithm>
#include <atomic>
#include <thread>
#include <vector>

namespace frameless {

ParallelFor thread_executor(int threads) {
  if (threads <= 0) threads = std::max(1, int(std::thread::hardware_concurrency()));
  return [threads](size_t n, const std::function<void(size_t)>& body) {
    std::atomic<size_t> next{0};
    auto worker = [&] {
      for (size_t i; (i = next.fetch_add(1, std::memory_order_relaxed)) < n;) body(i);
    };
    std::vector<std::thread> pool;
    const size_t extra = std::min<size_t>(size_t(threads), n) - (n > 0 ? 1 : 0);
    for (size_t t = 0; t < extra; ++t) pool.emplace_back(worker);
    worker();
    for (std::thread& t : pool) t.join();
  };
}

}  // namespace frameless
