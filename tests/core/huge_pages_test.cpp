// Storage advised for transparent huge pages (core/base/huge_pages.h): elements survive every
// move into new storage, and on a kernel that offers huge pages on request the big arrays get them.
#include "core/base/huge_pages.h"

#include <gtest/gtest.h>

#include <cstdint>
#include <cstdio>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

namespace frameless {
namespace {

std::vector<uint32_t> counting(size_t n) {
  std::vector<uint32_t> v(n);
  for (size_t i = 0; i < n; ++i) v[i] = uint32_t(i * 2654435761u);
  return v;
}

TEST(HugePages, ReserveKeepsTheElementsAndMakesRoom) {
  const size_t n = (kHugeArrayMin / sizeof(uint32_t)) * 2;  // 16 MiB: advised
  std::vector<uint32_t> v = counting(n);
  reserve_huge(v, n + n / 2);
  ASSERT_EQ(v.size(), n);
  EXPECT_GE(v.capacity(), n + n / 2);
  EXPECT_EQ(v, counting(n));
  std::vector<uint32_t> small = counting(100);  // under the threshold: an ordinary reserve
  reserve_huge(small, 1000);
  EXPECT_GE(small.capacity(), 1000u);
  EXPECT_EQ(small, counting(100));
}

TEST(HugePages, ResizeAssignAndRehomeKeepWhatTheyShould) {
  const size_t n = kHugeArrayMin / sizeof(uint32_t) + 7;
  std::vector<uint32_t> v = counting(100);
  resize_huge(v, n);  // grows: the first 100 stay, the rest are zero
  ASSERT_EQ(v.size(), n);
  for (size_t i = 0; i < 100; ++i) ASSERT_EQ(v[i], uint32_t(i * 2654435761u));
  for (size_t i = 100; i < n; ++i) ASSERT_EQ(v[i], 0u) << i;
  assign_huge(v, 2 * n, 7u);
  ASSERT_EQ(v.size(), 2 * n);
  for (uint32_t x : v) ASSERT_EQ(x, 7u);
  assign_huge(v, 10, 3u);  // shrinking keeps the storage
  EXPECT_EQ(v, std::vector<uint32_t>(10, 3u));
  std::vector<uint32_t> r = counting(n);
  rehome_huge(r);
  EXPECT_EQ(r, counting(n));
}

// The kernel's transparent huge page mode ("always", "madvise" or "never"), empty if unknown.
std::string thp_mode() {
  std::ifstream f("/sys/kernel/mm/transparent_hugepage/enabled");
  std::string line;
  std::getline(f, line);
  const size_t a = line.find('['), b = line.find(']');
  return a == std::string::npos || b == std::string::npos ? "" : line.substr(a + 1, b - a - 1);
}

// AnonHugePages (kB) of the mapping that holds `p`, from /proc/self/smaps; -1 if not found.
long huge_kb_at(const void* p) {
  std::ifstream f("/proc/self/smaps");
  std::string line;
  bool inside = false;
  const uintptr_t at = uintptr_t(p);
  while (std::getline(f, line)) {
    unsigned long lo = 0, hi = 0;
    if (std::sscanf(line.c_str(), "%lx-%lx ", &lo, &hi) == 2 && line.find(':') > line.find(' ')) {
      inside = at >= lo && at < hi;
      continue;
    }
    long kb = 0;
    if (inside && std::sscanf(line.c_str(), "AnonHugePages: %ld kB", &kb) == 1) return kb;
  }
  return -1;
}

TEST(HugePages, BigArraysGetHugePagesWhereTheKernelOffersThemOnRequest) {
  const std::string mode = thp_mode();
  if (mode != "madvise" && mode != "always") GTEST_SKIP() << "transparent huge pages: " << (mode.empty() ? "unknown" : mode);
  std::vector<uint64_t> big;
  assign_huge(big, size_t(64) << 17, uint64_t(1));  // 64 MiB, written after the advice
  const long kb = huge_kb_at(big.data() + big.size() / 2);
  ASSERT_GE(kb, 0) << "mapping not found in /proc/self/smaps";
  EXPECT_GT(kb, 0) << "no huge pages under a 64 MiB advised array (mode " << mode << ")";
}

}  // namespace
}  // namespace frameless
