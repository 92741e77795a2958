// Static assignment of pixels to render threads (Parker et al. 1999, section 2.2); built on the
// control thread, then read-only.
#pragma once
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

namespace frameless {

// How the image is linearised and dealt out; issue 5 compares these.
enum class PixelOrder {
  hilbert_shuffled,  // Hilbert curve -> chunks -> round-robin -> per-thread seeded chunk shuffle (default)
  hilbert,           // as above without the shuffle: each thread walks its chunks along the curve
  scanline,          // row-major line -> chunks -> round-robin, no shuffle
  random,            // seeded random permutation of all pixels -> chunks -> round-robin
};

// "hilbert-shuffled", "hilbert", "scanline", "random".
const char* to_string(PixelOrder order);
std::optional<PixelOrder> parse_pixel_order(const std::string& text);

struct PartitionConfig {
  int width = 1;                                  // image width in pixels (>= 1)
  int height = 1;                                 // image height in pixels (>= 1)
  int threads = 1;                                // number of render threads (>= 1)
  int chunk_size = 64;                            // pixels per chunk of the line (>= 1)
  PixelOrder order = PixelOrder::hilbert_shuffled;  // linearisation and shuffling
  uint64_t seed = 1;                              // seeds the shuffles
};

// pixels[t] lists thread t's pixel indices (y * width + x) in the order it visits them, forever
// repeating. Counts differ by at most one chunk; the union is every pixel exactly once.
struct Partition {
  int width = 0;
  int height = 0;
  int chunk_size = 0;
  std::vector<std::vector<uint32_t>> pixels;
  // Per thread: the list position of its chunk that is shorter than chunk_size (the line's last,
  // when chunk_size does not divide the pixel count), or SIZE_MAX. Every other chunk of a list
  // starts at a multiple of chunk_size before it, or at one past it shifted by its length.
  std::vector<size_t> short_chunk_at;
  // The number of pixels in chunk starting at `pos` of thread t's list.
  size_t chunk_length(int t, size_t pos) const {
    const size_t n = size_t(width) * size_t(height), c = size_t(chunk_size);
    return pos == short_chunk_at[size_t(t)] ? n % c : c;
  }
};

Partition make_partition(const PartitionConfig& config);

// The threads' lists one after another: the engine's slot order (slot s shows pixel result[s]).
std::vector<uint32_t> slot_order(const Partition& partition);

}  // namespace frameless
