// Display thread: collect -> blend -> publish through a triple buffer whose back buffer is
// brought up to date from short per-tick lists of changed slot runs, so a tick costs in
// proportion to the pixels that changed, not to the image size. The display thread keeps one
// 32-byte struct per pixel in the engine's slot order (the order render threads visit pixels),
// so the reads, blends and copies of a tick all stream through memory; the public DisplayImage
// layers (pixel order) are built only for whoever asks: the consumer in acquire_latest(), and
// the on-tick callback when one is set.
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

#include "display/display_pixel.h"
#include "display/reproject.h"
#include "frameless/cpu_clock.h"

namespace frameless {
namespace {

constexpr uint32_t kNew = 4;
constexpr uint32_t kEpochRing = 4096;  // epochs tracked for coverage (older ones are never newest)
constexpr uint64_t kHistory = 8;       // ticks of change lists kept (buffers and consumers catch up from them)
constexpr size_t kIntervalsKept = 1024;

// The engine's slot order and its inverse (built once per layout by the display thread).
struct SlotLayout {
  std::shared_ptr<const std::vector<uint32_t>> pixel_of;  // slot -> pixel (shared with the engine)
  std::vector<uint32_t> slot_of;                          // pixel -> slot
};
using LayoutPtr = std::shared_ptr<const SlotLayout>;  // null: slot s is pixel s

LayoutPtr make_layout(std::shared_ptr<const std::vector<uint32_t>> order) {
  if (!order) return nullptr;
  auto l = std::make_shared<SlotLayout>();
  l->slot_of.resize(order->size());
  for (size_t s = 0; s < order->size(); ++s) l->slot_of[(*order)[s]] = uint32_t(s);
  l->pixel_of = std::move(order);
  return l;
}

// A run of consecutive slots changed in one tick.
struct SlotRun {
  uint32_t first = 0;
  uint32_t count = 0;
};

// What the last kHistory ticks changed: tick t's slot runs in runs[t % kHistory], or full[...]
// when it changed (or cleared, or re-laid out) the whole image. Ticks before `newest` are recorded.
struct ChangeHistory {
  std::vector<SlotRun> runs[kHistory];
  bool full[kHistory] = {};
  uint64_t newest = 0;

  // Whether an image holding ticks before `have` can be brought to ticks before `now` from runs.
  bool covers(uint64_t have, uint64_t now) const {
    if (have == 0 || have > now || now > newest || have + kHistory < newest) return false;
    for (uint64_t t = have; t < now; ++t)
      if (full[t % kHistory]) return false;
    return true;
  }
};

// The display thread's image: the DisplayImage layers interleaved per pixel, stored by slot.
struct PixelImage {
  int width = 0;
  int height = 0;
  LayoutPtr layout;
  std::vector<DisplayPixel> px;
  FrameInfo info;
  ChangeHistory history;  // the display's change history when this image was published

