// The display thread's state (DisplayThread::Impl) and the sink that blends one tick's updates
// into its back buffer, shared by display_thread.cpp (the thread and its tick) and
// tick_sink.cpp (the blend of each update). Display thread only, except where marked.
#pragma once
#include <algorithm>
#include <atomic>
#include <cstring>
#include <cmath>
#include <chrono>
#include <condition_variable>
#include <deque>
#include <mutex>
#include <thread>

#include "display/display_pixel.h"
#include "display/display_thread.h"
#include "display/reproject.h"
#include "display/denoise.h"
#include "display/discontinuity_buffer.h"
#include "display/slot_image.h"
#include "frameless/cpu_clock.h"

namespace frameless {

// A public image shown denoised (display/denoise.h): its unfiltered colours wait in `raw` while it
// shows filtered ones, so the next sync patches unfiltered values.
struct FilteredShow {
  std::vector<float> raw;
  bool active = false;
  DenoiseBuffers buffers;
  DiscontinuityBuffers discontinuity;
};

struct DisplayThread::Impl {
  static constexpr uint32_t kNew = 4;  // marks an unconsumed image in `middle`
  static constexpr size_t kIntervalsKept = 1024;

  Impl(Engine& e, const DisplayConfig& c) : engine(e), config(c) {}

  Engine& engine;
  mutable std::mutex config_mutex;
  DisplayConfig config;
  std::function<void(const DisplayImage&)> on_tick;  // gets the public image (built for it)
  std::function<void(const FrameInfo&)> on_tick_info;  // gets the tick's FrameInfo only

  // Display-thread state.
  UpdateCursor cursor;
  DisplayImage tick_image;         // public layers of the newest image for the on-tick callback
  uint64_t tick_image_synced = 0;  // ticks whose changes tick_image holds (0: none)
  uint64_t tick_index = 0;
  uint64_t last_samples = 0;
  uint64_t rejected = 0;
  uint64_t reclaimed = 0;  // DisplayStats::reclaimed
  uint64_t record_copies = 0;  // DisplayStats::record_copies
  std::atomic<uint64_t> consumer_polls{0};  // acquire_latest calls (any thread)
  uint64_t polls_seen = 0;       // consumer_polls at the last tick that saw it change
  uint64_t last_poll_tick = 0;   // that tick
  uint64_t pixels_updated = 0;  // since construction
  LayoutPtr layout;             // the engine's current slot order and the display's places
  // By engine slot: the engine's sequence number of the update each slot shows, so that update is not
  // blended twice. One array for the three buffers (each is brought up to the newest image before
  // a tick blends into it); apart from the pixels, so reprojection leaves it where it is.
  std::vector<uint32_t> shown_seq;
  EpochCensus census;     // coverage: pixels currently showing each epoch
  ChangeHistory history;  // what the last ticks changed
  // Reprojection: the camera the image was last moved to (epoch 0: none yet) and scratch.
  // image_moved: the image was moved since reprojection (re)started; until then it shows its
  // updates where they were rendered, so older cameras' updates are not redirected.
  uint32_t reproject_epoch = 0;
  bool image_moved = false;
  CameraBasis reproject_basis;
  Reprojector reprojector;
  PixelImage reprojected;
  // A whole copy catch_up left for later: the back buffer is a stale copy of `deferred` (the
  // newest image), which a reprojection this tick reads directly instead; else it is copied.
  // deferred_records: its records too (else catch_up brought them up to date from the runs).
  const PixelImage* deferred = nullptr;
  bool deferred_records = false;
  // Reprojection's marks by pixel and, for marked pixels (content moved there), their points
  // (relative to reproject_basis); an unmarked pixel's point is the engine's. The display
  // thread's alone, so outside the triple buffer; with the reprojection's output for them.
  std::vector<ViewPoint> points, points_out;
  std::vector<uint8_t> marks, marks_out;
  ReprojectTotals reproject_totals;
  ReprojectBudget reproject_budget;

