// The frameless engine: owns the render threads, their pixels and the camera channel. Control
// methods run on one control thread; collect() on the display thread; render threads
// are internal. The destructor stops and joins every thread (RAII).
#pragma once
#include <atomic>
#include <functional>
#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "core/accel/instance_top.h"
#include "core/scene/camera.h"
#include "core/scene/dynamic.h"
#include "core/scene/scene.h"
#include "frameless/closed_loop.h"
#include "frameless/engine_config.h"
#include "frameless/partition.h"
#include "frameless/pixel_points.h"
#include "frameless/pixel_state.h"
#include "frameless/remote_frames.h"
#include "frameless/update_log.h"

namespace frameless {

// Counters of one render thread (always on; relaxed atomics written by the owner only).
struct ThreadStats {
  uint64_t pixels = 0;        // pixels the thread owns (frameless mode; 0 in conventional)
  uint64_t samples = 0;       // samples traced since start()
  uint64_t updates = 0;       // pixel updates published since start()
  uint64_t dropped = 0;       // samples dropped for NaN/Inf since start()
  double samples_per_s = 0;   // samples / engine seconds since start()
  double busy_seconds = 0;    // the thread's CPU time since start() (updated every ~1000 visits)
};

struct EngineStats {
  std::vector<ThreadStats> threads;  // one per render thread
  uint64_t samples = 0;              // sum over threads
  uint64_t updates = 0;              // sum over threads
  uint64_t dropped = 0;              // sum over threads
  double samples_per_s = 0;          // samples / seconds since start()
  double seconds = 0;                // engine seconds since start() (virtual in deterministic mode)
  uint64_t frames_completed = 0;     // conventional mode: frames finished since start()
  // Conventional mode's frame barrier (Parker et al. section 2.1), per frame: the release (from
  // the barrier's completion to the last thread running again: the synchronisation itself), its
  // mean and worst; the completion's own work (publishing the frame, starting the next); the wait
  // from the first thread's arrival to the last's (load imbalance). Zero in frameless mode.
  uint64_t barrier_frames = 0;
  double barrier_release_mean_us = 0, barrier_release_max_us = 0;
  double barrier_completion_mean_us = 0, barrier_wait_mean_us = 0;
  uint32_t camera_epoch = 0;         // newest published epoch
};

// Display-thread cursor: what it has already seen. Default-constructed = nothing seen.
struct UpdateCursor {
  uint64_t generation = ~uint64_t(0);    // engine layout generation it refers to
  uint64_t cleared = ~uint64_t(0);       // engine pixel-clear count it refers to
  std::vector<uint64_t> thread_updates;  // per render thread: visits already collected
  std::vector<uint64_t> thread_asked;    // per render thread: asked-for runs already collected
  int width = 0;                         // image size it last saw
  int height = 0;
};

// What one collect() call found.
struct CollectResult {
  RenderMode mode = RenderMode::frameless;  // mode the updates come from
  bool reset = false;        // pixel states were cleared (resize, restart): clear the image
  bool resync = false;       // new layout generation: every slot is offered again
  int width = 0;             // current image size
  int height = 0;
  // Frameless: the pixel (y * width + x) each slot holds, in slot order; null in conventional
  // mode, where frames come in pixel order. Shared and immutable: compare pointers to spot a change.
  std::shared_ptr<const std::vector<uint32_t>> slot_pixel;
  // Deepest reflection/refraction level of each pixel's newest update, by pixel (y * width + x),
  // written by the render threads after the state (relaxed): valid until collect() returns.
  const std::atomic<uint8_t>* levels = nullptr;
  // Primary hit of each pixel's newest update, by pixel, written like the levels (null before
  // the first layout): what reprojection moves (frameless/pixel_points.h).
  const PixelPoint* points = nullptr;
  // igi (else null): each pixel's mean indirect light, by pixel, written like the points; and
  // the interleaving pattern's side n, the window igi's discontinuity buffer filters over.
  const PixelIndirect* indirect = nullptr;
  int interleave = 0;
  // Closed-loop sampling (EngineConfig::closed_loop, frameless mode; else null): the display asks
  // for runs of slots here, from inside its sink callbacks (frameless/closed_loop.h).
  WantedRuns* wanted = nullptr;
  // Something in the world may move (dynamic objects, moved instances, a changed world): only
  // then are reprojected pixels showing such things stale.
  bool world_moves = false;
  uint32_t newest_epoch = 0; // newest published camera epoch
  uint64_t samples = 0;      // total samples traced since start() (for per-frame differences)
  uint64_t dropped = 0;      // total samples dropped for NaN/Inf since start()
  double time = 0;           // engine seconds at collection (virtual in deterministic mode)
  bool new_frame = false;    // conventional: a newly completed frame was collected
};

// Receives what Engine::collect() finds, on the display thread, while the layout is locked
// (so the state pointers stay valid). begin() comes first, then slots() or frame().
class UpdateSink {
 public:
  virtual ~UpdateSink() = default;
  // Size, mode, slot order and reset flags of this collection (new_frame not yet known).
  virtual void begin(const CollectResult& result) = 0;
  // Frameless: slots [first, first + count) may have changed since the cursor; states[i] is slot
  // first + i. Read each with read_pixel(); an unchanged seq (or epoch 0) means nothing new.
  virtual void slots(size_t first, const PixelState* states, size_t count) = 0;
  // Conventional: a newly completed frame, in pixel order (epoch 0: never rendered).
  virtual void frame(const std::vector<PixelSnapshot>& pixels) = 0;
};

// One remote render thread's news for a cluster master (src/cluster): its cumulative counters
// and the newest published state of every slot it changed since its previous batch.
struct RemoteSlot {
  uint32_t slot = 0;    // slot index (frameless: a position in the thread's list, offset)
  PixelSnapshot state;  // as read_pixel() gave it on the rendering process, levels included
};
struct RemoteBatch {
  int thread = 0;  // render thread index in the whole cluster's partition
  uint64_t updates = 0, samples = 0, dropped = 0, busy_ns = 0;  // ThreadCounters, cumulative
  std::vector<RemoteSlot> slots;
};

class Engine {
 public:
  // `scene` must be finalized and outlive the engine. The initial camera is `camera`.
  Engine(const Scene& scene, const EngineConfig& config, const Camera& camera);
  ~Engine();
  Engine(const Engine&) = delete;
  Engine& operator=(const Engine&) = delete;

