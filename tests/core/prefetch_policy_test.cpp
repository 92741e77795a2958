// The BVH walks' prefetch policy (core/accel/prefetch_policy.h): a tree whose hot part stays in
// the core's L2 cache is walked without prefetches, a much bigger one with them; the
// environment overrides both.
#include "core/accel/prefetch_policy.h"

#include <gtest/gtest.h>

#include <cstdlib>

namespace frameless {
namespace {

TEST(PrefetchPolicy, OnlyTreesWellBeyondTheL2CachePrefetch) {
  if (std::getenv("FRAMELESS_PREFETCH")) GTEST_SKIP() << "FRAMELESS_PREFETCH decides in this environment";
  const size_t l2 = l2_cache_bytes();
  EXPECT_GE(l2, size_t(1) << 16);  // a real cache size (or the 1 MiB stand-in)
  EXPECT_FALSE(prefetch_wanted(0));
  EXPECT_FALSE(prefetch_wanted(l2));
  EXPECT_FALSE(prefetch_wanted(kPrefetchTreeToL2 * l2));
  EXPECT_TRUE(prefetch_wanted(kPrefetchTreeToL2 * l2 + 1));
  EXPECT_TRUE(prefetch_wanted(size_t(1) << 40));
}

}  // namespace
}  // namespace frameless