  size_t pixels() const { return size_t(width) * size_t(height); }
  uint32_t pixel_of(size_t slot) const { return layout ? (*layout->pixel_of)[slot] : uint32_t(slot); }
  uint32_t slot_of(size_t pixel) const { return layout ? layout->slot_of[pixel] : uint32_t(pixel); }
  void reset(int w, int h, LayoutPtr l) {
    width = w;
    height = h;
    layout = std::move(l);
    px.assign(pixels(), DisplayPixel{});
  }
  // With the display's points and marks (which live outside the triple buffer: only the display
  // thread reads them), for reprojection.
  SlotImage slots(std::vector<ScenePoint>& points, std::vector<uint8_t>& marks,
                  const PixelPoint* engine_points = nullptr) {
    return {width,       height,        layout ? layout->pixel_of->data() : nullptr,
            layout ? layout->slot_of.data() : nullptr,
            px.data(),   points.data(), marks.data(), engine_points};
  }
};

// Writes the layers of slot `s` of `src` into pixel i of `dst`.
inline void export_pixel(const PixelImage& src, size_t s, DisplayImage& dst, size_t i) {
  const DisplayPixel& p = src.px[s];
  dst.rgb[3 * i] = p.rgb[0];
  dst.rgb[3 * i + 1] = p.rgb[1];
  dst.rgb[3 * i + 2] = p.rgb[2];
  dst.last_update[i] = p.last_update;
  dst.sample_count[i] = p.count;
  dst.variance[i] = p.variance;
  dst.epoch[i] = p.epoch;
  dst.levels[i] = p.levels;
}

// Converts the whole image into the public layer layout. It walks the pixels in order and
// gathers each from its slot: the writes stream, and the reads of a band of rows stay within
// the few hundred kilobytes of the Hilbert chunks that cover it.
void export_image(const PixelImage& src, DisplayImage& dst) {
  if (dst.width != src.width || dst.height != src.height || dst.epoch.size() != src.pixels() ||
      dst.levels.size() != src.pixels())
    dst.reset(src.width, src.height);
  const size_t n = src.pixels();
  if (src.layout) {
    const uint32_t* slot = src.layout->slot_of.data();
    for (size_t i = 0; i < n; ++i) export_pixel(src, slot[i], dst, i);
  } else {
    for (size_t i = 0; i < n; ++i) export_pixel(src, i, dst, i);
  }
  dst.info = src.info;
}

// Brings `out` (public layers, pixel order) up to `img`: patches the slots changed since the
// image it holds (ticks before `synced`) when img's change history covers them, else rebuilds it.
void sync_public(const PixelImage& img, DisplayImage& out, uint64_t& synced) {
  const uint64_t now = img.info.index + 1;
  if (out.width == img.width && out.height == img.height && img.history.covers(synced, now)) {
    for (uint64_t t = synced; t < now; ++t)
      for (const SlotRun& run : img.history.runs[t % kHistory])
        for (size_t s = run.first; s < size_t(run.first) + run.count; ++s)
          export_pixel(img, s, out, img.pixel_of(s));
    out.info = img.info;
  } else {
    export_image(img, out);
  }
  synced = now;
}

// `by_slot` (one entry per slot of `from`) with each pixel's entry moved to its slot under `to`
// (a layout change, same size; null layouts: slot s is pixel s).
template <typename T>
std::vector<T> to_new_slots(const std::vector<T>& by_slot, const SlotLayout* from, const SlotLayout* to) {
  std::vector<T> out(by_slot.size());
  for (size_t s = 0; s < out.size(); ++s) {
    const uint32_t pixel = to ? (*to->pixel_of)[s] : uint32_t(s);
    out[s] = by_slot[from ? from->slot_of[pixel] : pixel];
  }
  return out;
}

// dst <- src with each pixel moved to its slot under `layout` (a layout change, same size).
void remap(const PixelImage& src, PixelImage& dst, LayoutPtr layout) {
  dst.width = src.width;
  dst.height = src.height;
  dst.px = to_new_slots(src.px, src.layout.get(), layout.get());
  dst.layout = std::move(layout);
}

}  // namespace

struct DisplayThread::Impl {
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
  uint64_t pixels_updated = 0;  // since construction
  LayoutPtr layout;             // the engine's current slot order, with its inverse
  // By slot: the engine's sequence number of the update each slot shows, so that update is not
  // blended twice. One array for the three buffers (each is brought up to the newest image before
  // a tick blends into it); apart from the pixels, so reprojection leaves it where it is.
  std::vector<uint32_t> shown_seq;
  std::vector<uint32_t> epoch_tag, epoch_count;  // coverage: pixels currently showing each epoch
  ChangeHistory history;  // what the last ticks changed
  // Reprojection: the camera the image was last moved to (epoch 0: none yet) and scratch.
  // image_moved: the image was moved since reprojection (re)started; until then it shows its
  // updates where they were rendered, so older cameras' updates are not redirected.
  uint32_t reproject_epoch = 0;
  bool image_moved = false;
  CameraBasis reproject_basis;
  Reprojector reprojector;
  PixelImage reprojected;
  // Reprojection's marks by pixel and, for marked pixels (content moved there), their points; an
  // unmarked pixel's point is the engine's. The display thread's alone, so outside the triple
  // buffer; with the reprojection's output for them.
  std::vector<ScenePoint> points, points_out;
  std::vector<uint8_t> marks, marks_out;
  ReprojectTotals reproject_totals;
  ReprojectBudget reproject_budget;

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
  DisplayImage latest;        // consumer: public layers of buf[front]
  uint64_t latest_synced = 0;  // consumer: ticks whose changes `latest` holds (0: none)

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

