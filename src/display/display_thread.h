// The display thread: at its own refresh rate it collects the render threads' newest samples,
// blends them into the displayed image and hands consumers the newest completed DisplayImage
// through a triple buffer. Control methods run on one control thread; acquire_latest() on one
// consumer thread; the on-tick callback on the display thread.
#pragma once
#include <cstdint>
#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "display/blend.h"
#include "display/display_image.h"
#include "display/reproject.h"
#include "frameless/engine.h"

namespace frameless {

struct DisplayConfig {
  double refresh_hz = 60.0;  // ticks per second, 1..240 (also the virtual tick in deterministic mode)
  BlendConfig blend;         // alpha, time-based decay, convergence, temporal weights, reprojection
};

// What reprojection did since the display started.
struct ReprojectTotals {
  uint64_t reprojections = 0;  // camera changes the image was moved for
  uint64_t moved = 0;          // pixels moved (summed over reprojections)
  uint64_t filled = 0;         // cracks closed from a neighbour
  uint64_t disoccluded = 0;    // uncovered pixels guessed from the background around them
  uint64_t stale = 0;          // pixels showing what may move
  uint64_t redirected = 0;     // updates of an older camera shown where their point now projects
  double cpu_seconds = 0;      // display-thread CPU spent reprojecting (part of cpu_seconds)
  ReprojectTimes phase_ms;     // wall and CPU milliseconds of each phase, summed over the reprojections
};

// Always-on display instrumentation.
struct DisplayStats {
  uint64_t ticks = 0;             // ticks since start
  double mean_interval = 0;       // mean measured seconds between ticks
  double max_interval = 0;        // longest measured interval
  std::vector<double> intervals;  // the last (up to) 1024 measured intervals, oldest first
  double cpu_seconds = 0;         // display-thread CPU time (CLOCK_THREAD_CPUTIME_ID) in ticks
  uint64_t pixels_updated = 0;    // pixel updates blended since start (sum of FrameInfo::pixels_updated)
  double wall_seconds = 0;        // wall time since start
  double tick_end_seconds = 0;    // wall time (since start) when the last counted tick ended
  uint64_t rejected = 0;          // non-finite values stopped before the image
  uint64_t reclaimed = 0;         // ticks that blended into the newest image, no consumer having taken it
  // Whole-image copies of the records into a stale buffer (across a tick that changed everything,
  // or a consumer far behind); never for a reprojection, which moves pixels, not records.
  uint64_t record_copies = 0;
  ReprojectTotals reproject;
};

class DisplayThread {
 public:
  // `engine` must outlive this object.
  DisplayThread(Engine& engine, const DisplayConfig& config);
  ~DisplayThread();  // stops and joins
  DisplayThread(const DisplayThread&) = delete;
  DisplayThread& operator=(const DisplayThread&) = delete;

  // Wall-clock mode: starts the ticking thread (does nothing for a deterministic engine). Idempotent.
  void start();
  void stop();  // idempotent
  bool running() const;

  // Deterministic driving (caller's thread, thread not started): engine.advance(1 / refresh_hz)
  // then one tick. Same seed, same calls => bit-identical images.
  FrameInfo step();
  // One display tick now on the caller's thread without advancing the engine (not while running).
  FrameInfo tick();

  // Settings take effect at the next tick; any thread.
  void set_config(const DisplayConfig& config);
  DisplayConfig config() const;

  // Newest completed image; never blocks. The reference stays valid and unchanged until the
  // next acquire_latest() call (single consumer). *is_new: whether it changed since last call.
  const DisplayImage& acquire_latest(bool* is_new = nullptr);
  // Called on the display thread after every tick with the image just produced (keep it short).
  // Set before start(), or while stopped.
  void set_on_tick(std::function<void(const DisplayImage&)> callback);
  // Called on the display thread after every tick with that tick's FrameInfo only: no image is
  // built for it, so prefer it when the callback does not read pixels. Same rules as set_on_tick.
  void set_on_tick_info(std::function<void(const FrameInfo&)> callback);

  DisplayStats stats() const;
  // The error that stopped the display thread (an exception in a tick or callback); empty if none.
  std::optional<std::string> error() const;

  struct Impl;

 private:
  std::unique_ptr<Impl> impl_;
};

}  // namespace frameless
