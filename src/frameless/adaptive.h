// Adaptive frameless sampling (after Dayal et al. 2005): the render thread's per-visit decision
// to skip a converged pixel, with a bound on consecutive skips; render threads (owner only).
#pragma once
#include <cstdint>
#include <string>
#include <vector>

#include "frameless/engine_config.h"
#include "frameless/pixel_state.h"

namespace frameless {

// Luminance weights of the per-pixel variance (Rec. 709, as in the render loop's Welford step).
inline double luminance(double r, double g, double b) { return 0.2126 * r + 0.7152 * g + 0.0722 * b; }

// True when a pixel with `count` samples, running-mean luminance `mean_lum` and Welford sum
// `m2` has converged: its standard error sqrt(m2 / ((n - 1) n)) is at most
// rel_error * |mean_lum| + abs_error. Fewer than max(2, min_samples) samples never converge.
inline bool converged(const AdaptiveConfig& a, uint32_t count, double mean_lum, double m2) {
  if (count < a.min_samples || count < 2) return false;
  const double n = double(count);
  const double tol = double(a.rel_error) * (mean_lum < 0 ? -mean_lum : mean_lum) + double(a.abs_error);
  // m2 / ((n - 1) n) <= tol^2, without a division or a square root; a NaN m2 never converges.
  return m2 <= tol * tol * (n - 1.0) * n;
}

// Decides whether the owner skips this visit of pixel `p`. `run` is the pixel's count of
// consecutive skips (owner-private); it is reset whenever the pixel is rendered. A pixel whose
// newest sample belongs to another camera epoch than `epoch` is never skipped, so after a camera
// change every pixel is rendered once before any skipping (the staleness bound is unchanged).
inline bool adaptive_skip(const AdaptiveConfig& a, const PixelState& p, uint32_t epoch, uint8_t& run) {
  if (run >= a.max_skips || p.epoch.load(std::memory_order_relaxed) != epoch) {
    run = 0;
    return false;
  }
  const double mean_lum = luminance(p.mean[0].load(std::memory_order_relaxed),
                                    p.mean[1].load(std::memory_order_relaxed),
                                    p.mean[2].load(std::memory_order_relaxed));
  if (!converged(a, p.count.load(std::memory_order_relaxed), mean_lum,
                 p.m2.load(std::memory_order_relaxed))) {
    run = 0;
    return false;
  }
  ++run;
  return true;
}

// Owner-private adaptive state of one render thread: consecutive skips per list position.
struct AdaptiveWorkerState {
  std::vector<uint8_t> skip_run;  // sized to the thread's pixel list on first use
};

// Range checks of the adaptive settings; empty when valid, else "adaptive.FIELD: problem".
std::string validate(const AdaptiveConfig& a);

}  // namespace frameless
