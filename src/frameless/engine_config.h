// Settings of the frameless engine (plain data, filled field by field by the command line); any thread.
#pragma once
#include <cstddef>
#include <cstdint>
#include <optional>
#include <string>

#include "core/scene/camera.h"
#include "core/shading/render_sample.h"
#include "frameless/partition.h"

namespace frameless {

// frameless: asynchronous per-pixel updates (section 2.2); conventional: synchronous frames with a
// job queue and a barrier, shown only when complete (section 2.1, the baseline).
enum class RenderMode { frameless, conventional };
const char* to_string(RenderMode mode);  // "frameless" / "conventional"
std::optional<RenderMode> parse_render_mode(const std::string& text);

// Optional replacement for the core's trace_sample (tests, stats and overhead benchmarks use a
// cheap synthetic image). One indirect call per sample; production leaves it null and the render
// loop calls trace_sample directly. Must be pure and thread-safe like trace_sample.
struct SampleShader {
  SampleResult (*fn)(const void* context, const CameraBasis& camera, float px, float py,
                     uint64_t rng_seed) = nullptr;
  const void* context = nullptr;  // passed back to fn
};

// Adaptive frameless sampling (after Dayal et al. 2005; docs/adaptive.md). While a pixel's camera
// epoch is current and its running mean has converged, its owner skips it, so the thread's
// samples go to pixels that are still noisy or changed. Frameless mode only; default off.
struct AdaptiveConfig {
  bool enabled = false;          // off: every visit renders (the plain frameless loop)
  uint32_t min_samples = 8;      // never skip a pixel with fewer samples in its current epoch
  float rel_error = 0.02f;       // converged: standard error of the mean luminance below
  float abs_error = 2e-3f;       //   rel_error * mean luminance + abs_error
  uint32_t max_skips = 7;        // at most this many skips in a row: every pixel is rendered at
                                 // least once per max_skips + 1 sweeps of its thread (1..255)
};

// EngineConfig::render_nice unless set, and its largest value (Linux's nice range ends at 19).
inline constexpr int kDefaultRenderNice = 0;
inline constexpr int kMaxRenderNice = 19;

struct EngineConfig {
  int width = 640;                  // image width in pixels (1..16384)
  int height = 480;                 // image height in pixels (1..16384)
  int threads = 0;                  // render threads; 0 = hardware threads (oversubscription works)
  int chunk_size = 64;              // pixels per chunk of the Hilbert line (partition granularity)
  double update_percent = 1.0;      // a thread re-reads the camera after this % of its pixels (0.01..100)
  uint64_t seed = 1;                // mixed with the scene seed into every sample; seeds the shuffles
  RenderMode mode = RenderMode::frameless;          // see RenderMode
  PixelOrder order = PixelOrder::hilbert_shuffled;  // see PixelOrder
  bool jitter = true;               // frameless antialiasing: 2 of 4 stratified positions per update;
                                    // false: one sample at the pixel centre per update
  bool track_variance = false;      // keep per-pixel luminance variance (the m2 field); on only
                                    // where something reads it: the viewer, a variance capture
                                    // layer; adaptive sampling turns it on by itself
  bool deterministic = false;       // virtual clock: nothing renders except inside Engine::advance()
  uint64_t samples_per_tick = 0;    // deterministic: samples per advance() over all threads, dealt in
                                    // proportion to pixel counts; 0 = pixels x samples_per_update / 8
  size_t update_log_capacity = 0;   // per-thread update-log records (0 = off, no cost)
  SampleShader shader;              // null fn: the core's trace_sample
  AdaptiveConfig adaptive;          // adaptive frameless sampling (off by default)
  // Scenes where something moves (dynamic objects, or lights and materials changed while you
  // look): a pixel's running mean remembers at most this many samples (an exponential moving
  // average after that), and a sample more than 3 sigma from the mean restarts it, so moved
  // content is blended in instead of averaged forever (docs/engine.md). 2..65536.
  int motion_history = 8;
  // Trace the camera rays of consecutive owned pixels as coherent packets (core/accel/accel.h): same
  // images bit for bit, faster. Off: ray by ray (for comparison; custom shaders always are).
  bool packets = true;
  // Closed-loop sampling (frameless/closed_loop.h): render threads interleave the runs of pixels
  // the display asks for (reprojection's guesses, fast-changing colours) with their walk.
  bool closed_loop = false;
  // Frameless, wall clock: all render threads together trace at most this many samples a second
  // (each thread sleeps when ahead of its share); 0: as fast as they can. For measuring error
  // against sample rate (bench motion) and for leaving CPU to other work.
  double max_samples_per_s = 0.0;
  // Render threads raise their own nice value by this much (Linux, 0..19), so the display thread
  // and a window get a core as soon as they wake: a display that reprojects keeps up with the
  // camera instead of waiting out render threads' time slices (docs/motion.md). 0: the process's.
  int render_nice = kDefaultRenderNice;
  // Cluster (src/cluster): this process renders only threads [owned_first, owned_first +
  // owned_count) of the `threads`-thread partition; the other threads' pixels are rendered by
  // other processes and arrive through Engine::ingest() (frameless) or ingest_piece()
  // (conventional: a client's threads render the pieces of its PieceFeed instead of the job
  // list). -1: all threads (a single process); 0: none (the cluster master). `threads` must then
  // be explicit.
  int owned_first = 0;
  int owned_count = -1;
};

// Whether this process renders render thread t (EngineConfig::owned_first/owned_count).
inline bool owns_thread(const EngineConfig& c, int t) {
  return c.owned_count < 0 || (t >= c.owned_first && t < c.owned_first + c.owned_count);
}

// Whether render threads keep the Welford M2: asked for, or needed by adaptive sampling or closed loop.
// (Closed loop needs each pixel's noise to tell a moving colour from a noisy one.)
inline bool tracks_variance(const EngineConfig& c) {
  return c.track_variance || c.adaptive.enabled || c.closed_loop;
}

// Samples taken per pixel update: 2 with jitter (frameless antialiasing), 1 without.
inline int samples_per_update(const EngineConfig& c) { return c.jitter ? 2 : 1; }

// Checks ranges; returns an empty string when valid, else "FIELD: problem".
std::string validate(const EngineConfig& config);

}  // namespace frameless
