// Turns an update trace into the statistics of issue 5 (see docs/stats.md for their meaning).
#include "frameless/stats_analysis.h"

#include <algorithm>
#include <cmath>

namespace frameless {

ChunkLayout make_chunk_layout(int width, int height, int chunk_size, PixelOrder order, uint64_t seed) {
  // One thread and no shuffle: the partition's pixel list is the order's line itself.
  PartitionConfig pc;
  pc.width = width;
  pc.height = height;
  pc.threads = 1;
  pc.chunk_size = chunk_size;
  pc.order = order == PixelOrder::hilbert_shuffled ? PixelOrder::hilbert : order;
  pc.seed = seed;
  const Partition p = make_partition(pc);
  ChunkLayout layout;
  layout.width = p.width;
  layout.height = p.height;
  layout.chunk_size = p.chunk_size;
  const std::vector<uint32_t>& line = p.pixels[0];
  for (size_t s = 0; s < line.size(); s += size_t(p.chunk_size))
    layout.chunks.emplace_back(line.begin() + std::ptrdiff_t(s),
                               line.begin() + std::ptrdiff_t(std::min(line.size(), s + size_t(p.chunk_size))));
  return layout;
}

UniformityStats analyze_uniformity(const std::vector<uint32_t>& counts) {
  UniformityStats u;
  if (counts.empty()) return u;
  u.min = *std::min_element(counts.begin(), counts.end());
  u.max = *std::max_element(counts.begin(), counts.end());
  double sum = 0, sum2 = 0;
  for (uint32_t c : counts) {
    sum += c;
    sum2 += double(c) * c;
  }
  const double n = double(counts.size());
  u.mean = sum / n;
  const double var = std::max(0.0, sum2 / n - u.mean * u.mean);
  u.cv = u.mean > 0 ? std::sqrt(var) / u.mean : 0.0;
  u.chi2 = chi_square_equal_rates(counts);
  return u;
}

std::vector<std::vector<uint8_t>> interval_masks(const UpdateTrace& t, uint32_t begin, uint32_t end) {
  const size_t n = size_t(t.width) * size_t(t.height);
  std::vector<std::vector<uint8_t>> masks(end > begin ? end - begin : 0, std::vector<uint8_t>(n, 0));
  for (const auto& log : t.logs)
    for (const UpdateRecord& r : log)
      if (r.display_tick >= begin && r.display_tick < end && r.pixel < n)
        masks[r.display_tick - begin][r.pixel] = 1;
  return masks;
}

TemporalStats analyze_temporal(const UpdateTrace& t) {
  TemporalStats s;
  const size_t n = size_t(t.width) * size_t(t.height);
  std::vector<float> last(n, -1.0f);
  double sum = 0, sum2 = 0;
  // A pixel belongs to one thread, whose log is in time order.
  for (const auto& log : t.logs)
    for (const UpdateRecord& r : log) {
      if (r.pixel >= n) continue;
      if (last[r.pixel] >= 0.0f) {
        const double gap = double(r.time) - double(last[r.pixel]);
        sum += gap;
        sum2 += gap * gap;
        s.max_seconds = std::max(s.max_seconds, gap);
        ++s.intervals;
      }
      last[r.pixel] = r.time;
    }
  if (s.intervals == 0) return s;
  const double k = double(s.intervals);
  s.mean_seconds = sum / k;
  const double var = std::max(0.0, sum2 / k - s.mean_seconds * s.mean_seconds);
  s.cv = s.mean_seconds > 0 ? std::sqrt(var) / s.mean_seconds : 0.0;
  if (t.sweep_seconds > 0) {
    s.mean_sweeps = s.mean_seconds / t.sweep_seconds;
    s.max_sweeps = s.max_seconds / t.sweep_seconds;
  }
  return s;
}

StalenessStats analyze_staleness(const UpdateTrace& t, const TemporalStats& temporal,
                                 int curve_points) {
  StalenessStats s;
  s.bound_sweeps = 1.0 + t.update_percent / 100.0;
  s.max_age_sweeps = temporal.max_sweeps;
  if (t.change_time < 0 || t.sweep_seconds <= 0) return s;
  s.measured = true;
  const size_t n = size_t(t.width) * size_t(t.height);
  const double inf = std::numeric_limits<double>::infinity();
  std::vector<double> first(n, inf);  // time the pixel first showed the new camera
  for (const auto& log : t.logs)
    for (const UpdateRecord& r : log)
      if (r.pixel < n && r.epoch >= t.change_epoch && first[r.pixel] == inf) first[r.pixel] = r.time;
  std::vector<double> age;
  age.reserve(n);
  for (double f : first) {
    if (f == inf) {
      ++s.never;
      continue;
    }
    age.push_back(std::max(0.0, (f - t.change_time) / t.sweep_seconds));
  }
  std::sort(age.begin(), age.end());
  // Quantile q of all n pixels (never-updated ones count as infinitely late).
  auto quantile = [&](double q) {
    const size_t k = size_t(std::ceil(q * double(n)));
    if (k == 0) return 0.0;
    return k <= age.size() ? age[k - 1] : inf;
  };
  s.t50_sweeps = quantile(0.5);
  s.t95_sweeps = quantile(0.95);
  s.t100_sweeps = quantile(1.0);
  const double span = std::isfinite(s.t100_sweeps) ? std::max(s.t100_sweeps, s.bound_sweeps) * 1.1
                                                   : s.bound_sweeps * 1.5;
  for (int i = 0; i < curve_points; ++i) {
    const double x = span * i / std::max(1, curve_points - 1);
    const size_t k = size_t(std::upper_bound(age.begin(), age.end(), x) - age.begin());
    s.curve_sweeps.push_back(x);
    s.curve_fraction.push_back(double(k) / double(n));
  }
  return s;
}

BalanceStats analyze_balance(const UpdateTrace& t) {
  BalanceStats b;
  b.pixels = t.thread_pixels;
  for (const auto& log : t.logs) b.updates.push_back(log.size());
  b.samples_per_s = t.thread_samples_per_s;
  b.busy_s = t.thread_busy_s;
  if (!b.pixels.empty()) {
    const auto [lo, hi] = std::minmax_element(b.pixels.begin(), b.pixels.end());
    b.pixel_spread = *hi - *lo;
  }
  b.within_one_chunk = b.pixel_spread <= uint64_t(std::max(1, t.chunk_size));
  return b;
}

OrderStats analyze_trace(const UpdateTrace& t, const StructureOptions& options) {
  OrderStats s;
  const size_t n = size_t(t.width) * size_t(t.height);
  std::vector<uint32_t> counts(n, 0);
  for (const auto& log : t.logs)
    for (const UpdateRecord& r : log)
      if (r.pixel < n) ++counts[r.pixel];
  s.uniformity = analyze_uniformity(counts);

  const auto masks = interval_masks(t, t.mask_ticks_begin, t.mask_ticks_end);
  const ChunkNull null = make_chunk_null(make_chunk_layout(t.width, t.height, t.chunk_size, t.order, t.seed));
  s.structure = analyze_structure(masks, null, options);
  if (!masks.empty()) {
    s.typical_mask = masks[masks.size() / 2];
    s.typical_mask_tick = t.mask_ticks_begin + uint32_t(masks.size() / 2);
  }
  s.temporal = analyze_temporal(t);
  s.staleness = analyze_staleness(t, s.temporal);
  s.balance = analyze_balance(t);
  return s;
}

}  // namespace frameless
