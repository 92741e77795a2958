// The application's executor (frameless/thread_executor.h) and scene loading through it: every
// index runs once, and a scene built on several threads is the one a single thread builds. Runs
// under ThreadSanitizer with the engine suite.
#include <atomic>
#include <memory>
#include <vector>

#include <gtest/gtest.h>

#include "core/scene/scene_finalize.h"
#include "core/scenes/scene_load.h"
#include "frameless/thread_executor.h"

namespace frameless {
namespace {

TEST(ThreadExecutor, RunsEveryIndexOnce) {
  for (const int threads : {1, 3, 0}) {
    const ParallelFor pf = thread_executor(threads);
    for (const size_t n : {size_t(0), size_t(1), size_t(7), size_t(1000)}) {
      std::vector<std::atomic<int>> runs(n);
      for (auto& r : runs) r.store(0);
      pf(n, [&](size_t i) { runs[i].fetch_add(1, std::memory_order_relaxed); });
      for (size_t i = 0; i < n; ++i) ASSERT_EQ(runs[i].load(), 1) << "threads " << threads << ", n " << n << ", i " << i;
    }
  }
}

// Restores the default executor (none) however the test ends.
struct DefaultExecutorGuard {
  ~DefaultExecutorGuard() { set_default_build_executor({}); }
};

TEST(ThreadExecutor, SceneLoadsBuildThroughTheDefaultExecutorLikeOneThread) {
  DefaultExecutorGuard guard;
  // 100,000 triangles: above the builder's parallel threshold (65,536 references).
  const char* spec = "soup:100000:5";
  set_default_build_executor({});
  auto serial = load_scene(spec);
  ASSERT_TRUE(serial.ok()) << serial.error().message;
  auto calls = std::make_shared<std::atomic<int>>(0);
  const ParallelFor threads = thread_executor(3);
  set_default_build_executor([calls, threads](size_t n, const std::function<void(size_t)>& body) {
    calls->fetch_add(1, std::memory_order_relaxed);
    threads(n, body);
  });
  auto parallel = load_scene(spec);
  ASSERT_TRUE(parallel.ok()) << parallel.error().message;
  EXPECT_GT(calls->load(), 0);
  // The same tree: the primitives in the same leaf order, the same node count.
  EXPECT_EQ((*serial)->geometry.triangles, (*parallel)->geometry.triangles);
  EXPECT_EQ((*serial)->accel.stats().nodes, (*parallel)->accel.stats().nodes);
  EXPECT_EQ((*serial)->accel.stats().depth, (*parallel)->accel.stats().depth);
  // A build's own executor wins over the default.
  Scene& s = **serial;
  set_accel(s, AccelKind::kGrid);
  const int before = calls->load();
  AccelConfig own;
  int own_calls = 0;
  own.parallel_for = [&own_calls](size_t n, const std::function<void(size_t)>& body) {
    ++own_calls;
    for (size_t i = 0; i < n; ++i) body(i);
  };
  set_accel(s, AccelKind::kBvh, own);
  EXPECT_GT(own_calls, 0);
  EXPECT_EQ(calls->load(), before);
}

}  // namespace
}  // namespace frameless