  // Triple buffer: the display brings `back` up to date, blends the tick into it in place and
  // swaps it with `middle`; the consumer swaps `middle` into `front` and exports it into `latest`.
  // While no consumer asks, the display swaps the untaken newest image back out of `middle` and
  // blends into it again (catch_up). synced[b]: ticks whose changes buffer b holds; newest: the
  // buffer published last (3: none), never `front`.
  PixelImage buf[3];
  uint32_t newest = 3;
  uint64_t synced[3] = {0, 0, 0};
  std::atomic<uint32_t> middle{1};
  // Set while the display holds the newest published image it took back (until that tick's
  // publish): a consumer finding nothing new then waits for the publish instead of an older image.
  std::atomic<bool> holding_newest{false};
  // Clears holding_newest and wakes a consumer waiting on it (no system call while none waits).
  void release_hold() {
    holding_newest.store(false, std::memory_order_release);
    holding_newest.notify_all();
  }
  uint32_t back = 0;
  uint32_t front = 2;
  DisplayImage latest;        // consumer: public layers of buf[front]
  uint64_t latest_synced = 0;  // consumer: ticks whose changes `latest` holds (0: none)
  FilteredShow latest_filter, tick_filter;  // denoised showing of `latest` and `tick_image`

  // Wall-clock thread.
  std::thread thread;
  bool running = false;
  std::mutex wake_mutex;
  std::condition_variable wake;
  bool stop_requested = false;
  std::chrono::steady_clock::time_point t_start = std::chrono::steady_clock::now();

  mutable std::mutex stats_mutex;
  DisplayStats stats;
  std::deque<double> intervals;
  double interval_sum = 0;
  std::optional<std::string> error;

  double wall() const {
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - t_start).count();
  }

  bool reproject(PixelImage& img, bool enabled, float budget, bool world_moves,
                 const PixelPoint* engine_points);
  // Forgets what reprojection knew of the image (its points, marks and camera).
  void reset_reprojection() {
    points.clear();
    marks.clear();
    reproject_epoch = 0;
    image_moved = false;
  }

  FrameInfo run_tick(double interval);
  bool catch_up(const CollectResult& r);
  void finish_catch_up(PixelImage& img);
  void publish();
  void thread_main();
};

// Blends one tick's collected updates into the back buffer, slot run by slot run (display thread).
struct TickSink final : UpdateSink {
  TickSink(DisplayThread::Impl& display, const DisplayConfig& config)
      : d(display), rule(config.blend), reproject(config.blend.reproject) {}

  DisplayThread::Impl& d;
  const BlendRule rule;
  bool reproject = false;     // asked for; on in frameless mode only
  PixelImage* image = nullptr;
  const std::atomic<uint8_t>* levels = nullptr;  // the engine's, by pixel (CollectResult::levels)
  const PixelPoint* points = nullptr;            // the engine's, by pixel (reprojection only)
  WantedRuns* wanted = nullptr;                  // closed-loop sampling: where to ask (else null)
  bool asked = false;                            // asked for something since the last publish
  std::vector<SlotRun>* dirty = nullptr;
  bool full = false;          // this tick changed (or cleared) the whole image
  bool moved = false;         // a reprojection moved what every place shows (the records stay)
  bool conventional = false;
  size_t dirty_slots = 0;     // slots in *dirty
  uint64_t changed = 0;       // pixels blended
  uint64_t rejected = 0;      // blends that came out non-finite (kept the previous value)

  void begin(const CollectResult& r) override;
  void slots(size_t first, const PixelState* states, size_t count) override;
  void frame(const std::vector<PixelSnapshot>& pixels) override;
  void show(DisplayPixel& m, PlaceRecord& rec, const PixelSnapshot& u, bool guess);
  void redirect(const PixelSnapshot& u, const ScenePoint& point);
  // Places [first, first + count) changed.
  void mark_dirty(size_t first, size_t count) {
    if (full) return;
    if (!dirty->empty() && dirty->back().first + dirty->back().count == first)
      dirty->back().count += uint32_t(count);
    else
      dirty->push_back({uint32_t(first), uint32_t(count)});
    dirty_slots += count;
    if (dirty_slots > image->pixels() / 4) full = true;  // cheaper to copy everything
  }
  // Engine slots [first, first + count) changed: the runs of places they are kept in.
  void mark_dirty_engine(size_t first, size_t count) {
    if (full) return;
    if (!image->layout) return mark_dirty(first, count);
    const uint32_t* place = image->layout->place_of_engine_slot.data() + first;
    size_t i = 0;
    while (i < count) {
      size_t j = i + 1;
      while (j < count && place[j] == place[j - 1] + 1) ++j;
      mark_dirty(place[i], j - i);
      i = j;
    }
  }
};

}  // namespace frameless
