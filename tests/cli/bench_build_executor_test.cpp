// Benchmarks that report build times choose how scene loads build (bench_options.h): inside a
// ScopedBuildExecutor the scene's build runs through it, and the process default comes back after.
#include <gtest/gtest.h>

#include <atomic>
#include <memory>

#include "bench/bench_options.h"
#include "core/scene/scene_finalize.h"
#include "core/scenes/scene_load.h"

namespace frameless::bench {
namespace {

TEST(ScopedBuildExecutor, LoadsBuildThroughItAndTheDefaultComesBack) {
  auto outer = std::make_shared<std::atomic<int>>(0), inner = std::make_shared<std::atomic<int>>(0);
  const auto counting = [](std::shared_ptr<std::atomic<int>> calls) {
    return ParallelFor([calls](size_t n, const std::function<void(size_t)>& body) {
      calls->fetch_add(1);
      for (size_t i = 0; i < n; ++i) body(i);
    });
  };
  set_default_build_executor(counting(outer));
  {
    const ScopedBuildExecutor scope(counting(inner));
    ASSERT_TRUE(load_scene("soup:70000:3").ok());  // above the parallel threshold (65,536)
    EXPECT_GT(inner->load(), 0);
    EXPECT_EQ(outer->load(), 0);
    const ScopedBuildExecutor one_thread({});
    const int before = inner->load();
    ASSERT_TRUE(load_scene("soup:70000:4").ok());
    EXPECT_EQ(inner->load(), before);  // empty: serial
  }
  ASSERT_TRUE(load_scene("soup:70000:5").ok());
  EXPECT_GT(outer->load(), 0);  // the default is back
  set_default_build_executor({});
}

}  // namespace
}  // namespace frameless::bench
