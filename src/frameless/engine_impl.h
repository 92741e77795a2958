// Internal state of Engine shared by engine.cpp (control, exchange) and render_loop.cpp (render
// threads); not a public interface. Ownership per field is noted.
#pragma once
#include <atomic>
#include <barrier>
#include <chrono>
#include <condition_variable>
#include <functional>
#include <memory>
#include <mutex>
#include <thread>

#include "core/scene/dynamic.h"
#include "frameless/adaptive.h"
#include "frameless/camera_channel.h"
#include "frameless/closed_loop.h"
#include "frameless/conventional_jobs.h"
#include "frameless/cpu_clock.h"
#include "frameless/engine.h"
#include "frameless/pixel_points.h"
#include "frameless/remote_frames.h"
#include "frameless/world_channel.h"

namespace frameless {

// Per-thread counters, written by the owner only (relaxed), read by anyone.
struct alignas(64) ThreadCounters {
  std::atomic<uint64_t> updates{0};  // pixel visits since start (drives the display's cursor)
  std::atomic<uint64_t> samples{0};
  std::atomic<uint64_t> dropped{0};
  std::atomic<uint64_t> busy_ns{0};  // the thread's CPU time since start (sampled, not per update)
};

// How a pixel's running statistics treat their history when the world may have changed.
enum class History : uint8_t {
  kStill,     // nothing ever changed but the camera: plain running mean
  kTracked,   // the world changed before: keep the variance the temporal rule will need
  kTemporal,  // the world moves now (or just changed): the temporal rule decides what to keep
};

// A frameless render thread's private walking state (owned by that thread).
struct FramelessWorker {
  int index = 0;
  const std::vector<uint32_t>* pixels = nullptr;  // its pixels in visiting order
  size_t first_slot = 0;       // state of (*pixels)[i] is states[first_slot + i]
  size_t pos = 0;              // next position in *pixels
  size_t chunk_left = 0;       // visits left in the walk's current chunk (0: pos starts one)
  uint64_t updates = 0;        // pixel visits since start
  uint64_t interval = 1;       // visits between camera checks
  uint64_t countdown = 1;      // visits until the next camera check (staggered at start)
  uint64_t budget_done = 0;    // deterministic: cumulative budget consumed
  uint32_t epoch = 0;          // camera epoch in use
  CameraBasis basis;           // camera in use
  UpdateLog* log = nullptr;    // null when logging is off
  AdaptiveWorkerState adaptive;  // adaptive sampling: consecutive skips per list position
  // What moves (core/scene/dynamic.h): the world in use, picked up like the camera, and this thread's
  // frame of it, moved to each sample's instant. `moving` passes the frame to shading at all.
  uint32_t world_epoch = 0;
  WorldState world;
  DynamicFrame frame;
  std::vector<float> world_buf;
  uint64_t frame_serial = ~uint64_t(0);  // conventional: the frame serial `frame` was evaluated for
  uint32_t instances_epoch = 1;          // moved instances in frame.instances (1: as built)
  bool moving = false;
  // After a world change every pixel of the list gets one update under the temporal rule (those
  // whose sample disagrees restart, the rest keep a short history); then the means accumulate
  // again without a cap, so they converge to the changed world. Dynamic objects keep the rule on.
  uint64_t settle_left = 0;
  bool animated = false;  // the scene has dynamic objects: they move with time, always
  History history() const {
    if (animated || settle_left > 0) return History::kTemporal;
    return moving ? History::kTracked : History::kStill;
  }
  // Closed-loop sampling: the runs asked for and not yet rendered, served front to back, and the
  // generation of the display's asks last scanned.
  struct AskedRun {
    uint32_t pos;  // list position of the run's first pixel
    float time;    // engine seconds when it was queued
  };
  std::vector<AskedRun> asked;
  size_t asked_next = 0;
  uint64_t asked_generation = 0;
};

// Conventional frames: render side writes `back`, publishes by exchanging it with `middle`;
// the display takes `middle` into `front`. kNew marks an unconsumed frame. `back2` receives the
// next frame while `back` is still being assembled (a cluster master's asynchronous frames).
struct FrameBuffers {
  static constexpr uint32_t kNew = 4;
  std::vector<PixelSnapshot> buf[4];
  std::atomic<uint32_t> middle{1};
  uint32_t back = 0;   // render side (barrier completion / deterministic coordinator / cluster master)
  uint32_t back2 = 3;  // render side: the next frame's buffer
  uint32_t front = 2;  // display side
  std::atomic<uint64_t> completed{0};
};

// A conventional frame as this rank renders it: one camera, one instant, one world.
struct FrameState {
  uint64_t serial = 0;
  uint32_t epoch = 0;
  Camera camera;
  CameraBasis basis;
  double time = 0.0;
  uint32_t world_epoch = 0;
  WorldState world;
  uint32_t instances_epoch = 1;
  std::shared_ptr<const InstanceTop> instances;  // moved instances (null: as built)
};

struct Engine::Impl {
  struct FrameDone {
    Impl* e;
    void operator()() noexcept;
  };

