// Transparent huge pages for the big arrays that rays reach at random (BVH nodes, triangles,
// vertices, spheres): one 2 MiB page maps what 512 small ones do,
// so a random walk over hundreds of megabytes stops paying a page walk at most steps. The kernel
// picks a page's size when it is first touched, so storage is advised before anything is written.
#pragma once
#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <string_view>
#include <vector>

#if defined(__linux__)
#include <sys/mman.h>
#endif

namespace frameless {

inline constexpr size_t kHugePage = size_t(2) << 20;
// Arrays smaller than this keep ordinary pages (a huge page half used is memory wasted).
inline constexpr size_t kHugeArrayMin = 4 * kHugePage;

// Whether to ask at all: FRAMELESS_HUGE_PAGES=0 in the environment turns the advice off (to
// measure it, or where a sandbox's memory handles it badly), read once.
inline bool huge_pages_wanted() {
  static const bool wanted = [] {
    const char* e = std::getenv("FRAMELESS_HUGE_PAGES");
    return !(e && std::string_view(e) == "0");
  }();
  return wanted;
}

// Asks for huge pages on the whole 2 MiB pages inside [data, data + bytes). A hint: where the
// kernel has them off (or another system), nothing changes.
inline void advise_huge_pages(const void* data, size_t bytes) {
#if defined(__linux__) && defined(MADV_HUGEPAGE)
  if (!huge_pages_wanted()) return;
  const uintptr_t begin = (uintptr_t(data) + kHugePage - 1) & ~uintptr_t(kHugePage - 1);
  const uintptr_t end = (uintptr_t(data) + bytes) & ~uintptr_t(kHugePage - 1);
  if (end > begin) (void)madvise(reinterpret_cast<void*>(begin), end - begin, MADV_HUGEPAGE);
#else
  (void)data;
  (void)bytes;
#endif
}

// Room for `n` elements in new storage advised before use; `v` keeps its elements (copied in).
// Small arrays are reserved as usual.
template <class T>
void reserve_huge(std::vector<T>& v, size_t n) {
  if (n * sizeof(T) < kHugeArrayMin) {
    v.reserve(n);
    return;
  }
  std::vector<T> fresh;
  fresh.reserve(std::max(n, v.size()));
  advise_huge_pages(fresh.data(), fresh.capacity() * sizeof(T));
  fresh.insert(fresh.end(), v.begin(), v.end());
  v.swap(fresh);
}

// `v`'s elements moved into storage advised for huge pages (a copy, once, after an array is
// built by code that cannot reserve ahead: loaders, generators).
template <class T>
void rehome_huge(std::vector<T>& v) {
  if (v.size() * sizeof(T) >= kHugeArrayMin) reserve_huge(v, v.size());
}

// resize and assign that take advised storage whenever they must grow.
template <class T>
void resize_huge(std::vector<T>& v, size_t n) {
  if (n > v.capacity()) reserve_huge(v, n);
  v.resize(n);
}
template <class T>
void assign_huge(std::vector<T>& v, size_t n, const T& value) {
  if (n > v.capacity()) {
    std::vector<T>().swap(v);  // nothing to keep: the old elements are not copied
    reserve_huge(v, n);
  }
  v.assign(n, value);
}

}  // namespace frameless
