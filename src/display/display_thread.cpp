// Display thread: collect -> blend -> publish through a triple buffer whose back buffer is
// brought up to date from short per-tick dirty lists, so a tick costs in proportion to the pixels
// that changed, not to the image size. The display thread keeps one 32-byte struct per pixel (a
// blend or copy touches half a cache line instead of five scattered ones); the public
// DisplayImage layers are built only for whoever asks: the consumer in acquire_latest(), and
// the on-tick callback when one is set.
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
// Pixels ahead whose display pixel is prefetched: updates arrive in scattered chunks of a large
// image, so without it each blend and each copy waits for a cache miss.
constexpr size_t kPrefetch = 16;

// One displayed pixel and its layers, kept together (see DisplayImage for their meaning).
struct DisplayPixel {
  float rgb[3] = {0.0f, 0.0f, 0.0f};
  float last_update = -1.0f;
  uint32_t count = 0;
  float variance = 0.0f;
  uint32_t epoch = 0;
  uint32_t unused = 0;  // pads to 32 bytes: two pixels per cache line
};
static_assert(sizeof(DisplayPixel) == 32);

// The display thread's image: the DisplayImage layers interleaved per pixel.
struct PixelImage {
  int width = 0;
  int height = 0;
  std::vector<DisplayPixel> px;
  FrameInfo info;

  size_t pixels() const { return size_t(width) * size_t(height); }
  void reset(int w, int h) {
    width = w;
    height = h;
    px.assign(pixels(), DisplayPixel{});
  }
};

// Writes the layers of pixel i of `src` into `dst` (same size).
inline void export_pixel(const PixelImage& src, DisplayImage& dst, size_t i) {
  const DisplayPixel& p = src.px[i];
  dst.rgb[3 * i] = p.rgb[0];
  dst.rgb[3 * i + 1] = p.rgb[1];
  dst.rgb[3 * i + 2] = p.rgb[2];
  dst.last_update[i] = p.last_update;
  dst.sample_count[i] = p.count;
  dst.variance[i] = p.variance;
  dst.epoch[i] = p.epoch;
}

// Converts the whole image into the public layer layout.
void export_image(const PixelImage& src, DisplayImage& dst) {
  if (dst.width != src.width || dst.height != src.height || dst.epoch.size() != src.pixels())
    dst.reset(src.width, src.height);
  const size_t n = src.pixels();
  for (size_t i = 0; i < n; ++i) export_pixel(src, dst, i);
  dst.info = src.info;
}

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
  DisplayImage tick_image;         // public layers of the newest image for the on-tick callback
  uint64_t tick_image_synced = 0;  // ticks whose changes tick_image holds (0: none)
  uint64_t tick_index = 0;
  uint64_t last_samples = 0;
  uint64_t rejected = 0;
  std::vector<uint32_t> epoch_tag, epoch_count;  // coverage: pixels currently showing each epoch
  std::vector<uint32_t> dirty[kHistory];
  bool dirty_full[kHistory] = {};

  // Triple buffer: the display brings `back` up to date, blends the tick into it in place and
  // swaps it with `middle`; the consumer swaps `middle` into `front` and exports it into `latest`.
  // synced[b]: ticks whose changes buffer b holds; newest: the buffer published last (3: none),
  // which only ever gets read while it is not `back`.
  PixelImage buf[3];
  uint32_t newest = 3;
  uint64_t synced[3] = {0, 0, 0};
  std::atomic<uint32_t> middle{1};
  uint32_t back = 0;
  uint32_t front = 2;
  DisplayImage latest;  // consumer: public layers of buf[front]

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
  bool catch_up(int width, int height, bool reset);
  void publish();
  void update_tick_image(const PixelImage& img, bool full);
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
  bool full = catch_up(r.width, r.height, r.reset);
  PixelImage& image = buf[back];
  std::vector<uint32_t>& dirty_now = dirty[tick_index % kHistory];
  dirty_now.clear();

  const bool conventional = r.mode == RenderMode::conventional;
  for (size_t k = 0; k < updates.size(); ++k) {
    const PixelUpdate& u = updates[k];
    if (k + kPrefetch < updates.size())
      __builtin_prefetch(&image.px[updates[k + kPrefetch].pixel], 1);
    DisplayPixel& m = image.px[u.pixel];
    const Vec3 prev(m.rgb[0], m.rgb[1], m.rgb[2]);
    bool bad = false;
    const Vec3 c =
        blend_pixel(cfg.blend, conventional, prev, m.epoch, m.last_update, u.state, &bad);
    rejected += bad;
    count_epoch(m.epoch, u.state.epoch);
    m.rgb[0] = c.x;
    m.rgb[1] = c.y;
    m.rgb[2] = c.z;
    m.last_update = u.state.time;
    m.count = u.state.count;
    m.variance = std::isfinite(u.state.variance) ? u.state.variance : 0.0f;
    m.epoch = u.state.epoch;
    if (!full) dirty_now.push_back(u.pixel);
  }
  if (dirty_now.size() > image.pixels() / 4) full = true;  // cheaper to copy everything
  dirty_full[tick_index % kHistory] = full;

  FrameInfo& info = image.info;
  info.index = tick_index;
  info.wall_time = wall();
  info.virtual_time = r.time;
  info.interval = interval;
  info.samples = r.samples >= last_samples ? r.samples - last_samples : r.samples;
  last_samples = r.samples;
  info.pixels_updated = updates.size();
  const uint32_t e = r.newest_epoch;
  const uint32_t covered = epoch_tag.empty() || epoch_tag[e % kEpochRing] != e ? 0 : epoch_count[e % kEpochRing];
  info.coverage = image.pixels() ? double(covered) / double(image.pixels()) : 0.0;
  info.newest_epoch = e;
  info.mode = r.mode;
  info.dropped_samples = r.dropped;
  info.rejected = rejected;

  publish();
  if (on_tick) {
    update_tick_image(image, full);
    on_tick(tick_image);
  }
  ++tick_index;
  return info;
}