  Impl(const Scene& s, const EngineConfig& c, const Camera& camera)
      : scene(s), cfg(c), channel(camera), world_channel(initial_world_floats(s)) {}
  // The newest moved top into `top` when its epoch differs from `epoch`; true when picked up.
  bool pick_up_instances(uint32_t& epoch, std::shared_ptr<const InstanceTop>& top) const {
    if (instances_epoch.load(std::memory_order_acquire) == epoch) return false;
    std::lock_guard<std::mutex> lock(instances_mutex);
    top = instances;
    epoch = instances_epoch.load(std::memory_order_relaxed);
    return true;
  }
  static std::vector<float> initial_world_floats(const Scene& s) {
    std::vector<float> v;
    pack_world(initial_world(s), v);
    return v;
  }

  const Scene& scene;
  EngineConfig cfg;          // control thread; read-only for render threads while they run
  CameraChannel channel;
  WorldChannel world_channel;  // dynamic objects, lights, materials (application side publishes)
  // Moved instances: the newest top level (null until the first move) and its epoch (1: as
  // built). The mutex guards the pointer while it is copied, at a pick-up (update percentage or
  // frame start), never per sample; publishers hold instances_publish across their whole update.
  mutable std::mutex instances_mutex;
  std::shared_ptr<const InstanceTop> instances;
  std::atomic<uint32_t> instances_epoch{1};
  std::mutex instances_publish;
  uint64_t sample_seed_base = 0;  // scene seed mixed with cfg.seed

  // Layout (rebuilt by the control thread while render threads are stopped).
  Partition partition;
  // Pixel states are stored in the order their owner visits them (frameless: thread by thread
  // along each partition list; conventional: job order), so the render threads and the display
  // walk memory sequentially instead of jumping between scattered chunks. Pixel p lives in
  // states[slot_of[p]].
  std::unique_ptr<PixelState[]> states;
  // Deepest reflection/refraction level of each pixel's newest update, by pixel (y * width + x),
  // beside the states because PixelState fills its cache line; frameless/pixel_levels.h.
  std::unique_ptr<std::atomic<uint8_t>[]> levels;
  // Primary hit of each pixel's newest update, by pixel like the levels: what the display's
  // reprojection moves (frameless/pixel_points.h).
  std::unique_ptr<PixelPoint[]> points;
  // igi only (else null): each pixel's mean indirect light, by pixel (frameless/pixel_points.h).
  std::unique_ptr<PixelIndirect[]> indirect;
  std::vector<uint32_t> slot_of;
  std::vector<size_t> thread_first_slot;  // frameless: first slot of each thread's list
  // Frameless: the pixel each slot holds, shared with the display (immutable once built); null
  // in conventional mode.
  std::shared_ptr<const std::vector<uint32_t>> display_order;
  uint64_t cleared = 0;  // layouts built with cleared pixel states (guarded by layout_mutex)
  size_t pixel_count = 0;
  int threads = 1;
  std::unique_ptr<ThreadCounters[]> counters;
  // Closed-loop sampling (null/empty when off): the display's asks by run of slots, and each
  // render thread's announcements of the runs it rendered out of walk order.
  WantedRuns wanted;
  std::unique_ptr<PriorityRing[]> priority_rings;
  std::vector<UpdateLog> logs;
  std::vector<FramelessWorker> workers;
  std::vector<TileJob> jobs;
  std::vector<uint32_t> job_pixels;
  std::vector<size_t> job_first_pixel;  // job j renders job_pixels[first[j], first[j + 1])
  FrameBuffers frames;

