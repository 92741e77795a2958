// Engine control: layout (partition, pixel state, jobs), thread start/stop, deterministic
// stepping, the display-side collection of updates, and instrumentation. Updates from other
// processes come in through frameless/engine_ingest.cpp.
#include "frameless/engine.h"

#include <cmath>
#include <stdexcept>

#include "core/base/rng.h"
#include "core/scene/dynamic.h"
#include "frameless/engine_impl.h"
#include "frameless/thread_priority.h"

namespace frameless {

void Engine::Impl::record_error(const std::string& message) {
  {
    std::lock_guard<std::mutex> lock(error_mutex);
    if (!error) error = message;
  }
  stop_flag.store(true, std::memory_order_relaxed);
}

namespace {

int resolve_threads(int requested) {
  if (requested > 0) return requested;
  const unsigned hw = std::thread::hardware_concurrency();
  return hw ? int(hw) : 1;
}

// Installs `config` and rebuilds everything that depends on size, thread count, order or mode,
// in one critical section: the display never sees a new size with an old layout. Threads are
// stopped. A change without a resize keeps every pixel's state (moved if its slot changed).
void rebuild_layout(Engine::Impl& e, const EngineConfig& config) {
  std::lock_guard<std::mutex> lock(e.layout_mutex);
  const bool resized = !e.states || config.width != e.cfg.width || config.height != e.cfg.height;
  e.cfg = config;
  e.threads = resolve_threads(e.cfg.threads);
  // Counters follow the thread count at once (zeroed), so readers never index past them.
  e.counters.reset(new ThreadCounters[size_t(e.threads)]);
  e.partition = make_partition({e.cfg.width, e.cfg.height, e.threads, e.cfg.chunk_size,
                                e.cfg.order, e.cfg.seed});
  const size_t n = size_t(e.cfg.width) * size_t(e.cfg.height);
  e.jobs = make_tile_jobs(e.cfg.width, e.cfg.height, e.threads);
  e.job_pixels = tile_job_pixels(e.cfg.width, e.cfg.height, e.jobs);
  e.job_first_pixel.assign(1, 0);
  for (const TileJob& j : e.jobs) {
    size_t pixels = 0;
    const uint32_t tx = uint32_t((e.cfg.width + kTileWidth - 1) / kTileWidth);
    for (uint32_t t = j.first_tile; t < j.first_tile + j.tiles; ++t) {
      const int x0 = int(t % tx) * kTileWidth, y0 = int(t / tx) * kTileHeight;
      pixels += size_t(std::min(kTileWidth, e.cfg.width - x0)) *
                size_t(std::min(kTileHeight, e.cfg.height - y0));
    }
    e.job_first_pixel.push_back(e.job_first_pixel.back() + pixels);
  }
  // Slots in visiting order (see Engine::Impl::states): frameless, thread by thread along each
  // list; conventional, job order.
  std::vector<uint32_t> slot_pixel;
  e.thread_first_slot.assign(1, 0);
  if (e.cfg.mode == RenderMode::frameless) {
    slot_pixel.reserve(n);
    for (const std::vector<uint32_t>& list : e.partition.pixels) {
      slot_pixel.insert(slot_pixel.end(), list.begin(), list.end());
      e.thread_first_slot.push_back(slot_pixel.size());
    }
  } else {
    slot_pixel = e.job_pixels;
  }
  std::vector<uint32_t> slot_of(n, 0);
  for (size_t s = 0; s < n; ++s) slot_of[slot_pixel[s]] = uint32_t(s);
  if (resized) {
    e.states.reset(new PixelState[n]);
    e.levels.reset(new std::atomic<uint8_t>[n]());  // by pixel: a new slot order keeps it
    e.points.reset(new PixelPoint[n]);
    e.indirect.reset(e.scene.settings.integrator == Integrator::kIgi ? new PixelIndirect[n] : nullptr);
    ++e.cleared;
  } else if (slot_of != e.slot_of) {
    std::unique_ptr<PixelState[]> states(new PixelState[n]);
    for (size_t p = 0; p < n; ++p) copy_state(e.states[e.slot_of[p]], states[slot_of[p]]);
    e.states = std::move(states);
  }  // else: same slots (a restart, an update-% change), the states stay where they are
  e.slot_of = std::move(slot_of);
  e.pixel_count = n;
  // The display's copy of the order, replaced only when the order changed.
  if (e.cfg.mode != RenderMode::frameless)
    e.display_order.reset();
  else if (!e.display_order || *e.display_order != slot_pixel)
    e.display_order = std::make_shared<const std::vector<uint32_t>>(std::move(slot_pixel));
  for (auto& b : e.frames.buf) b.assign(n, PixelSnapshot{});
  if (e.cfg.closed_loop && e.cfg.mode == RenderMode::frameless)
    e.wanted.reset(n);
  else
    e.wanted.reset(0);
  e.sample_seed_base = mix64(e.scene.settings.seed ^ mix64(e.cfg.seed));
  e.generation.fetch_add(1, std::memory_order_release);
}

// Closed-loop sampling: the runs each render thread rendered out of walk order since the
// cursor, from its ring; a display that fell a ring behind gets the thread's whole range.
void collect_asked(Engine::Impl& e, UpdateCursor& cursor, UpdateSink& sink, int threads) {
  for (int t = 0; t < threads; ++t) {
    PriorityRing& ring = e.priority_rings[t];
    const size_t first = e.thread_first_slot[size_t(t)], end = e.thread_first_slot[size_t(t) + 1];
    uint64_t& seen = cursor.thread_asked[size_t(t)];
    const uint64_t head = ring.head.load(std::memory_order_acquire);
    if (head == seen) continue;
    bool lapped = head < seen || head - seen > PriorityRing::kCapacity / 2;
    for (uint64_t k = seen; !lapped && k < head; ++k) {
      const size_t slot = ring.first_slot[k % PriorityRing::kCapacity].load(std::memory_order_relaxed);
      if (slot < first || slot >= end) continue;  // never: a thread announces its own slots
      sink.slots(slot, &e.states[slot], std::min<size_t>(kRunLength, end - slot));
    }
    // Entries read while the thread kept writing may have been overwritten: check it did not lap.
    if (ring.head.load(std::memory_order_acquire) - seen > PriorityRing::kCapacity / 2) lapped = true;
    if (lapped && end > first) sink.slots(first, &e.states[first], end - first);
    seen = head;
  }
}

}  // namespace

Engine::Engine(const Scene& scene, const EngineConfig& config, const Camera& camera)
    : impl_(std::make_unique<Impl>(scene, config, camera)) {
  const std::string problem = validate(config);
  if (!problem.empty()) throw std::invalid_argument("engine config: " + problem);
  rebuild_layout(*impl_, EngineConfig(impl_->cfg));
}

Engine::~Engine() { stop(); }

void Engine::start() {
  Impl& e = *impl_;
  if (e.running) return;
  {
    std::lock_guard<std::mutex> lock(e.layout_mutex);
    e.stop_flag.store(false, std::memory_order_relaxed);
    e.counters.reset(new ThreadCounters[size_t(e.threads)]);
    e.priority_rings.reset(e.wanted.runs ? new PriorityRing[size_t(e.threads)] : nullptr);
    e.logs.assign(size_t(e.threads), UpdateLog{});
    if (e.cfg.update_log_capacity > 0)
      for (UpdateLog& l : e.logs) l.records.reserve(e.cfg.update_log_capacity);
    e.workers.assign(size_t(e.threads), FramelessWorker{});
    for (int t = 0; t < e.threads; ++t) {
      FramelessWorker& w = e.workers[size_t(t)];
      w.index = t;
      w.pixels = &e.partition.pixels[size_t(t)];
      w.first_slot = e.cfg.mode == RenderMode::frameless ? e.thread_first_slot[size_t(t)] : 0;
      const double n = double(w.pixels->size());
      w.interval = std::max<uint64_t>(1, uint64_t(std::ceil(e.cfg.update_percent / 100.0 * n)));
      // Stagger the camera checks so threads do not switch in lockstep.
      w.countdown = w.interval - (w.interval * uint64_t(t)) / uint64_t(e.threads);
      w.log = e.cfg.update_log_capacity > 0 ? &e.logs[size_t(t)] : nullptr;
      uint32_t ep = 0;
      const Camera cam = e.channel.read(&ep);
      w.basis = make_camera_basis(cam, e.cfg.width, e.cfg.height);
      w.epoch = ep;
      w.world = initial_world(e.scene);
      w.world_epoch = e.world_channel.read(w.world_buf);
      unpack_world(w.world_buf.data(), w.world_buf.size(), w.world);
      evaluate_frame(e.scene, w.world, e.now(), w.frame);
      e.pick_up_instances(w.instances_epoch, w.frame.instances);
      w.moving = !e.scene.dynamic.empty() || w.world_epoch > 1 || w.frame.instances;
      w.animated = !e.scene.dynamic.empty();
      w.settle_left = 0;
    }
    e.frame = FrameState{};
    e.frame.world = initial_world(e.scene);
    e.next_frame = e.frame;
    e.next_begun = false;
    e.frames.middle.store(1, std::memory_order_relaxed);
    e.frames.back = 0;
    e.frames.back2 = 3;
    e.frames.front = 2;
    e.frames.completed.store(0, std::memory_order_relaxed);
    e.next_job.store(0, std::memory_order_relaxed);
    e.frame_stop = false;
    begin_frame(e);
    e.ticks.store(0, std::memory_order_relaxed);
    e.start_time.store(e.now(), std::memory_order_relaxed);
    e.generation.fetch_add(1, std::memory_order_release);
  }
  e.running = true;
  // Every render thread first steps aside for interactive threads (EngineConfig::render_nice).
  const auto launch = [&e](void (*body)(Engine::Impl&, int), int t) {
    e.thread_handles.emplace_back([&e, body, t] {
      lower_thread_priority(e.cfg.render_nice);
      body(e, t);
    });
  };
  if (e.cfg.deterministic) {
    e.pool_quit = false;
    e.pool_generation = 0;
    for (int t = 0; t < e.threads; ++t)
      if (owns_thread(e.cfg, t)) launch(pool_thread_main, t);
  } else if (e.cfg.mode == RenderMode::frameless) {
    for (int t = 0; t < e.threads; ++t)
      if (owns_thread(e.cfg, t)) launch(frameless_thread_main, t);
  } else if (e.cfg.owned_count >= 0) {
    // Conventional across a cluster: a client's threads render the pieces its feed hands them;
    // a master (no threads) assembles the frames from what the clients send (ingest_piece).
    if (e.cfg.owned_count > 0 && !e.feed) throw std::logic_error("start: a cluster client needs a piece feed");
    for (int t = 0; t < e.threads; ++t)
      if (owns_thread(e.cfg, t)) launch(piece_thread_main, t);
  } else {
    e.barrier_arrive_ns.assign(size_t(e.threads), 0);
    e.barrier_leave_ns.assign(size_t(e.threads), 0);
    e.done_begin_ns = e.done_end_ns = 0;
    for (auto* a : {&e.barrier_frames, &e.barrier_release_sum_ns, &e.barrier_release_max_ns, &e.barrier_done_sum_ns,
                    &e.barrier_wait_sum_ns})
      a->store(0, std::memory_order_relaxed);
    e.barrier = std::make_unique<std::barrier<Impl::FrameDone>>(e.threads, Impl::FrameDone{&e});
    for (int t = 0; t < e.threads; ++t)
      launch(conventional_thread_main, t);
  }
}

void Engine::stop() {
  Impl& e = *impl_;
  if (!e.running) return;
  e.stop_flag.store(true, std::memory_order_relaxed);
  if (e.feed) e.feed->close();
  if (e.cfg.deterministic) {
    std::lock_guard<std::mutex> lock(e.pool_mutex);
    e.pool_quit = true;
    e.pool_cv.notify_all();
  }
  for (std::thread& t : e.thread_handles) t.join();
  e.thread_handles.clear();
  e.barrier.reset();
  e.running = false;
}

bool Engine::running() const { return impl_->running; }

void Engine::reconfigure(const EngineConfig& config) {
  const std::string problem = validate(config);
  if (!problem.empty()) throw std::invalid_argument("engine config: " + problem);
  Impl& e = *impl_;
  const bool was_running = e.running;
  stop();
  rebuild_layout(e, config);
  if (was_running) start();
}

void Engine::resize(int width, int height) {
  EngineConfig c = impl_->cfg;
  c.width = width;
  c.height = height;
  reconfigure(c);
}
void Engine::set_mode(RenderMode mode) {
  EngineConfig c = impl_->cfg;
  c.mode = mode;
  reconfigure(c);
}
void Engine::set_threads(int threads) {
  EngineConfig c = impl_->cfg;
  c.threads = threads;
  reconfigure(c);
}
void Engine::set_update_percent(double percent) {
  EngineConfig c = impl_->cfg;
  c.update_percent = percent;
  reconfigure(c);
}

EngineConfig Engine::config() const {
  EngineConfig c = impl_->cfg;
  c.threads = impl_->threads;
  return c;
}
int Engine::width() const { return impl_->cfg.width; }
int Engine::height() const { return impl_->cfg.height; }
int Engine::thread_count() const { return impl_->threads; }
const Partition& Engine::partition() const { return impl_->partition; }

namespace {

// Runs task(t) on every pool thread and waits for all.
void run_pool(Engine::Impl& e, std::function<void(int)> task) {
  std::unique_lock<std::mutex> lock(e.pool_mutex);
  e.pool_task = std::move(task);
  e.pool_pending = int(e.thread_handles.size());  // the owned threads (all, outside a cluster)
  ++e.pool_generation;
  e.pool_cv.notify_all();
  e.pool_done_cv.wait(lock, [&] { return e.pool_pending == 0; });
}

}  // namespace

void Engine::advance(double tick_seconds) {
  Impl& e = *impl_;
  if (!e.cfg.deterministic) throw std::logic_error("advance: engine is not deterministic");
  if (!e.running) start();
  if (e.stop_flag.load(std::memory_order_relaxed)) return;  // a render thread failed
  const uint64_t spu = uint64_t(samples_per_update(e.cfg));
  const uint64_t per_tick = e.cfg.samples_per_tick > 0 ? std::max<uint64_t>(1, e.cfg.samples_per_tick / spu)
                                                       : std::max<uint64_t>(1, e.pixel_count / 8);
  const uint64_t k = e.ticks.load(std::memory_order_relaxed);
  const double t_begin = e.virtual_time.load(std::memory_order_relaxed);

  if (e.cfg.mode == RenderMode::frameless) {
    // Thread t's cumulative budget after k ticks: floor(k * per_tick * n_t / N), exact.
    run_pool(e, [&](int t) {
      FramelessWorker& w = e.workers[size_t(t)];
      const unsigned __int128 share = (unsigned __int128)per_tick * w.pixels->size();
      const uint64_t target = uint64_t((share * (k + 1)) / e.pixel_count);
      const uint64_t count = target - w.budget_done;
      w.budget_done = target;
      const double dt = count ? tick_seconds / double(count) : 0.0;
      const uint64_t cpu0 = thread_cpu_ns();
      frameless_run(e, w, count, t_begin + dt, dt);
      e.counters[t].busy_ns.fetch_add(thread_cpu_ns() - cpu0, std::memory_order_relaxed);
    });
  } else {
    // Conventional: the frame advances by per_tick pixels, split evenly over the threads; a pixel's
    // value does not depend on which thread renders it, so the result is deterministic.
    uint64_t left = per_tick, done = 0;
    while (left > 0) {
      const size_t take = size_t(std::min<uint64_t>(left, e.pixel_count - e.frame_pos));
      const size_t base = e.frame_pos;
      const double dt = tick_seconds / double(per_tick);
      const double tb = t_begin + dt * double(done + 1);
      run_pool(e, [&](int t) {
        const size_t b = base + take * size_t(t) / size_t(e.threads);
        const size_t en = base + take * size_t(t + 1) / size_t(e.threads);
        conventional_range(e, t, e.frame, b, en, tb + dt * double(b - base), dt,
                           e.frames.buf[e.frames.back].data(), nullptr);
      });
      // Across a cluster the other ranks render the segment now (ingest_piece), split the same way.
      if (e.remote_pieces)
        e.remote_pieces(spec_of(e.frame), FramePiece{e.frame.serial, uint32_t(base),
                                                     uint32_t(base + take), tb, dt});
      e.frame_pos += take;
      left -= take;
      done += take;
      if (e.frame_pos == e.pixel_count) {
        publish_frame(e);
        begin_frame(e);
      }
    }
  }
  if (e.remote_advance) e.remote_advance(k, tick_seconds);
  e.virtual_time.store(t_begin + tick_seconds, std::memory_order_relaxed);
  e.ticks.store(k + 1, std::memory_order_relaxed);
}

uint64_t Engine::ticks() const { return impl_->ticks.load(std::memory_order_relaxed); }
double Engine::now() const { return impl_->now(); }

CollectResult Engine::collect(UpdateCursor& cursor, UpdateSink& sink) {
  Impl& e = *impl_;
  std::lock_guard<std::mutex> lock(e.layout_mutex);
  CollectResult r;
  r.mode = e.cfg.mode;
  r.width = e.cfg.width;
  r.height = e.cfg.height;
  r.slot_pixel = e.display_order;
  r.levels = e.levels.get();
  r.points = e.points.get();
  r.indirect = e.indirect.get();
  r.interleave = e.indirect ? std::max(1, e.scene.settings.igi.interleave) : 0;
  r.wanted = e.wanted.runs && e.priority_rings ? &e.wanted : nullptr;
  r.world_moves = !e.scene.dynamic.empty() || e.instances_epoch.load(std::memory_order_relaxed) > 1 ||
                  e.world_channel.epoch() > 1;
  r.newest_epoch = e.channel.epoch();
  r.time = e.now();
  const int threads = e.threads;  // counters always have this many entries (see rebuild_layout)
  for (int t = 0; t < threads; ++t) {
    r.samples += e.counters[t].samples.load(std::memory_order_relaxed);
    r.dropped += e.counters[t].dropped.load(std::memory_order_relaxed);
  }
  const uint64_t generation = e.generation.load(std::memory_order_acquire);
  r.resync = cursor.generation != generation;
  if (r.resync) {
    r.reset = cursor.cleared != e.cleared || cursor.width != r.width || cursor.height != r.height;
    cursor.generation = generation;
    cursor.cleared = e.cleared;
    cursor.width = r.width;
    cursor.height = r.height;
    cursor.thread_updates.assign(size_t(threads), 0);
    cursor.thread_asked.assign(size_t(threads), 0);
  }
  sink.begin(r);

  if (e.cfg.mode == RenderMode::frameless) {
    if (r.resync) {
      // Counters first: anything published during the scan is offered (again) next time.
      for (int t = 0; t < threads; ++t)
        cursor.thread_updates[size_t(t)] = e.counters[t].updates.load(std::memory_order_acquire);
      if (e.pixel_count) sink.slots(0, &e.states[0], e.pixel_count);
      if (r.wanted)
        for (int t = 0; t < threads; ++t)
          cursor.thread_asked[size_t(t)] = e.priority_rings[t].head.load(std::memory_order_acquire);
      return r;
    }
    for (int t = 0; t < threads; ++t) {
      const uint64_t n = e.partition.pixels[size_t(t)].size();
      const size_t first = e.thread_first_slot[size_t(t)];
      const uint64_t now = e.counters[t].updates.load(std::memory_order_acquire);
      uint64_t& seen = cursor.thread_updates[size_t(t)];
      if (n == 0 || now == seen) continue;
      // Visit u touched list position u mod n, which is slot first + (u mod n): the counter
      // alone says which slots changed, as at most two runs (the second when the range wraps).
      const uint64_t from = now - seen >= n ? now - n : seen;
      const size_t pos = size_t(from % n), len = size_t(now - from);
      const size_t head = std::min(len, size_t(n) - pos);
      sink.slots(first + pos, &e.states[first + pos], head);
      if (head < len) sink.slots(first, &e.states[first], len - head);
      seen = now;
    }
    if (r.wanted) collect_asked(e, cursor, sink, threads);
    return r;
  }

  // Conventional: only completed frames, each once.
  FrameBuffers& f = e.frames;
  if (f.middle.load(std::memory_order_acquire) & FrameBuffers::kNew) {
    const uint32_t old = f.middle.exchange(f.front, std::memory_order_acq_rel);
    f.front = old & 3u;
    sink.frame(f.buf[f.front]);
    r.new_frame = true;
  }
  return r;
}

void Engine::note_display_tick(uint32_t index) {
  impl_->display_tick.store(index, std::memory_order_relaxed);
}

EngineStats Engine::stats() const {
  Impl& e = *impl_;
  std::lock_guard<std::mutex> lock(e.layout_mutex);  // any thread, even during a reconfiguration
  EngineStats s;
  s.seconds = e.now() - e.start_time.load(std::memory_order_relaxed);
  s.camera_epoch = e.channel.epoch();
  s.frames_completed = e.frames.completed.load(std::memory_order_relaxed);
  if (const uint64_t n = e.barrier_frames.load(std::memory_order_relaxed); n > 0) {
    s.barrier_frames = n;
    s.barrier_release_mean_us = double(e.barrier_release_sum_ns.load(std::memory_order_relaxed)) / double(n) * 1e-3;
    s.barrier_release_max_us = double(e.barrier_release_max_ns.load(std::memory_order_relaxed)) * 1e-3;
    s.barrier_completion_mean_us = double(e.barrier_done_sum_ns.load(std::memory_order_relaxed)) / double(n) * 1e-3;
    s.barrier_wait_mean_us = double(e.barrier_wait_sum_ns.load(std::memory_order_relaxed)) / double(n) * 1e-3;
  }
  for (int t = 0; t < e.threads; ++t) {
    ThreadStats ts;
    ts.pixels = e.cfg.mode == RenderMode::frameless ? e.partition.pixels[size_t(t)].size() : 0;
    ts.samples = e.counters[t].samples.load(std::memory_order_relaxed);
    ts.updates = e.counters[t].updates.load(std::memory_order_relaxed);
    ts.dropped = e.counters[t].dropped.load(std::memory_order_relaxed);
    ts.samples_per_s = s.seconds > 0 ? double(ts.samples) / s.seconds : 0.0;
    ts.busy_seconds = double(e.counters[t].busy_ns.load(std::memory_order_relaxed)) * 1e-9;
    s.samples += ts.samples;
    s.updates += ts.updates;
    s.dropped += ts.dropped;
    s.threads.push_back(ts);
  }
  s.samples_per_s = s.seconds > 0 ? double(s.samples) / s.seconds : 0.0;
  return s;
}

std::optional<std::string> Engine::error() const {
  std::lock_guard<std::mutex> lock(impl_->error_mutex);
  return impl_->error;
}

const UpdateLog& Engine::update_log(int thread) const {
  static const UpdateLog empty;
  if (thread < 0 || size_t(thread) >= impl_->logs.size()) return empty;
  return impl_->logs[size_t(thread)];
}

bool Engine::read_pixel(int x, int y, PixelSnapshot& out) const {
  const Impl& e = *impl_;
  if (x < 0 || y < 0 || x >= e.cfg.width || y >= e.cfg.height) return false;
  const size_t pixel = size_t(y) * size_t(e.cfg.width) + size_t(x);
  if (!frameless::read_pixel(e.states[e.slot_of[pixel]], out)) return false;
  out.levels = e.levels[pixel].load(std::memory_order_relaxed);
  return true;
}

void Engine::copy_levels(std::vector<uint8_t>& out) const {
  Impl& e = *impl_;
  std::lock_guard<std::mutex> lock(e.layout_mutex);  // a resize replaces the array
  out.resize(e.pixel_count);
  for (size_t i = 0; i < e.pixel_count; ++i) out[i] = e.levels[i].load(std::memory_order_relaxed);
}

}  // namespace frameless
