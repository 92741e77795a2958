// Hilbert line -> chunks -> round-robin -> per-thread seeded chunk shuffle.
#include "frameless/partition.h"

#include <algorithm>
#include <numeric>

#include "core/base/rng.h"
#include "frameless/hilbert.h"

namespace frameless {

const char* to_string(PixelOrder order) {
  switch (order) {
    case PixelOrder::hilbert_shuffled: return "hilbert-shuffled";
    case PixelOrder::hilbert: return "hilbert";
    case PixelOrder::scanline: return "scanline";
    case PixelOrder::random: return "random";
  }
  return "?";
}

std::optional<PixelOrder> parse_pixel_order(const std::string& text) {
  for (PixelOrder o : {PixelOrder::hilbert_shuffled, PixelOrder::hilbert, PixelOrder::scanline,
                       PixelOrder::random})
    if (text == to_string(o)) return o;
  return std::nullopt;
}

namespace {

// Fisher-Yates with our counter-based generator, so partitions are identical on every platform.
template <class T>
void shuffle(std::vector<T>& v, uint64_t seed) {
  Rng rng(seed);
  for (size_t i = v.size(); i > 1; --i) {
    const size_t j = size_t((uint64_t(rng.next_u32()) * i) >> 32);
    std::swap(v[i - 1], v[j]);
  }
}

}  // namespace

Partition make_partition(const PartitionConfig& c) {
  Partition p;
  p.width = std::max(1, c.width);
  p.height = std::max(1, c.height);
  p.chunk_size = std::max(1, c.chunk_size);
  const int threads = std::max(1, c.threads);
  const size_t n = size_t(p.width) * size_t(p.height);

  std::vector<uint32_t> line;
  if (c.order == PixelOrder::hilbert_shuffled || c.order == PixelOrder::hilbert) {
    line = hilbert_order(p.width, p.height);
  } else {
    line.resize(n);
    std::iota(line.begin(), line.end(), 0u);
    if (c.order == PixelOrder::random) shuffle(line, mix64(c.seed ^ 0x72616e646f6dull));
  }

  // Deal chunks round-robin; remember each thread's chunk starts so they can be shuffled.
  const size_t chunk = size_t(p.chunk_size);
  const size_t chunks = (n + chunk - 1) / chunk;
  std::vector<std::vector<size_t>> starts(static_cast<size_t>(threads));
  for (size_t k = 0; k < chunks; ++k) starts[k % size_t(threads)].push_back(k * chunk);

  p.pixels.resize(size_t(threads));
  p.short_chunk_at.assign(size_t(threads), SIZE_MAX);
  for (int t = 0; t < threads; ++t) {
    auto& mine = starts[size_t(t)];
    if (c.order == PixelOrder::hilbert_shuffled) shuffle(mine, mix64(c.seed + 0x1000u * uint64_t(t + 1)));
    auto& out = p.pixels[size_t(t)];
    out.reserve(mine.size() * chunk);
    for (size_t s : mine) {
      if (s + chunk > n) p.short_chunk_at[size_t(t)] = out.size();
      for (size_t i = s; i < std::min(n, s + chunk); ++i) out.push_back(line[i]);
    }
  }
  return p;
}

std::vector<uint32_t> slot_order(const Partition& partition) {
  std::vector<uint32_t> order;
  for (const std::vector<uint32_t>& list : partition.pixels) order.insert(order.end(), list.begin(), list.end());
  return order;
}

}  // namespace frameless
