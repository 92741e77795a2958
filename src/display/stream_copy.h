// Whole-image copies with streaming stores (display thread): what a whole copy writes is next read
// a tick or more later, by when the render threads have pushed it out of the caches, so reading
// each destination line before writing it (what an ordinary store does) is wasted. glibc's memcpy
// streams only above a threshold drawn from the reported cache size, which a virtual machine may
// overstate (this project's 2-core VM reports a 480 MB L3: 15 MB copies went through the caches).
#pragma once
#include <cstddef>
#include <cstdint>
#include <cstring>

#if defined(__SSE2__)
#include <immintrin.h>
#endif

namespace frameless {

// Copies `bytes` bytes; both pointers and `bytes` multiples of 16 (else a plain memcpy).
inline void stream_copy(void* dst, const void* src, size_t bytes) {
#if defined(__SSE2__)
  if ((reinterpret_cast<uintptr_t>(dst) | reinterpret_cast<uintptr_t>(src) | bytes) & 15) {
    std::memcpy(dst, src, bytes);
    return;
  }
  auto* d = static_cast<char*>(dst);
  const auto* s = static_cast<const char*>(src);
  const char* end = s + bytes;
#if defined(__AVX512F__)
  // Sixteen bytes at a time up to the destination's first whole line, then lines.
  while (s < end && (reinterpret_cast<uintptr_t>(d) & 63))
    _mm_stream_si128(reinterpret_cast<__m128i*>(d), _mm_load_si128(reinterpret_cast<const __m128i*>(s))), d += 16, s += 16;
  for (; end - s >= 64; d += 64, s += 64)
    _mm512_stream_si512(reinterpret_cast<__m512i*>(d), _mm512_loadu_si512(s));
#endif
  for (; s < end; d += 16, s += 16)
    _mm_stream_si128(reinterpret_cast<__m128i*>(d), _mm_load_si128(reinterpret_cast<const __m128i*>(s)));
  _mm_sfence();  // ordered before the image is handed on
#else
  std::memcpy(dst, src, bytes);
#endif
}

}  // namespace frameless
