// Conventional frames across a cluster: a client's frames and piece feed, a master's frame
// assembly from the pieces its clients render (frameless/remote_frames.h).
#include <cmath>
#include <stdexcept>

#include "core/scene/dynamic.h"
#include "frameless/engine.h"
#include "frameless/engine_impl.h"

namespace frameless {

void Engine::set_piece_feed(PieceFeed* feed) {
  if (impl_->running) throw std::logic_error("set_piece_feed: engine is running");
  impl_->feed = feed;
}

std::shared_ptr<const FrameState> Engine::remote_frame(const FrameSpec& spec) const {
  Impl& e = *impl_;
  auto f = std::make_shared<FrameState>();
  f->world = initial_world(e.scene);
  std::vector<float> buf;
  f->world_epoch = e.world_channel.read(buf);
  unpack_world(buf.data(), buf.size(), f->world);
  e.pick_up_instances(f->instances_epoch, f->instances);
  f->serial = spec.serial;
  f->epoch = spec.epoch;
  f->camera = spec.camera;
  f->basis = make_camera_basis(spec.camera, e.partition.width, e.partition.height);
  f->time = spec.time;
  return f;
}

void Engine::render_feed() {
  Impl& e = *impl_;
  if (!e.cfg.deterministic || !e.feed) throw std::logic_error("render_feed: needs deterministic mode and a feed");
  if (!e.running) start();
  std::unique_lock<std::mutex> lock(e.pool_mutex);
  e.pool_task = [&e](int t) {
    std::unique_ptr<PieceJob> job;
    while (e.feed->next(t, job)) {
      render_piece(e, t, *job);
      e.feed->done(t, std::move(job));
    }
  };
  e.pool_pending = int(e.thread_handles.size());
  ++e.pool_generation;
  e.pool_cv.notify_all();
  e.pool_done_cv.wait(lock, [&] { return e.pool_pending == 0; });
}

FrameSpec Engine::current_frame() const { return spec_of(impl_->frame); }

std::optional<FrameSpec> Engine::begin_next_frame() {
  Impl& e = *impl_;
  if (e.next_begun) return std::nullopt;
  e.next_frame.world = e.frame.world;  // fill_frame reads the world only when it changed
  e.next_frame.world_epoch = e.frame.world_epoch;
  e.next_frame.instances_epoch = e.frame.instances_epoch;
  e.next_frame.instances = e.frame.instances;
  fill_frame(e, e.next_frame, e.frame.serial + 1);
  e.next_begun = true;
  return spec_of(e.next_frame);
}

FrameWorld Engine::frame_world(uint64_t serial) const {
  const Impl& e = *impl_;
  const FrameState* f = serial == e.frame.serial ? &e.frame
                        : e.next_begun && serial == e.next_frame.serial ? &e.next_frame
                                                                       : nullptr;
  if (!f) throw std::out_of_range("frame_world: frame " + std::to_string(serial) + " is not in flight");
  return FrameWorld{f->world_epoch, f->world, f->instances_epoch, f->instances};
}

void Engine::publish_current_frame() {
  Impl& e = *impl_;
  if (!e.next_begun) begin_next_frame();
  publish_frame(e);
  std::swap(e.frame, e.next_frame);
  e.next_begun = false;
}

void Engine::ingest_piece(int thread, const FramePiece& piece, const PixelRecord* records,
                          uint64_t samples, uint64_t dropped, uint64_t busy_ns) {
  Impl& e = *impl_;
  std::lock_guard<std::mutex> lock(e.layout_mutex);  // the layout stays put
  auto bad = [&](const std::string& what) {
    throw std::invalid_argument("remote thread " + std::to_string(thread) + ": " + what);
  };
  if (e.cfg.mode != RenderMode::conventional) bad("pieces need conventional mode");
  if (thread < 0 || thread >= e.threads) bad("no such render thread");
  if (owns_thread(e.cfg, thread)) bad("this process renders that thread itself");
  const FrameState* f = piece.serial == e.frame.serial ? &e.frame
                        : e.next_begun && piece.serial == e.next_frame.serial ? &e.next_frame
                                                                             : nullptr;
  if (!f) bad("frame " + std::to_string(piece.serial) + " is not in flight");
  if (piece.begin >= piece.end || piece.end > e.pixel_count)
    bad("slots " + std::to_string(piece.begin) + ".." + std::to_string(piece.end) + " out of range");
  const size_t n = piece.end - piece.begin;
  if (samples > 2 * n || dropped > samples) bad("sample counts out of range");
  for (size_t k = 0; k < n; ++k) {
    const PixelRecord& r = records[k];
    if (r.epoch > f->epoch) bad("camera epoch " + std::to_string(r.epoch) + " after its frame's");
    if (r.epoch > 0 && r.count < 1) bad("a sampled pixel without samples");
    bool finite = std::isfinite(r.m2) && r.m2 >= 0.0 && std::isfinite(r.time);
    for (int c = 0; c < 3; ++c) finite = finite && std::isfinite(r.sample[c]) && std::isfinite(r.mean[c]);
    if (!finite) bad("non-finite value in slot " + std::to_string(piece.begin + k));
  }
  PixelSnapshot* frame = e.frames.buf[f == &e.frame ? e.frames.back : e.frames.back2].data();
  for (size_t k = 0; k < n; ++k) {
    // A state computed elsewhere, published as a render thread publishes its own.
    const PixelRecord& r = records[k];
    PixelState& s = e.states[piece.begin + k];
    const uint32_t idx = e.job_pixels[piece.begin + k];
    s.passes.store(r.passes, std::memory_order_relaxed);
    const uint32_t seq = publish_state(s, r.count, r.epoch, r.mean, r.m2, r.sample, r.time, [&] {
      e.levels[idx].store(r.levels, std::memory_order_relaxed);
    });
    PixelSnapshot& o = frame[idx];  // what finish_update() writes into a local frame
    o.sample = r.sample;
    o.mean = Vec3(float(r.mean[0]), float(r.mean[1]), float(r.mean[2]));
    o.variance = r.count > 1 ? float(r.m2 / double(r.count - 1)) : 0.0f;
    o.count = r.count;
    o.epoch = r.epoch;
    o.time = r.time;
    o.seq = seq;
    o.levels = r.levels;
  }
  ThreadCounters& c = e.counters[thread];
  constexpr auto rl = std::memory_order_relaxed;
  c.samples.store(c.samples.load(rl) + samples, rl);
  c.dropped.store(c.dropped.load(rl) + dropped, rl);
  if (busy_ns) c.busy_ns.store(busy_ns, rl);
  c.updates.store(c.updates.load(rl) + n, std::memory_order_release);
}

void Engine::read_records(uint32_t begin, uint32_t end, PixelRecord* out) const {
  const Impl& e = *impl_;
  if (begin > end || end > e.pixel_count) throw std::out_of_range("read_records: slots out of range");
  for (uint32_t i = begin; i < end; ++i)  // the caller is the states' one writer
    out[i - begin] = record_of(e, e.states[i], e.job_pixels[i]);
}

void Engine::set_remote_pieces(std::function<void(const FrameSpec&, const FramePiece&)> fn) {
  impl_->remote_pieces = std::move(fn);
}

const std::vector<uint32_t>& Engine::job_pixels() const { return impl_->job_pixels; }
const std::vector<size_t>& Engine::job_first_slot() const { return impl_->job_first_pixel; }

}  // namespace frameless