  // Recounts the coverage from scratch (after reprojection moved epochs around).
  void recount_epochs(const PixelImage& img) {
    epoch_tag.assign(kEpochRing, 0);
    epoch_count.assign(kEpochRing, 0);
    for (const DisplayPixel& p : img.px)
      if (p.epoch != 0) count_epoch(0, p.epoch);
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
  void publish();
  void thread_main();
};

namespace {

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
  bool conventional = false;
  size_t dirty_slots = 0;     // slots in *dirty
  uint64_t changed = 0;       // pixels blended
  uint64_t rejected = 0;      // blends that came out non-finite (kept the previous value)

  void begin(const CollectResult& r) override;
  void slots(size_t first, const PixelState* states, size_t count) override;
  void frame(const std::vector<PixelSnapshot>& pixels) override;
  void show(DisplayPixel& m, const PixelSnapshot& u, bool guess);
  void redirect(const PixelSnapshot& u, const ScenePoint& point);
  void mark_dirty(size_t first, size_t count) {
    if (full) return;
    dirty->push_back({uint32_t(first), uint32_t(count)});
    dirty_slots += count;
    if (dirty_slots > image->pixels() / 4) full = true;  // cheaper to copy everything
  }
};

}  // namespace

void TickSink::begin(const CollectResult& r) {
  conventional = r.mode == RenderMode::conventional;
  full = d.catch_up(r);
  image = &d.buf[d.back];
  levels = r.levels;
  dirty = &d.history.runs[d.tick_index % kHistory];
  dirty->clear();
  reproject = reproject && !conventional && r.points;
  wanted = conventional ? nullptr : r.wanted;
  points = reproject ? r.points : nullptr;
  if (d.reproject(*image, reproject, rule.config.reproject_budget, r.world_moves, r.points)) {
    full = true;
    if (wanted) {  // closed loop: what reprojection could not guess (nothing near it, may have moved) first
      const uint8_t* marks = d.marks.data();
      for (size_t pixel = 0; pixel < d.marks.size(); ++pixel)
        if (marks[pixel] & (kMarkUnknown | kMarkStale)) wanted->want(image->slot_of(pixel));
      wanted->publish();
    }
  }
}

// Closed loop: a sample of the same camera far from what its pixel shows (beyond its noise, as
// temporal_alpha judges) means something moves there: ask for its run again soon. (After a camera
// change every pixel jumps; reprojection's marks ask for what matters then.)
inline bool jumps(const DisplayPixel& m, const PixelSnapshot& u) {
  // Four samples at least: before that the pixel's noise is not known.
  if (m.epoch == 0 || m.epoch != u.epoch || u.count < 4) return false;
  return temporal_alpha(1.0f, Vec3(m.rgb[0], m.rgb[1], m.rgb[2]), u) >= 1.0f;
}

// `guess`: what the pixel shows was guessed by reprojection (a crack, a disocclusion, something
// that may have moved): the first real sample replaces it whole.
inline void TickSink::show(DisplayPixel& m, const PixelSnapshot& u, bool guess) {
  bool bad = false;
  const Vec3 c = blend_pixel(rule, conventional, Vec3(m.rgb[0], m.rgb[1], m.rgb[2]),
                             guess ? 0u : m.epoch, m.last_update, u, &bad);
  rejected += bad;
  d.count_epoch(m.epoch, u.epoch);
  m.rgb[0] = c.x;
  m.rgb[1] = c.y;
  m.rgb[2] = c.z;
  m.last_update = u.time;
  m.count = u.count;
  m.variance = std::isfinite(u.variance) ? u.variance : 0.0f;
  m.epoch = u.epoch;
  ++changed;
}

// An update rendered with a camera older than the one the image was moved to belongs where its
// point now projects (the render cache): blended there if nothing nearer is shown, never at its
// own pixel, which shows moved content by now.
void TickSink::redirect(const PixelSnapshot& u, const ScenePoint& point) {
  float px, py, depth;
  const CameraBasis& b = d.reproject_basis;
  if (!project_point(b, point, px, py, depth)) return;
  const size_t pixel = size_t(int(py)) * size_t(image->width) + size_t(int(px));
  const size_t slot = image->slot_of(pixel);
  uint8_t& mark = d.marks[pixel];
  // A marked pixel shows moved content with its moved point; an unmarked one its own newest
  // update (a point its owner keeps rewriting: leave the pixel as it is).
  ScenePoint shown;
  if (mark)
    shown = d.points[pixel];
  else if (!read_point(points[pixel], shown))
    return;
  float sx, sy, shown_depth;
  const bool nearer = !project_point(b, shown, sx, sy, shown_depth) || depth <= shown_depth * 1.01f;
  if (!(mark & kMarkGuess) && !nearer) return;  // hidden behind what the pixel shows
  DisplayPixel& m = image->px[slot];
  const Vec3 c = (mark & kMarkGuess) ? u.sample : blend(Vec3(m.rgb[0], m.rgb[1], m.rgb[2]), u.sample, rule.config.alpha);
  if (!is_finite(c)) return;
  m.rgb[0] = c.x;
  m.rgb[1] = c.y;
  m.rgb[2] = c.z;
  d.points[pixel] = point;
  mark = kMarkMoved;
  ++d.reproject_totals.redirected;
  mark_dirty(slot, 1);
}

void TickSink::slots(size_t first, const PixelState* states, size_t count) {
  DisplayPixel* px = image->px.data() + first;
  uint32_t* seq = d.shown_seq.data() + first;
  PixelSnapshot u;
  for (size_t i = 0; i < count; ++i) {
    // A slot whose owner kept writing it is picked up on the owner's next visit.
    if (!read_pixel(states[i], u) || u.epoch == 0 || u.seq == seq[i]) continue;
    seq[i] = u.seq;
    const size_t pixel = image->pixel_of(first + i);
    uint8_t* mark = nullptr;  // reprojection's mark of this pixel (null: reprojection off)
    if (points) {
      if (u.epoch < d.reproject_epoch && d.image_moved) {
        // The update's own point (read in the same sequence lock); if a newer update has replaced
        // it, that one is collected at the next tick instead.
        ScenePoint point;
        if (read_point_of(states[i], u.seq, points[pixel], point)) redirect(u, point);
        continue;
      }
      mark = &d.marks[pixel];
    }
    const bool guess = mark && (*mark & kMarkGuess);
    if (wanted && !guess && jumps(px[i], u)) {
      wanted->want(first + i);
      asked = true;
    }
    show(px[i], u, guess);
    // Unmarked: the engine's point is this pixel's (read at the next reprojection), so a tick
    // costs a byte per update here, not a point.
    if (mark && *mark) *mark = kMarkNone;
    // Read after the state's seq: these levels are the shown update's or a newer one's.
    if (levels) px[i].levels = levels[pixel].load(std::memory_order_relaxed);
  }
  mark_dirty(first, count);
  if (asked) {  // inside collect(): the asks stay valid (the layout is locked)
    wanted->publish();
    asked = false;
  }
}

void TickSink::frame(const std::vector<PixelSnapshot>& pixels) {
  const size_t n = std::min(pixels.size(), image->px.size());
  for (size_t i = 0; i < n; ++i) {
    if (pixels[i].epoch == 0) continue;
    show(image->px[i], pixels[i], false);
    d.shown_seq[i] = 0;  // frames carry no sequence number; frameless updates compare against 0
    image->px[i].levels = pixels[i].levels;
  }
  full = true;
}

FrameInfo DisplayThread::Impl::run_tick(double interval) {
  DisplayConfig cfg;
  {
    std::lock_guard<std::mutex> lock(config_mutex);
    cfg = config;
  }
  engine.note_display_tick(uint32_t(tick_index));
  TickSink sink(*this, cfg);
  const CollectResult r = engine.collect(cursor, sink);
  const bool full = sink.full;
  history.full[tick_index % kHistory] = full;
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
  const uint32_t covered = epoch_tag.empty() || epoch_tag[e % kEpochRing] != e ? 0 : epoch_count[e % kEpochRing];
  info.coverage = image.pixels() ? double(covered) / double(image.pixels()) : 0.0;
  info.newest_epoch = e;
  info.mode = r.mode;
  info.dropped_samples = r.dropped;
  info.rejected = rejected;

  publish();
  if (on_tick) {
    sync_public(image, tick_image, tick_image_synced);
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
  const size_t n = size_t(r.width) * size_t(r.height);
  if ((layout ? layout->pixel_of : nullptr) != r.slot_pixel) {
    LayoutPtr next = make_layout(r.slot_pixel);
    // Each pixel keeps the seq it shows, in its new slot.
    if (shown_seq.size() == n) shown_seq = to_new_slots(shown_seq, layout.get(), next.get());
    layout = std::move(next);
  }
  PixelImage& img = buf[back];
  if (r.reset || newest > 2 || buf[newest].width != r.width || buf[newest].height != r.height) {
    shown_seq.assign(n, 0);
    img.reset(r.width, r.height, layout);
    reset_reprojection();  // a cleared or resized image has no points (same pixel count or not)
    epoch_tag.assign(kEpochRing, 0);
    epoch_count.assign(kEpochRing, 0);
    return true;
  }
  const PixelImage& src = buf[newest];
  if (src.layout != layout) {
    remap(src, img, layout);
    return true;
  }
  const uint64_t have = synced[back];
  if (img.width != r.width || img.height != r.height || img.layout != src.layout ||
      !history.covers(have, tick_index)) {
    img.width = src.width;
    img.height = src.height;
    img.layout = src.layout;
    img.px = src.px;
    return false;
  }
  for (uint64_t t = have; t < tick_index; ++t)
    for (const SlotRun& run : history.runs[t % kHistory]) {
      std::memcpy(&img.px[run.first], &src.px[run.first], run.count * sizeof(DisplayPixel));
    }
  return false;
}

// Moves the back buffer to the newest camera, once per camera change; true when it did.
bool DisplayThread::Impl::reproject(PixelImage& img, bool enabled, float budget, bool world_moves,
                                    const PixelPoint* engine_points) {
  if (!enabled) {
    reset_reprojection();
    return false;
  }
  if (points.size() != img.pixels()) {  // just turned on, or cleared: nothing shown has a point yet
    reset_reprojection();
    points.assign(img.pixels(), ScenePoint{});
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
  const ReprojectStats st = reprojector.run(reproject_basis, img.slots(points, marks, engine_points),
                                            out.slots(points_out, marks_out), world_moves);
  image_moved = true;
  std::swap(img.px, out.px);
  std::swap(points, points_out);
  std::swap(marks, marks_out);
  recount_epochs(img);
  ReprojectTotals& t = reproject_totals;
  ++t.reprojections;
  t.moved += st.moved;
  t.filled += st.filled;
  t.disoccluded += st.disoccluded;
  t.stale += st.stale;
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
  const bool fresh = d.middle.load(std::memory_order_acquire) & kNew;
  if (fresh) {
    const uint32_t old = d.middle.exchange(d.front, std::memory_order_acq_rel);
    d.front = old & 3u;
    // The public layers are built here, on the consumer's thread, and only for images it takes:
    // from the image's change history when it covers the ticks since the last one taken.
    sync_public(d.buf[d.front], d.latest, d.latest_synced);
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
