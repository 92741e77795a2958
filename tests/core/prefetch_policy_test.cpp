// The BVH walks' prefetch policy (core/accel/prefetch_policy.h): a tree that fits the last-level
// cache is walked without prefetches, a bigger one with them; the environment overrides both.
#include "core/accel/prefetch_policy.h"

#include <gtest/gtest.h>

#include <cstdlib>

namespace frameless {
namespace {

TEST(PrefetchPolicy, OnlyTreesBiggerThanTheLastLevelCachePrefetch) {
  if (std::getenv("FRAMELESS_PREFETCH")) GTEST_SKIP() << "FRAMELESS_PREFETCH decides in this environment";
  const size_t cache = last_level_cache_bytes();
  EXPECT_GE(cache, size_t(1) << 16);  // a real cache size (or the 32 MiB stand-in)
  EXPECT_FALSE(prefetch_wanted(0));
  EXPECT_FALSE(prefetch_wanted(cache));
  EXPECT_TRUE(prefetch_wanted(cache + 1));
  EXPECT_TRUE(prefetch_wanted(size_t(1) << 40));
}

}  // namespace
}  // namespace frameless
