// Display thread: collect -> blend -> publish through a triple buffer whose back buffer is
// brought up to date from short per-tick dirty lists, so a tick costs in proportion to the pixels
// that changed, not to the image size.
#include "display/display_thread.h"

#include <time.h>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <chrono>
#include <condition_variable>
#include <deque>
#include <mutex>
#include <thread>

namespace frameless {
namespace {

double thread_cpu_seconds() {
  timespec ts{};
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts);
  return double(ts.tv_sec) + 1e-9 * double(ts.tv_nsec);
}

constexpr uint32_t kNew = 4;
constexpr uint32_t kEpochRing = 4096;  // epochs tracked for coverage (older ones are never newest)
constexpr uint64_t kHistory = 4;       // ticks of dirty lists kept for the triple buffer
constexpr size_t kIntervalsKept = 1024;

}  // namespace

struct DisplayThread::Impl {
  Impl(Engine& e, const DisplayConfig& c) : engine(e), config(c) {}

  Engine& engine;
  mutable std::mutex config_mutex;
  DisplayConfig config;
  std::function<void(const DisplayImage&)> on_tick;

  // Display-thread state.
  UpdateCursor cursor;
  std::vector<PixelUpdate> updates;
  DisplayImage master;
  uint64_t tick_index = 0;
  uint64_t last_samples = 0;
  uint64_t rejected = 0;
  std::vector<uint32_t> epoch_tag, epoch_count;  // coverage: pixels currently showing each epoch
  std::vector<uint32_t> dirty[kHistory];
  bool dirty_full[kHistory] = {};

  // Triple buffer: the display fills `back`, swaps it with `middle`; the consumer swaps `middle`
  // into `front`. synced[b]: ticks whose changes buffer b holds.
  DisplayImage buf[3];
  uint64_t synced[3] = {0, 0, 0};
  std::atomic<uint32_t> middle{1};
  uint32_t back = 0;
  uint32_t front = 2;

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

  void reset_image(int w, int h) {
    master.reset(w, h);
    epoch_tag.assign(kEpochRing, 0);
    epoch_count.assign(kEpochRing, 0);
  }

  // Moves one pixel's epoch from `from` to `to` in the coverage counts.
  void count_epoch(uint32_t from, uint32_t to) {
    if (from == to) return;
    if (from != 0 && epoch_tag[from % kEpochRing] == from) --epoch_count[from % kEpochRing];
    if (epoch_tag[to % kEpochRing] != to) {
      epoch_tag[to % kEpochRing] = to;
      epoch_count[to % kEpochRing] = 0;
    }
    ++epoch_count[to % kEpochRing];
  }

  FrameInfo run_tick(double interval);
  void publish();
  void thread_main();
};

FrameInfo DisplayThread::Impl::run_tick(double interval) {
  DisplayConfig cfg;
  {
    std::lock_guard<std::mutex> lock(config_mutex);
    cfg = config;
  }
  engine.note_display_tick(uint32_t(tick_index));
  const CollectResult r = engine.collect_updates(cursor, updates);
  std::vector<uint32_t>& dirty_now = dirty[tick_index % kHistory];
  dirty_now.clear();
  bool full = false;
  if (r.reset || master.width != r.width || master.height != r.height) {
    reset_image(r.width, r.height);
    full = true;
  }

  const bool conventional = r.mode == RenderMode::conventional;
  for (const PixelUpdate& u : updates) {
    const size_t i = u.pixel;
    const Vec3 prev(master.rgb[3 * i], master.rgb[3 * i + 1], master.rgb[3 * i + 2]);
    bool bad = false;
    const Vec3 c = blend_pixel(cfg.blend, conventional, prev, master.epoch[i],
                               master.last_update[i], u.state, &bad);
    rejected += bad;
    count_epoch(master.epoch[i], u.state.epoch);
    master.rgb[3 * i] = c.x;
    master.rgb[3 * i + 1] = c.y;
    master.rgb[3 * i + 2] = c.z;
    master.last_update[i] = u.state.time;
    master.sample_count[i] = u.state.count;
    master.variance[i] = std::isfinite(u.state.variance) ? u.state.variance : 0.0f;
    master.epoch[i] = u.state.epoch;
    if (!full) dirty_now.push_back(u.pixel);
  }
  if (dirty_now.size() > master.pixels() / 4) full = true;  // cheaper to copy everything
  dirty_full[tick_index % kHistory] = full;

  FrameInfo& info = master.info;
  info.index = tick_index;
  info.wall_time = wall();
  info.virtual_time = r.time;
  info.interval = interval;
  info.samples = r.samples >= last_samples ? r.samples - last_samples : r.samples;
  last_samples = r.samples;
  info.pixels_updated = updates.size();
  const uint32_t e = r.newest_epoch;
  const uint32_t covered = epoch_tag.empty() || epoch_tag[e % kEpochRing] != e ? 0 : epoch_count[e % kEpochRing];
  info.coverage = master.pixels() ? double(covered) / double(master.pixels()) : 0.0;
  info.newest_epoch = e;
  info.mode = r.mode;
  info.dropped_samples = r.dropped;
  info.rejected = rejected;

  publish();
  if (on_tick) on_tick(master);
  ++tick_index;
  return info;
}

void DisplayThread::Impl::publish() {
  DisplayImage& img = buf[back];
  const uint64_t have = synced[back];
  bool full = img.width != master.width || img.height != master.height || have == 0 ||
              tick_index + 1 - have > kHistory;
  for (uint64_t t = have; !full && t <= tick_index; ++t) full = dirty_full[t % kHistory];
  if (full) {
    img.width = master.width;
    img.height = master.height;
    img.rgb = master.rgb;
    img.last_update = master.last_update;
    img.sample_count = master.sample_count;
    img.variance = master.variance;
    img.epoch = master.epoch;
  } else {
    for (uint64_t t = have; t <= tick_index; ++t)
      for (uint32_t i : dirty[t % kHistory]) copy_pixel(master, img, i);
  }
  img.info = master.info;
  synced[back] = tick_index + 1;
  const uint32_t old = middle.exchange(back | kNew, std::memory_order_acq_rel);
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
  const bool fresh = d.middle.load(std::memory_order_acquire) & kNew;
  if (fresh) {
    const uint32_t old = d.middle.exchange(d.front, std::memory_order_acq_rel);
    d.front = old & 3u;
  }
  if (is_new) *is_new = fresh;
  return d.buf[d.front];
}

void DisplayThread::set_on_tick(std::function<void(const DisplayImage&)> callback) {
  impl_->on_tick = std::move(callback);
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
  }
  return s;
}

std::optional<std::string> DisplayThread::error() const {
  std::lock_guard<std::mutex> lock(impl_->stats_mutex);
  return impl_->error;
}

}  // namespace frameless