  // Starts the render threads (wall clock) or the idle worker pool (deterministic). Idempotent.
  void start();
  // Stops and joins all render threads. Idempotent; also called by the destructor.
  void stop();
  bool running() const;

  // Publishes a new camera without blocking; returns its epoch. Any thread.
  uint32_t publish_camera(const Camera& camera);
  // A cluster client mirrors its master's camera under the master's epoch (0 and no change
  // unless epoch > camera_epoch()). Any thread.
  uint32_t publish_camera_as(const Camera& camera, uint32_t epoch);
  uint32_t camera_epoch() const;  // newest epoch; any thread
  Camera camera() const;          // newest camera; any thread
  Camera camera(uint32_t* epoch) const;  // newest camera and its epoch, read together; any thread
  // What moves while you look (core/scene/dynamic.h): publishes where the dynamic objects sit (their
  // own motion adds to that), the lights and the material parameters, without blocking; render
  // threads pick it up at the update percentage, like the camera. Throws std::invalid_argument
  // when the counts differ from the scene's or a value is not finite. Any thread.
  uint32_t publish_world(const WorldState& world);
  uint32_t world_epoch() const;  // 1 until the first publish; any thread
  WorldState world() const;      // newest published world; any thread
  // Instances moved while you look (OpenRT; core/accel/instance_top.h): applies the moves (declared
  // instance index, new world transform: only what changed) to the newest top level on the
  // caller's thread (copied, then refit or rebuilt; the shared meshes are never touched) and
  // publishes it; render threads pick it up at the update percentage, like the camera. Returns
  // its epoch. Throws std::invalid_argument (one line) for an index out of range or a singular
  // transform. Any thread; publishers are serialised.
  uint32_t move_instances(const std::vector<InstanceMove>& moves, InstanceUpdate* info = nullptr);
  // Moves the scene's animated instances (Scene::instance_motions) to engine time t; 0 (nothing
  // published) when the scene has none.
  uint32_t animate_instances(double t, InstanceUpdate* info = nullptr);
  uint32_t instances_epoch() const;  // 1 until the first move; any thread
  // Newest top level (null without instances): picking an instance under a ray. Any thread.
  std::shared_ptr<const InstanceTop> instance_top() const;
  // Newest world transform of declared instance i (std::out_of_range past the end). Any thread.
  Affine instance_transform(uint32_t i) const;

  // Runtime changes (control thread). Each stops the threads, rebuilds what it must (resize
  // re-partitions and clears pixel state) and restarts them if they were running.
  void resize(int width, int height);
  void set_mode(RenderMode mode);
  void set_threads(int threads);
  void set_update_percent(double percent);
  void reconfigure(const EngineConfig& config);  // any combination of the above
  EngineConfig config() const;                   // current settings (threads resolved)
  int width() const;
  int height() const;
  int thread_count() const;  // resolved number of render threads
  const Partition& partition() const;  // control thread; valid until the next reconfiguration

