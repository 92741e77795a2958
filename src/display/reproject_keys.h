// Reprojection's per-pixel keys and the helpers its scalar and vector paths share
// (reproject.cpp, reproject_avx2.cpp); not a public interface.
#pragma once
#include <cstdint>
#include <cstring>

#include "display/reproject.h"

#if defined(__AVX2__)
#include <immintrin.h>
#endif
#if defined(__AVX512F__) && defined(__GNUC__) && !defined(__clang__)
// GCC 12 flags the deliberately undefined operands inside its own AVX-512 intrinsics in the
// vector paths that include this (clang's -Wsometimes-uninitialized still checks them).
#pragma GCC diagnostic ignored "-Wmaybe-uninitialized"
#endif

namespace frameless::reproject_keys {

constexpr uint32_t kNone = ~0u;
constexpr uint64_t kHole = ~uint64_t(0);  // no point landed (depth bits 0xffffffff: a NaN, never a depth)

// The pairs of opposite neighbours a crack is closed across.
constexpr int kOpposite[4][2] = {{1, 0}, {0, 1}, {1, 1}, {1, -1}};

inline uint32_t depth_bits(uint64_t key) { return uint32_t(key >> 32); }
inline float key_depth(uint64_t key) {
  float d;
  const uint32_t bits = depth_bits(key);
  std::memcpy(&d, &bits, sizeof d);
  return d;
}
// Depths are positive or +infinity, so their bits order as the depths do.
inline uint64_t make_key(float depth, uint32_t source) {
  uint32_t bits;
  std::memcpy(&bits, &depth, sizeof bits);
  return uint64_t(bits) << 32 | source;
}

// The engine's point of unmarked pixel p, all of it from one update: a point its owner keeps
// rewriting counts as none (the pixel moves nowhere this time; its next update is shown in place).
inline ScenePoint engine_point(const SlotImage& img, size_t p) {
  ScenePoint out;
  if (!read_point(img.engine_points[p], out)) out = ScenePoint{};
  return out;
}
}  // namespace frameless::reproject_keys