// Brings buf[back] up to the newest published image (the changes of ticks synced[back] ..
// tick_index - 1), so this tick blends into it in place: one copy per changed pixel and buffer.
// Clears it instead on a reset or a size change. Returns whether it was cleared.
bool DisplayThread::Impl::catch_up(int width, int height, bool reset) {
  PixelImage& img = buf[back];
  if (reset || newest > 2 || buf[newest].width != width || buf[newest].height != height) {
    img.reset(width, height);
    epoch_tag.assign(kEpochRing, 0);
    epoch_count.assign(kEpochRing, 0);
    return true;
  }
  const PixelImage& src = buf[newest];
  const uint64_t have = synced[back];
  bool full = img.width != width || img.height != height || have == 0 ||
              have + kHistory <= tick_index;
  for (uint64_t t = have; !full && t < tick_index; ++t) full = dirty_full[t % kHistory];
  if (full) {
    img.width = width;
    img.height = height;
    img.px = src.px;
    return false;
  }
  for (uint64_t t = have; t < tick_index; ++t) {
    const std::vector<uint32_t>& list = dirty[t % kHistory];
    for (size_t k = 0; k < list.size(); ++k) {
      if (k + kPrefetch < list.size()) {
        __builtin_prefetch(&img.px[list[k + kPrefetch]], 1);
        __builtin_prefetch(&src.px[list[k + kPrefetch]], 0);
      }
      img.px[list[k]] = src.px[list[k]];
    }
  }
  return false;
}

void DisplayThread::Impl::publish() {
  synced[back] = tick_index + 1;
  newest = back;
  const uint32_t old = middle.exchange(back | kNew, std::memory_order_acq_rel);
  back = old & 3u;
}

// Brings the callback's public image up to this tick: this tick's dirty pixels when it was
// current at the previous tick, else everything.
void DisplayThread::Impl::update_tick_image(const PixelImage& img, bool full) {
  if (full || tick_image_synced != tick_index || tick_image.width != img.width ||
      tick_image.height != img.height) {
    export_image(img, tick_image);
  } else {
    for (uint32_t i : dirty[tick_index % kHistory]) export_pixel(img, tick_image, i);
    tick_image.info = img.info;
  }
  tick_image_synced = tick_index + 1;
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
    // The public layers are built here, on the consumer's thread, and only for images it takes.
    export_image(d.buf[d.front], d.latest);
  }
  if (is_new) *is_new = fresh;
  return d.latest;
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
