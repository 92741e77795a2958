// Render threads' conventional loop (double buffering, the baseline frameless is measured
// against): whole frames rendered by ranges or pieces, then published at once. Render threads;
// the per-sample path is the frameless loop's (frameless/pixel_update.h).
#include <algorithm>
#include <chrono>
#include <thread>

#include "frameless/pixel_update.h"

namespace frameless {

using namespace render_detail;

void conventional_range(Engine::Impl& e, int t, const FrameState& f, size_t begin, size_t end,
                        double t_begin, double dt, PixelSnapshot* frame, PixelRecord* out) {
  ThreadCounters& ctr = e.counters[t];
  // A conventional frame sees one instant: its world is evaluated once per frame and thread.
  FramelessWorker& w = e.workers[size_t(t)];
  if (w.frame_serial != f.serial) {
    w.moving = !e.scene.dynamic.empty() || f.world_epoch > 1 || f.instances;
    w.animated = !e.scene.dynamic.empty();
    // A frame whose world differs from the previous frame's settles (frameless/engine_impl.h).
    w.settle_left = f.world_epoch != w.world_epoch || f.instances != w.frame.instances ? 1 : 0;
    w.world_epoch = f.world_epoch;
    if (w.moving) evaluate_frame(e.scene, f.world, f.time, w.frame);
    w.frame.instances = f.instances;
    w.frame_serial = f.serial;
  }
  const History history = w.history();
  // Consecutive pixels of a tile row as batches; the frame's world stays at one instant.
  PacketBatch b;
  for (size_t i = begin; i < end;) {  // in conventional mode slot i holds job_pixels[i]
    const size_t first = i;
    for (b.n = 0; b.n < PacketBatch::kMax && i < end; ++b.n, ++i) {
      b.idx[b.n] = e.job_pixels[i];
      b.state[b.n] = &e.states[i];
      b.t[b.n] = t_begin + dt * double(i - begin);
      b.frame[b.n] = frame ? &frame[e.job_pixels[i]] : nullptr;
    }
    trace_batch(e, b, f.basis, w.moving ? &w.frame : nullptr, nullptr);
    for (int k = 0; k < b.n; ++k)
      finish_update(e, b.idx[k], *b.state[k], f.epoch, float(b.t[k]), ctr, b.frame[k], history, b.r[k]);
    if (out)  // this thread wrote the states: relaxed reads are exact
      for (int k = 0; k < b.n; ++k) out[first + size_t(k) - begin] = record_of(e, *b.state[k], b.idx[k]);
  }
  ctr.updates.store(ctr.updates.load(std::memory_order_relaxed) + (end - begin),
                    std::memory_order_release);
}

void render_piece(Engine::Impl& e, int t, PieceJob& job) {
  const FramePiece& p = job.piece;
  // Handed-over states: whoever rendered these pixels last continues here (see PieceJob).
  for (size_t k = 0; k < job.in.size(); ++k) {
    const PixelRecord& r = job.in[k];
    PixelState& s = e.states[p.begin + k];
    s.passes.store(r.passes, std::memory_order_relaxed);
    const uint32_t idx = e.job_pixels[p.begin + k];
    publish_state(s, r.count, r.epoch, r.mean, r.m2, r.sample, r.time,
                  [&] { e.levels[idx].store(r.levels, std::memory_order_relaxed); });
  }
  ThreadCounters& ctr = e.counters[t];
  const uint64_t samples0 = ctr.samples.load(std::memory_order_relaxed);
  const uint64_t dropped0 = ctr.dropped.load(std::memory_order_relaxed);
  job.out.resize(p.end - p.begin);
  conventional_range(e, t, *job.frame, p.begin, p.end, p.t_begin, p.dt, nullptr, job.out.data());
  job.samples = ctr.samples.load(std::memory_order_relaxed) - samples0;
  job.dropped = ctr.dropped.load(std::memory_order_relaxed) - dropped0;
}

void piece_thread_main(Engine::Impl& e, int t) {
  enable_flush_to_zero();
  try {
    const uint64_t cpu0 = thread_cpu_ns();
    std::unique_ptr<PieceJob> job;
    while (e.feed->next(t, job)) {
      render_piece(e, t, *job);
      e.feed->done(t, std::move(job));
      e.counters[t].busy_ns.store(thread_cpu_ns() - cpu0, std::memory_order_relaxed);
    }
  } catch (const std::exception& ex) {
    e.record_error(std::string("render thread ") + std::to_string(t) + ": " + ex.what());
  } catch (...) {
    e.record_error("render thread " + std::to_string(t) + ": unknown exception");
  }
}

void fill_frame(Engine::Impl& e, FrameState& f, uint64_t serial) {
  f.camera = e.channel.read(&f.epoch);
  f.basis = make_camera_basis(f.camera, e.partition.width, e.partition.height);
  f.time = e.now();
  if (e.world_channel.epoch() != f.world_epoch) {
    f.world_epoch = e.world_channel.read(e.frame_world_buf);
    unpack_world(e.frame_world_buf.data(), e.frame_world_buf.size(), f.world);
  }
  e.pick_up_instances(f.instances_epoch, f.instances);
  f.serial = serial;
}

void begin_frame(Engine::Impl& e) {
  e.frame_pos = 0;
  fill_frame(e, e.frame, e.frame.serial + 1);
}

void publish_frame(Engine::Impl& e) {
  const uint32_t old = e.frames.middle.exchange(e.frames.back | FrameBuffers::kNew,
                                                std::memory_order_acq_rel);
  e.frames.back = e.frames.back2;
  e.frames.back2 = old & 3u;
  e.frames.completed.fetch_add(1, std::memory_order_release);
}

namespace {
int64_t steady_ns() {
  return std::chrono::duration_cast<std::chrono::nanoseconds>(std::chrono::steady_clock::now().time_since_epoch()).count();
}
}  // namespace

void Engine::Impl::FrameDone::operator()() noexcept {
  // Runs on one thread once all have arrived: publish the finished frame, start the next.
  const int64_t begin = steady_ns();
  if (!e->barrier_arrive_ns.empty()) {
    // The previous barrier's release: from its completion's end to the last thread leaving.
    if (e->done_end_ns > 0) {
      const int64_t last_leave = *std::max_element(e->barrier_leave_ns.begin(), e->barrier_leave_ns.end());
      const uint64_t release = uint64_t(std::max<int64_t>(0, last_leave - e->done_end_ns));
      e->barrier_frames.fetch_add(1, std::memory_order_relaxed);
      e->barrier_release_sum_ns.fetch_add(release, std::memory_order_relaxed);
      if (release > e->barrier_release_max_ns.load(std::memory_order_relaxed))
        e->barrier_release_max_ns.store(release, std::memory_order_relaxed);
      e->barrier_done_sum_ns.fetch_add(uint64_t(e->done_end_ns - e->done_begin_ns), std::memory_order_relaxed);
    }
    // This barrier's wait for the slowest thread (load imbalance): first arrival to the last.
    const int64_t first = *std::min_element(e->barrier_arrive_ns.begin(), e->barrier_arrive_ns.end());
    e->barrier_wait_sum_ns.fetch_add(uint64_t(std::max<int64_t>(0, begin - first)), std::memory_order_relaxed);
  }
  e->done_begin_ns = begin;
  e->frame_stop = e->stop_flag.load(std::memory_order_relaxed);
  if (!e->frame_stop) {
    publish_frame(*e);
    begin_frame(*e);
  }
  e->next_job.store(0, std::memory_order_relaxed);
  e->done_end_ns = steady_ns();
}

void conventional_thread_main(Engine::Impl& e, int t) {
  enable_flush_to_zero();
  try {
    const uint64_t cpu0 = thread_cpu_ns();
    for (;;) {
      for (;;) {
        const uint32_t j = e.next_job.fetch_add(1, std::memory_order_relaxed);
        if (j >= e.jobs.size()) break;
        if (e.stop_flag.load(std::memory_order_relaxed)) continue;  // drain quickly on stop
        // Job j covers a contiguous range of job_pixels (tiles are laid out in job order).
        const size_t px_begin = e.job_first_pixel[j];
        const size_t px_end = e.job_first_pixel[j + 1];
        conventional_range(e, t, e.frame, px_begin, px_end, e.now(), 0.0,
                           e.frames.buf[e.frames.back].data(), nullptr);
        e.counters[t].busy_ns.store(thread_cpu_ns() - cpu0, std::memory_order_relaxed);  // per job
      }
      e.barrier_arrive_ns[size_t(t)] = steady_ns();
      e.barrier->arrive_and_wait();
      e.barrier_leave_ns[size_t(t)] = steady_ns();
      if (e.frame_stop) break;
    }
  } catch (const std::exception& ex) {
    e.record_error(std::string("render thread ") + std::to_string(t) + ": " + ex.what());
    e.barrier->arrive_and_drop();
  } catch (...) {
    e.record_error("render thread " + std::to_string(t) + ": unknown exception");
    e.barrier->arrive_and_drop();
  }
}

void pool_thread_main(Engine::Impl& e, int t) {
  enable_flush_to_zero();
  uint64_t seen = 0;
  for (;;) {
    std::function<void(int)>* task = nullptr;
    {
      std::unique_lock<std::mutex> lock(e.pool_mutex);
      e.pool_cv.wait(lock, [&] { return e.pool_quit || e.pool_generation != seen; });
      if (e.pool_quit) return;
      seen = e.pool_generation;
      task = &e.pool_task;
    }
    try {
      (*task)(t);
    } catch (const std::exception& ex) {
      e.record_error(std::string("render thread ") + std::to_string(t) + ": " + ex.what());
    } catch (...) {
      e.record_error("render thread " + std::to_string(t) + ": unknown exception");
    }
    std::lock_guard<std::mutex> lock(e.pool_mutex);
    if (--e.pool_pending == 0) e.pool_done_cv.notify_all();
  }
}

}  // namespace frameless