  // Conventional frame state: written in the barrier completion, read after the barrier (a
  // cluster master: by its communication thread, or the control thread in deterministic mode).
  std::atomic<uint32_t> next_job{0};
  FrameState frame;       // the frame being rendered (or assembled)
  FrameState next_frame;  // cluster master: the next frame, once begun (next_begun)
  bool next_begun = false;
  std::vector<float> frame_world_buf;
  PieceFeed* feed = nullptr;  // cluster client: where the render threads take pieces from
  bool frame_stop = false;
  size_t frame_pos = 0;  // deterministic: pixels of the current frame already rendered
  std::unique_ptr<std::barrier<FrameDone>> barrier;
  // The barrier's own cost (Parker et al. section 2.1): per thread, when it arrived and when it
  // left (its slot written by it alone, read in the next completion: the barrier orders them);
  // the completion's start and end; per frame, the time from the completion's end to the last
  // thread leaving (the release), summed by the completion (atomics: stats() reads them).
  std::vector<int64_t> barrier_arrive_ns, barrier_leave_ns;
  int64_t done_begin_ns = 0, done_end_ns = 0;
  std::atomic<uint64_t> barrier_frames{0}, barrier_release_sum_ns{0}, barrier_release_max_ns{0},
      barrier_done_sum_ns{0}, barrier_wait_sum_ns{0};

  // Control.
  std::mutex layout_mutex;  // held by control while rebuilding or changing cfg, by the display while collecting, by stats()
  std::atomic<uint64_t> generation{0};
  std::vector<std::thread> thread_handles;
  bool running = false;
  std::atomic<bool> stop_flag{false};
  std::chrono::steady_clock::time_point t0 = std::chrono::steady_clock::now();
  std::atomic<double> start_time{0.0};
  std::atomic<double> virtual_time{0.0};
  std::atomic<uint64_t> ticks{0};
  std::atomic<uint32_t> display_tick{0};
  mutable std::mutex error_mutex;
  std::optional<std::string> error;

  // Deterministic worker pool.
  std::mutex pool_mutex;
  std::condition_variable pool_cv, pool_done_cv;
  uint64_t pool_generation = 0;
  int pool_pending = 0;
  bool pool_quit = false;
  std::function<void(int)> pool_task;
  std::function<void(uint64_t, double)> remote_advance;  // cluster master (Engine::set_remote_advance)
  std::function<void(const FrameSpec&, const FramePiece&)> remote_pieces;  // (Engine::set_remote_pieces)

  double now() const {
    if (cfg.deterministic) return virtual_time.load(std::memory_order_relaxed);
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  }
  void record_error(const std::string& message);
};

// render_loop.cpp
void frameless_thread_main(Engine::Impl& e, int t);
void conventional_thread_main(Engine::Impl& e, int t);
void pool_thread_main(Engine::Impl& e, int t);
// Deterministic: `count` visits of worker w, visit i stamped with time t_begin + i * dt.
void frameless_run(Engine::Impl& e, FramelessWorker& w, uint64_t count, double t_begin, double dt);
void piece_thread_main(Engine::Impl& e, int t);
// Renders job_pixels[begin, end) of frame `f` on render thread t (conventional mode), into the
// frame buffer `frame` (by pixel; null: none) and whole-state records `out` (by slot - begin;
// null: none).
void conventional_range(Engine::Impl& e, int t, const FrameState& f, size_t begin, size_t end,
                        double t_begin, double dt, PixelSnapshot* frame, PixelRecord* out);
// Renders one piece handed over by a cluster feed (its handed-over states first).
void render_piece(Engine::Impl& e, int t, PieceJob& job);
// Fills `f` with the newest camera, world and instances and the engine's instant.
void fill_frame(Engine::Impl& e, FrameState& f, uint64_t serial);
// The whole state of pixel `idx` held in `p` (relaxed loads: for the states' one writer).
inline PixelRecord record_of(const Engine::Impl& e, const PixelState& p, uint32_t idx) {
  constexpr auto r = std::memory_order_relaxed;
  PixelRecord o;
  o.passes = p.passes.load(r);
  o.count = p.count.load(r);
  o.epoch = p.epoch.load(r);
  for (int c = 0; c < 3; ++c) o.mean[c] = p.mean[c].load(r), o.sample[c] = p.sample[c].load(r);
  o.m2 = p.m2.load(r);
  o.time = p.time.load(r);
  o.levels = e.levels[idx].load(r);
  return o;
}
inline FrameSpec spec_of(const FrameState& f) { return FrameSpec{f.serial, f.epoch, f.camera, f.time}; }
// Reads the newest camera into the frame state (conventional mode, between frames).
void begin_frame(Engine::Impl& e);
// Publishes the back frame buffer (conventional mode, after a complete frame).
void publish_frame(Engine::Impl& e);

}  // namespace frameless
