// Spatial structure of update masks (issue 5): power spectrum against the randomised-chunk null
// and Moran's I; pure functions, any thread.
#pragma once
#include <cstdint>
#include <vector>

#include "frameless/stats_math.h"

namespace frameless {

// The units an order deals out: chunks[j] lists the pixels (y * width + x) of chunk j. They tile
// the image (every pixel in exactly one chunk).
struct ChunkLayout {
  int width = 0;
  int height = 0;
  int chunk_size = 0;
  std::vector<std::vector<uint32_t>> chunks;
};

// Null spectrum: the expected periodogram of a mask made by choosing chunks uniformly at random
// without replacement is q (1 - q) C / (C - 1) * S(f) / N, where S(f) = sum_j |B_j(f)|^2 is the
// summed power of the chunk indicators (computed once, as the DFT of the same-chunk pair
// displacement histogram). For single-pixel chunks this is white noise, q (1 - q).
struct ChunkNull {
  int width = 0;
  int height = 0;
  size_t chunks = 0;
  std::vector<double> s;  // S(f), row-major over (kx, ky)
};
ChunkNull make_chunk_null(const ChunkLayout& layout);

struct StructureOptions {
  double lowfreq_cutoff = 1.0 / 16.0;  // low band: 0 < |f| <= cutoff (cycles per pixel)
  double radial_bin = 1.0 / 64.0;      // width of the radial-average bins (cycles per pixel)
  int coarse_cell = 0;                 // cell side for the coarse Moran's I; 0 = 2 ceil(sqrt(chunk))
};

struct StructureStats {
  int masks = 0;                 // display-interval masks analysed
  double mean_density = 0;       // mean fraction of pixels updated per mask
  // Mean over the low band and the masks of periodogram / null expectation: ~1 for randomly
  // placed chunks, >> 1 for large-scale patterns (bands, wipes, regions).
  double lowfreq_ratio = 0;
  // Same against pixel white noise q (1 - q): what the eye compares with (chunk clumping included).
  double lowfreq_ratio_white = 0;
  uint64_t lowfreq_terms = 0;    // independent periodogram ordinates summed (half-plane x masks)
  // P(ratio >= observed) when each ordinate / expectation ~ Exp(1) independently: Gamma(m, 1/m).
  double lowfreq_p_value = 1;
  double morans_i = 0;           // mean over masks, pixel level, rook weights
  double morans_i_expected = 0;  // under randomisation
  double morans_i_variance = 0;  // under randomisation (mean over masks)
  double morans_i_z = 0;         // mean z over masks
  double morans_i_coarse = 0;    // mean over masks of Moran's I of the cell-density field
  int coarse_cell = 0;           // cell side used
  std::vector<double> radial_freq;   // bin centres (cycles per pixel)
  std::vector<double> radial_ratio;  // mean periodogram / chunk null per bin
  std::vector<double> radial_white;  // mean periodogram / white noise per bin
};

// masks[k][pixel] = 1 if the pixel was updated in interval k. Every mask must be width x height.
StructureStats analyze_structure(const std::vector<std::vector<uint8_t>>& masks,
                                 const ChunkNull& null, const StructureOptions& options = {});

}  // namespace frameless
