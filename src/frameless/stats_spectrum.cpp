// Periodograms of update masks against the randomised-chunk null; Moran's I at two scales.
#include "frameless/stats_spectrum.h"

#include <algorithm>
#include <cmath>
#include <complex>

namespace frameless {
namespace {

// Signed frequency of DFT index k on n points, in cycles per sample.
double signed_freq(int k, int n) { return (2 * k <= n ? double(k) : double(k - n)) / double(n); }

// Cell-density field of a mask: fraction of each cell's pixels updated.
std::vector<double> coarse_field(const std::vector<uint8_t>& mask, int width, int height, int cell,
                                 int& cw, int& ch) {
  cw = (width + cell - 1) / cell;
  ch = (height + cell - 1) / cell;
  std::vector<double> sum(size_t(cw) * size_t(ch), 0.0), area(sum.size(), 0.0);
  for (int y = 0; y < height; ++y)
    for (int x = 0; x < width; ++x) {
      const size_t c = size_t(y / cell) * size_t(cw) + size_t(x / cell);
      sum[c] += mask[size_t(y) * size_t(width) + size_t(x)];
      area[c] += 1.0;
    }
  for (size_t i = 0; i < sum.size(); ++i) sum[i] /= area[i];
  return sum;
}

}  // namespace

ChunkNull make_chunk_null(const ChunkLayout& layout) {
  ChunkNull null;
  null.width = layout.width;
  null.height = layout.height;
  null.chunks = layout.chunks.size();
  const size_t w = size_t(layout.width), h = size_t(layout.height);
  // Histogram of displacements (mod the image size) between pixels of the same chunk.
  std::vector<std::complex<double>> hist(w * h, 0.0);
  std::vector<uint32_t> xs, ys;
  for (const auto& chunk : layout.chunks) {
    xs.clear();
    ys.clear();
    for (uint32_t p : chunk) {
      xs.push_back(p % uint32_t(w));
      ys.push_back(p / uint32_t(w));
    }
    for (size_t a = 0; a < chunk.size(); ++a)
      for (size_t b = 0; b < chunk.size(); ++b) {
        const size_t dx = (xs[a] + w - xs[b]) % w, dy = (ys[a] + h - ys[b]) % h;
        hist[dy * w + dx] += 1.0;
      }
  }
  dft_2d(hist, layout.width, layout.height);
  null.s.resize(w * h);
  for (size_t i = 0; i < hist.size(); ++i) null.s[i] = std::max(0.0, hist[i].real());
  return null;
}

StructureStats analyze_structure(const std::vector<std::vector<uint8_t>>& masks,
                                 const ChunkNull& null, const StructureOptions& o) {
  StructureStats r;
  const int w = null.width, h = null.height;
  const size_t n = size_t(w) * size_t(h);
  if (n < 4 || null.chunks < 2) return r;
  const double cc = double(null.chunks) / double(null.chunks - 1);
  const int bins = int(std::ceil(std::sqrt(0.5) / o.radial_bin)) + 1;
  std::vector<double> bin_ratio(size_t(bins), 0.0), bin_white(size_t(bins), 0.0);
  std::vector<uint64_t> bin_count(size_t(bins), 0);
  int cell = o.coarse_cell;
  if (cell <= 0) {
    const size_t chunk = n / null.chunks;
    cell = 2 * int(std::ceil(std::sqrt(double(std::max<size_t>(1, chunk)))));
  }
  r.coarse_cell = cell;
  double low_sum = 0, low_white = 0;
  std::vector<std::complex<double>> f(n);
  for (const auto& mask : masks) {
    if (mask.size() != n) continue;
    size_t count = 0;
    for (uint8_t v : mask) count += v ? 1 : 0;
    if (count == 0 || count == n) continue;
    const double q = double(count) / double(n);
    ++r.masks;
    r.mean_density += q;
    for (size_t i = 0; i < n; ++i) f[i] = (mask[i] ? 1.0 : 0.0) - q;
    dft_2d(f, w, h);
    const double white = q * (1.0 - q);
    for (int ky = 0; ky < h; ++ky)
      for (int kx = 0; kx < w; ++kx) {
        const size_t i = size_t(ky) * size_t(w) + size_t(kx);
        if (i == 0) continue;
        const double p = std::norm(f[i]) / double(n);
        const double expect = white * cc * null.s[i] / double(n);
        const double fx = signed_freq(kx, w), fy = signed_freq(ky, h);
        const double radius = std::sqrt(fx * fx + fy * fy);
        const size_t b = std::min(size_t(bins - 1), size_t(radius / o.radial_bin));
        if (expect > 1e-12) bin_ratio[b] += p / expect;
        bin_white[b] += p / white;
        ++bin_count[b];
        // Low band, one ordinate of each conjugate pair (self-conjugate ones are real: skipped).
        const size_t conj = size_t((h - ky) % h) * size_t(w) + size_t((w - kx) % w);
        if (radius <= o.lowfreq_cutoff && i < conj && expect > 1e-12) {
          low_sum += p / expect;
          low_white += p / white;
          ++r.lowfreq_terms;
        }
      }
    const std::vector<double> field(mask.begin(), mask.end());
    const MoransI mi = morans_i(field, w, h);
    r.morans_i += mi.i;
    r.morans_i_expected = mi.expected;
    r.morans_i_variance += mi.variance;
    r.morans_i_z += mi.z;
    int cw = 0, ch = 0;
    const std::vector<double> coarse = coarse_field(mask, w, h, cell, cw, ch);
    r.morans_i_coarse += morans_i(coarse, cw, ch).i;
  }
  if (r.masks == 0) return r;
  const double k = double(r.masks);
  r.mean_density /= k;
  r.morans_i /= k;
  r.morans_i_variance /= k;
  r.morans_i_z /= k;
  r.morans_i_coarse /= k;
  if (r.lowfreq_terms > 0) {
    const double m = double(r.lowfreq_terms);
    r.lowfreq_ratio = low_sum / m;
    r.lowfreq_ratio_white = low_white / m;
    r.lowfreq_p_value = gamma_q(m, m * r.lowfreq_ratio);
  }
  for (int b = 0; b < bins; ++b) {
    if (bin_count[size_t(b)] == 0) continue;
    r.radial_freq.push_back((b + 0.5) * o.radial_bin);
    r.radial_ratio.push_back(bin_ratio[size_t(b)] / double(bin_count[size_t(b)]));
    r.radial_white.push_back(bin_white[size_t(b)] / double(bin_count[size_t(b)]));
  }
  return r;
}

}  // namespace frameless
