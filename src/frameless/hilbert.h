// Generalized Hilbert curve ("gilbert") over any width x height rectangle; any thread (pure).
#pragma once
#include <cstdint>
#include <vector>

namespace frameless {

// Pixel indices (y * width + x) of a width x height image in generalized-Hilbert order: every
// pixel exactly once, consecutive pixels 4-adjacent except for at most one diagonal step, which
// the construction needs when the longer side is even and the shorter side odd (see
// docs/engine.md). width, height >= 1.
std::vector<uint32_t> hilbert_order(int width, int height);

// Same, appended to `out` (reuses its storage).
void append_hilbert_order(int width, int height, std::vector<uint32_t>& out);

}  // namespace frameless