  // Deterministic mode (control thread): every render thread renders its share of
  // samples_per_tick, then the virtual clock advances by `tick_seconds`. Returns when all are done.
  void advance(double tick_seconds);
  uint64_t ticks() const;  // advance() calls since start()
  // Cluster master (src/cluster): called inside every advance(), after this process's own
  // threads rendered their share and before the virtual clock moves, with the tick index and its
  // seconds: the other processes render theirs and ingest() it before the display looks.
  // Control thread; set while stopped.
  void set_remote_advance(std::function<void(uint64_t tick, double seconds)> fn);
  // Engine seconds since construction: wall clock, or the virtual clock in deterministic mode.
  double now() const;

  // Display thread: hands `sink` every slot that may have changed since `cursor`, as runs of
  // consecutive slots (so the reader streams through memory), and advances the cursor. In
  // conventional mode it hands over the newest completed frame, once.
  CollectResult collect(UpdateCursor& cursor, UpdateSink& sink);
  // Cluster master (one communication thread): writes the states a remote render thread
  // published into its slots exactly as a local thread would, then its counters, so collect()
  // offers them to the display unchanged. Checked before use: a thread this engine renders
  // itself or out of range, a slot outside the thread's list, an epoch from the future, a
  // non-finite value or falling counters throw std::invalid_argument (one line), and nothing of
  // that batch is written.
  void ingest(const RemoteBatch& batch);

  // Conventional frames across a cluster (src/cluster; frameless/remote_frames.h).
  // Client: its render threads take pieces from `feed` (control thread, while stopped).
  void set_piece_feed(PieceFeed* feed);
  // Client: frame `spec` with this rank's newest world and instances. Any thread.
  std::shared_ptr<const FrameState> remote_frame(const FrameSpec& spec) const;
  // Client, deterministic: the render threads render what the feed hands them until next()
  // returns false; returns when all are done. Control thread.
  void render_feed();
  // Master (its communication thread, or the control thread in deterministic mode): the frame
  // being assembled, and the next one, begun now (newest camera, world, instances, instant)
  // unless it already was (then nullopt). At most two frames are in flight.
  FrameSpec current_frame() const;
  std::optional<FrameSpec> begin_next_frame();
  // Master: the world and instances frame `serial` (current or next) sees; std::out_of_range
  // for another frame.
  FrameWorld frame_world(uint64_t serial) const;
  // Master: writes what a client rendered of a frame in flight (whole states of slots
  // [piece.begin, piece.end), one record each) into the pixel states and that frame's buffer,
  // counting it for render thread `thread`. Checked first (std::invalid_argument, one line,
  // nothing written): mode, thread, frame serial, slot range, epochs, finite values.
  // `busy_ns`: the CPU time of the remote rank's render threads so far (stats; 0: unchanged).
  void ingest_piece(int thread, const FramePiece& piece, const PixelRecord* records,
                    uint64_t samples, uint64_t dropped, uint64_t busy_ns = 0);
  // Master: publishes the current frame (all its pieces ingested); the next becomes current.
  void publish_current_frame();
  // Master: the whole states of slots [begin, end) (handing pixels to another rank).
  void read_records(uint32_t begin, uint32_t end, PixelRecord* out) const;
  // Master, deterministic: called inside advance() for each stretch of a frame the tick covers,
  // before the frame is published; the other ranks render it and ingest_piece() it.
  void set_remote_pieces(std::function<void(const FrameSpec&, const FramePiece&)> fn);
  // Conventional job order: slot i holds pixel job_pixels()[i]; job j covers slots
  // [job_first_slot()[j], job_first_slot()[j + 1]). Control thread; valid until a reconfiguration.
  const std::vector<uint32_t>& job_pixels() const;
  const std::vector<size_t>& job_first_slot() const;

  // Display thread: the display interval index stamped into update-log records.
  void note_display_tick(uint32_t index);

  // Always-on instrumentation; any thread.
  EngineStats stats() const;
  // The first error a render thread hit (it then stopped the engine); empty when none.
  std::optional<std::string> error() const;

  // Update log of render thread `thread` (config.update_log_capacity > 0). Read only while the
  // threads are stopped or between advance() calls in deterministic mode.
  const UpdateLog& update_log(int thread) const;
  // Consistent copy of pixel (x, y)'s state (tests, stats), with its levels; any thread.
  bool read_pixel(int x, int y, PixelSnapshot& out) const;
  // The deepest reflection/refraction level of every pixel's newest update (0: the camera ray
  // alone; saturates at 255), by pixel y * width + x; any thread.
  void copy_levels(std::vector<uint8_t>& out) const;

  struct Impl;

 private:
  std::unique_ptr<Impl> impl_;
};

}  // namespace frameless
