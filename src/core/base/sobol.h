// Owen-scrambled Sobol' points in two dimensions (Burley 2020, "Practical Hash-based Owen
// Scrambling"): the first 2^k points of a pixel's sequence form a (0, 2)-net, so a pixel's
// jitter is stratified at every power of two of its sample count. Pure, any thread.
#pragma once
#include <cstdint>

#include "core/base/rng.h"

namespace frameless {

inline uint32_t reverse_bits(uint32_t x) {
  x = (x << 16) | (x >> 16);
  x = ((x & 0x00ff00ffu) << 8) | ((x & 0xff00ff00u) >> 8);
  x = ((x & 0x0f0f0f0fu) << 4) | ((x & 0xf0f0f0f0u) >> 4);
  x = ((x & 0x33333333u) << 2) | ((x & 0xccccccccu) >> 2);
  return ((x & 0x55555555u) << 1) | ((x & 0xaaaaaaaau) >> 1);
}

// Nested uniform scramble of a 32-bit fixed-point coordinate: each bit is flipped by a hash of
// the bits above it (Laine and Karras 2011's hash with Burley's constants, on reversed bits).
inline uint32_t owen_scramble(uint32_t x, uint32_t seed) {
  x = reverse_bits(x);
  x += seed;
  x ^= x * 0x6c50b47cu;
  x ^= x * 0xb82f1e52u;
  x ^= x * 0xc7afe638u;
  x ^= x * 0x8d22f6e6u;
  return reverse_bits(x);
}

// Point `index` of the Sobol' sequence's first two dimensions, Owen-scrambled by `seed`, in
// [0, 1)^2.
inline void owen_sobol_2d(uint32_t index, uint64_t seed, float& u, float& v) {
  uint32_t y = 0;
  for (uint32_t i = index, d = 1u << 31; i; i >>= 1, d ^= d >> 1)
    if (i & 1u) y ^= d;
  const uint64_t h = mix64(seed);
  u = float(owen_scramble(reverse_bits(index), uint32_t(h)) >> 8) * 0x1.0p-24f;
  v = float(owen_scramble(y, uint32_t(h >> 32)) >> 8) * 0x1.0p-24f;
}

}  // namespace frameless
