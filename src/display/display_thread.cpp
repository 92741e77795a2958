// Display thread: collect -> blend -> publish through a triple buffer whose back buffer is
// brought up to date from short per-tick lists of changed runs, so a tick costs in proportion to
// the pixels that changed, not to the image size. The display thread keeps two 16-byte structs per
// pixel (what it shows; its newest update's record) along the Hilbert curve, where each of the
// engine's 64-pixel chunks is a run (so the reads, blends and copies of a tick stream through
// memory) and neighbours stay near (so reprojection's moves do); the public DisplayImage layers
// (pixel order) are built only for whoever asks: the consumer in acquire_latest(), and the
// on-tick callback when one is set. The image itself is display/slot_image.h.
#include "display/display_thread.h"

#include <algorithm>
#include <atomic>
#include <cstring>
#include <cmath>
#include <chrono>
#include <condition_variable>
#include <deque>
#include <mutex>
#include <thread>

#include "display/display_thread_impl.h"

namespace frameless {
namespace {

// Brings `out` up to `img` and, when img carries denoising guides, shows it filtered; the raw
// colours wait in f.raw so that the next sync patches raw values.
void show(const PixelImage& img, DisplayImage& out, uint64_t& synced, FilteredShow& f) {
  if (f.active) {
    out.rgb.swap(f.raw);
    f.active = false;
  }
  sync_public(img, out, synced);
  const bool discontinuity = img.discontinuity > 1 && img.indirect.size() == out.pixels();
  const bool denoise = img.denoise_iterations > 0;
  if ((discontinuity || denoise) && img.guides.size() == out.pixels()) {
    f.raw = out.rgb;
    if (discontinuity) filter_discontinuity(out, img.guides, img.indirect, img.discontinuity, f.discontinuity);
    if (denoise) denoise_image(out, img.guides, img.denoise_iterations, f.buffers);
    f.active = true;
  }
}

}  // namespace

FrameInfo DisplayThread::Impl::run_tick(double interval) {
  DisplayConfig cfg;
  {
    std::lock_guard<std::mutex> lock(config_mutex);
    cfg = config;
  }
  engine.note_display_tick(uint32_t(tick_index));
  struct ReleaseHold {  // a tick that throws after taking the newest image back must not hang a consumer
    Impl& d;
    ~ReleaseHold() { d.release_hold(); }
  } hold_guard{*this};
  TickSink sink(*this, cfg);
  const CollectResult r = engine.collect(cursor, sink);
  const bool full = sink.full;
  history.full[tick_index % kHistory] = full;
  history.moved[tick_index % kHistory] = sink.moved && !full;
  history.newest = tick_index + 1;
  rejected += sink.rejected;

  PixelImage& image = buf[back];
  FrameInfo& info = image.info;
  info.index = tick_index;
  info.wall_time = wall();
  info.virtual_time = r.time;
  info.interval = interval;
  info.samples = r.samples >= last_samples ? r.samples - last_samples : r.samples;
  last_samples = r.samples;
  info.pixels_updated = sink.changed;
  pixels_updated += sink.changed;
  const uint32_t e = r.newest_epoch;
  const uint32_t covered = census.of(e);
  info.coverage = image.pixels() ? double(covered) / double(image.pixels()) : 0.0;
  info.newest_epoch = e;
  info.mode = r.mode;
  info.dropped_samples = r.dropped;
  info.rejected = rejected;

  // The denoiser's guides: each pixel's newest normal, position and albedo (read here, while
  // the engine's points are certainly valid).
  const bool discontinuity = cfg.blend.discontinuity && r.indirect && r.interleave > 1;
  if ((cfg.blend.denoise || discontinuity) && r.points && image.pixels() > 0) {
    image.guides.resize(image.pixels());
    for (size_t i = 0; i < image.pixels(); ++i)
      if (!read_guide(r.points[i], image.guides[i])) image.guides[i] = PointGuide{};
  } else {
    image.guides.clear();
  }
  image.denoise_iterations = cfg.blend.denoise && !image.guides.empty() ? std::clamp(cfg.blend.denoise_iterations, 1, 8) : 0;
  // igi's indirect light, for the discontinuity buffer (relaxed reads: frameless/pixel_points.h).
  image.discontinuity = discontinuity && !image.guides.empty() ? r.interleave : 0;
  image.indirect.resize(image.discontinuity > 0 ? image.pixels() : 0);
  for (size_t i = 0; i < image.indirect.size(); ++i)
    for (int c = 0; c < 3; ++c) image.indirect[i][c] = r.indirect[i].mean[c].load(std::memory_order_relaxed);
  publish();
  if (on_tick) {
    show(image, tick_image, tick_image_synced, tick_filter);
    on_tick(tick_image);
  }
  if (on_tick_info) on_tick_info(info);
  ++tick_index;
  return info;
}

// Brings buf[back] up to the newest published image (the changes of ticks synced[back] ..
// tick_index - 1), so this tick blends into it in place: one copy per changed run and buffer.
// Clears it instead on a reset or a size change, and moves every pixel to its new slot on a
// layout change. Returns whether this tick therefore changed the whole image.
bool DisplayThread::Impl::catch_up(const CollectResult& r) {
  deferred = nullptr;  // set again below only when this tick leaves a full copy for later
  const size_t n = size_t(r.width) * size_t(r.height);
  if ((layout ? layout->engine_order : nullptr) != r.slot_pixel) {
    LayoutPtr next = make_layout(r.slot_pixel, r.width, r.height);
    // Each pixel keeps the seq it shows, in its new engine slot.
    if (shown_seq.size() == n) shown_seq = to_new_slots(shown_seq, layout.get(), next.get(), true);
    layout = std::move(next);
  }
  // No consumer has asked for an image for kHistory ticks (a headless run that reads only
  // FrameInfo): the display takes the untaken newest image back to blend into, instead of
  // copying it into another buffer (after a reprojection, the whole image). A consumer that asks
  // at all keeps every image in `middle` until it takes it or a newer one replaces it (taking it
  // back whenever untaken would starve a consumer that polls right after a busy tick's publish).
  if (const uint64_t polls = consumer_polls.load(std::memory_order_relaxed); polls != polls_seen) {
    polls_seen = polls;
    last_poll_tick = tick_index;
  }
  uint32_t untaken = newest | kNew;
  if (tick_index >= last_poll_tick + kHistory && newest < 3 && newest != back) {
    holding_newest.store(true, std::memory_order_relaxed);  // before the CAS: its release publishes it
    if (middle.compare_exchange_strong(untaken, back, std::memory_order_acq_rel, std::memory_order_relaxed)) {
      back = newest;
      ++reclaimed;
    } else {
      release_hold();  // the consumer took it meanwhile
    }
  }
  PixelImage& img = buf[back];
  if (r.reset || newest > 2 || buf[newest].width != r.width || buf[newest].height != r.height) {
    shown_seq.assign(n, 0);
    img.reset(r.width, r.height, layout);
    reset_reprojection();  // a cleared or resized image has no points (same pixel count or not)
    census.clear();
    return true;
  }
  const PixelImage& src = buf[newest];
  if (src.layout != layout) {
    remap(src, img, layout);
    return true;
  }
  const uint64_t have = synced[back];
  if (img.width != r.width || img.height != r.height || img.layout != src.layout ||
      !history.covers_records(have, tick_index)) {
    img.width = src.width;
    img.height = src.height;
    img.layout = src.layout;
    img.px.resize(src.px.size());
    img.rec.resize(src.rec.size());
    deferred = &src;  // copied by finish_catch_up unless a reprojection reads src instead
    deferred_records = true;
    return false;
  }
  // After a reprojection the pixels come whole (or this tick's reprojection reads src); records stay: runs.
  const bool reprojected_since = !history.covers(have, tick_index);
  if (reprojected_since) deferred = &src, deferred_records = false;
  for (uint64_t t = have; t < tick_index; ++t)
    for (const SlotRun& run : history.runs[t % kHistory]) {
      if (!reprojected_since) img.copy_pixels(src, run.first, run.count);
      img.copy_records(src, run.first, run.count);
    }
  return false;
}

// The whole copy catch_up deferred, when no reprojection made it unneeded.
void DisplayThread::Impl::finish_catch_up(PixelImage& img) {
  if (deferred) {
    img.copy_pixels(*deferred, 0, img.pixels());
    if (deferred_records) img.copy_records(*deferred, 0, img.pixels()), ++record_copies;
  }
  deferred = nullptr;
}

// Moves the back buffer to the newest camera, once per camera change; true when it did. A full
// copy catch_up deferred is not made: the reprojection reads the newest image itself.
bool DisplayThread::Impl::reproject(PixelImage& img, bool enabled, float budget, bool world_moves,
                                    const PixelPoint* engine_points) {
  if (!enabled) {
    reset_reprojection();
    return false;
  }
  if (points.size() != img.pixels()) {  // just turned on, or cleared: nothing shown has a point yet
    reset_reprojection();
    points.assign(img.pixels(), ViewPoint{});
    marks.assign(img.pixels(), kMarkNone);
  }
  uint32_t epoch = 0;
  const Camera camera = engine.camera(&epoch);
  if (epoch == reproject_epoch) return false;  // a still camera is never reprojected
  // Over budget: this change merges into a later one (deterministic runs ignore the clock).
  if (!(budget > 0.0f) || engine.config().deterministic) budget = 0.0f;  // unlimited: no credit kept
  if (budget > 0.0f && reproject_epoch != 0 &&
      !reproject_budget.allow(
          std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count(), budget))
    return false;
  const bool first = reproject_epoch == 0;
  reproject_epoch = epoch;
  const CameraBasis before = reproject_basis;  // the camera the marked pixels' points are relative to
  reproject_basis = make_camera_basis(camera, img.width, img.height);
  if (first) return false;
  const double c0 = thread_cpu_seconds();
  PixelImage& out = reprojected;
  out.width = img.width;
  out.height = img.height;
  out.layout = img.layout;
  const size_t n = img.pixels();
  out.px.resize(n);
  points_out.resize(n);
  marks_out.resize(n);
  // What each pixel shows: moved content keeps its moved point (marked), a rendered pixel the
  // engine's point of its newest update (read by the reprojection).
  const PixelImage& from = deferred ? *deferred : img;
  census.clear();  // the gather counts the epochs it moves
  const ReprojectStats st = reprojector.run(before, reproject_basis, from.slots(points, marks, engine_points),
                                            out.slots(points_out, marks_out), world_moves, 3, &census);
  // The records stay in place: a stale back buffer gets the newest image's (unless catch_up
  // brought them up to date from the runs).
  if (deferred && deferred_records) img.copy_records(*deferred, 0, img.pixels()), ++record_copies;
  deferred = nullptr;
  image_moved = true;
  std::swap(img.px, out.px);
  std::swap(points, points_out);
  std::swap(marks, marks_out);
  ReprojectTotals& t = reproject_totals;
  ++t.reprojections;
  t.moved += st.moved;
  t.filled += st.filled;
  t.disoccluded += st.disoccluded;
  t.stale += st.stale;
  t.phase_ms += reprojector.last_times();
  const double cost = thread_cpu_seconds() - c0;
  reproject_budget.spend(cost, budget);
  t.cpu_seconds += cost;
  return true;
}

void DisplayThread::Impl::publish() {
  buf[back].history = history;  // a few runs per tick: no allocation once the vectors have grown
  synced[back] = tick_index + 1;
  newest = back;
  const uint32_t old = middle.exchange(back | kNew, std::memory_order_acq_rel);
  release_hold();
  back = old & 3u;
}

void DisplayThread::Impl::thread_main() {
  using clock = std::chrono::steady_clock;
  double cpu = 0.0;
  auto next = clock::now();
  auto prev = next;
  bool first = true;
  try {
    for (;;) {
      double hz;
      {
        std::lock_guard<std::mutex> lock(config_mutex);
        hz = std::clamp(config.refresh_hz, 1.0, 240.0);
      }
      const auto period = std::chrono::duration_cast<clock::duration>(std::chrono::duration<double>(1.0 / hz));
      next += period;
      const auto now0 = clock::now();
      if (next < now0 - period) next = now0;  // fell behind: do not try to catch up with a burst
      {
        std::unique_lock<std::mutex> lock(wake_mutex);
        if (wake.wait_until(lock, next, [&] { return stop_requested; })) break;
      }
      const auto now = clock::now();
      const double interval = first ? 1.0 / hz : std::chrono::duration<double>(now - prev).count();
      prev = now;
      const double c0 = thread_cpu_seconds();
      run_tick(interval);
      cpu += thread_cpu_seconds() - c0;
      std::lock_guard<std::mutex> lock(stats_mutex);
      stats.ticks = tick_index;
      stats.cpu_seconds = cpu;
      stats.tick_end_seconds = wall();
      stats.pixels_updated = pixels_updated;
      if (!first) {
        intervals.push_back(interval);
        interval_sum += interval;
        stats.max_interval = std::max(stats.max_interval, interval);
        if (intervals.size() > kIntervalsKept) {
          interval_sum -= intervals.front();
          intervals.pop_front();
        }
        stats.mean_interval = interval_sum / double(intervals.size());
      }
      stats.rejected = rejected;
      stats.reclaimed = reclaimed;
      stats.record_copies = record_copies;
      stats.reproject = reproject_totals;
      first = false;
    }
  } catch (const std::exception& ex) {
    std::lock_guard<std::mutex> lock(stats_mutex);
    error = std::string("display thread: ") + ex.what();
  }
}

DisplayThread::DisplayThread(Engine& engine, const DisplayConfig& config)
    : impl_(std::make_unique<Impl>(engine, config)) {}

DisplayThread::~DisplayThread() { stop(); }

void DisplayThread::start() {
  Impl& d = *impl_;
  if (d.running || d.engine.config().deterministic) return;
  d.stop_requested = false;
  d.running = true;
  d.thread = std::thread([&d] { d.thread_main(); });
}

void DisplayThread::stop() {
  Impl& d = *impl_;
  if (!d.running) return;
  {
    std::lock_guard<std::mutex> lock(d.wake_mutex);
    d.stop_requested = true;
  }
  d.wake.notify_all();
  d.thread.join();
  d.running = false;
}

bool DisplayThread::running() const { return impl_->running; }

FrameInfo DisplayThread::step() {
  const double dt = 1.0 / std::clamp(config().refresh_hz, 1.0, 240.0);
  impl_->engine.advance(dt);
  return impl_->run_tick(dt);
}

FrameInfo DisplayThread::tick() { return impl_->run_tick(1.0 / std::clamp(config().refresh_hz, 1.0, 240.0)); }

void DisplayThread::set_config(const DisplayConfig& config) {
  std::lock_guard<std::mutex> lock(impl_->config_mutex);
  impl_->config = config;
}

DisplayConfig DisplayThread::config() const {
  std::lock_guard<std::mutex> lock(impl_->config_mutex);
  return impl_->config;
}

const DisplayImage& DisplayThread::acquire_latest(bool* is_new) {
  Impl& d = *impl_;
  // Only an image still flagged new is taken: the display may take the one in `middle` back
  // (catch_up, while no consumer has asked lately) between this load and the exchange.
  d.consumer_polls.fetch_add(1, std::memory_order_relaxed);
  uint32_t in_middle = d.middle.load(std::memory_order_acquire);
  // Nothing new because the display holds the newest image (taken back mid-tick): sleep until this
  // tick's publish, which always comes (run_tick releases the hold on any exit).
  while (!(in_middle & Impl::kNew) && d.holding_newest.load(std::memory_order_acquire)) {
    d.holding_newest.wait(true, std::memory_order_acquire);
    in_middle = d.middle.load(std::memory_order_acquire);
  }
  while ((in_middle & Impl::kNew) &&
         !d.middle.compare_exchange_weak(in_middle, d.front, std::memory_order_acq_rel, std::memory_order_acquire)) {
  }
  const bool fresh = in_middle & Impl::kNew;
  if (fresh) {
    d.front = in_middle & 3u;
    // The public layers are built here, on the consumer's thread, and only for images it takes:
    // from the image's change history when it covers the ticks since the last one taken.
    show(d.buf[d.front], d.latest, d.latest_synced, d.latest_filter);
  }
  if (is_new) *is_new = fresh;
  return d.latest;
}

void DisplayThread::set_on_tick(std::function<void(const DisplayImage&)> callback) {
  impl_->on_tick = std::move(callback);
}

void DisplayThread::set_on_tick_info(std::function<void(const FrameInfo&)> callback) {
  impl_->on_tick_info = std::move(callback);
}

DisplayStats DisplayThread::stats() const {
  const Impl& d = *impl_;
  std::lock_guard<std::mutex> lock(d.stats_mutex);
  DisplayStats s = d.stats;
  s.intervals.assign(d.intervals.begin(), d.intervals.end());
  s.wall_seconds = d.wall();
  if (!d.running) {
    s.ticks = d.tick_index;
    s.rejected = d.rejected;
    s.reclaimed = d.reclaimed;
    s.record_copies = d.record_copies;
    s.reproject = d.reproject_totals;
    s.pixels_updated = d.pixels_updated;
  }
  return s;
}

std::optional<std::string> DisplayThread::error() const {
  std::lock_guard<std::mutex> lock(impl_->stats_mutex);
  return impl_->error;
}

}  // namespace frameless
