// Counter-based random numbers: a sample's randomness is a pure function of its inputs; any thread.
#pragma once
#include <cstdint>

namespace frameless {

// SplitMix64 finaliser: a strong 64-bit mix of its input.
inline uint64_t mix64(uint64_t z) {
  z += 0x9e3779b97f4a7c15ull;
  z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ull;
  z = (z ^ (z >> 27)) * 0x94d049bb133111ebull;
  return z ^ (z >> 31);
}

// Seed for pixel (x, y), sample index s, global seed g.
inline uint64_t sample_seed(uint32_t x, uint32_t y, uint32_t s, uint64_t g) {
  return mix64(g ^ mix64((uint64_t(x) << 32 | y) ^ mix64(s)));
}

// Small sequential generator (PCG32-style output on a 64-bit LCG state).
struct Rng {
  uint64_t state;
  explicit Rng(uint64_t seed) : state(mix64(seed)) {}
  uint32_t next_u32() {
    const uint64_t old = state;
    state = old * 6364136223846793005ull + 1442695040888963407ull;
    const uint32_t xorshifted = uint32_t(((old >> 18u) ^ old) >> 27u);
    const uint32_t rot = uint32_t(old >> 59u);
    return (xorshifted >> rot) | (xorshifted << ((-rot) & 31));
  }
  // Uniform float in [0, 1).
  float next_float() { return float(next_u32() >> 8) * 0x1.0p-24f; }
};

}  // namespace frameless
