// Conventional frames rendered across a cluster (src/cluster, OpenRT's distribution): what every
// rank agrees a frame shows, the pieces a frame is cut into, a pixel's whole state (what moves
// with a piece when another rank renders it next), and the queue a client's render threads take
// pieces from.
#pragma once
#include <cstdint>
#include <memory>
#include <vector>

#include "core/accel/instance_top.h"
#include "core/base/types.h"
#include "core/scene/camera.h"
#include "core/scene/dynamic.h"

namespace frameless {

// A conventional frame as the master begins it; a client adds the world and instances its
// channels hold when the spec arrives (the master sends their changes first).
struct FrameSpec {
  uint64_t serial = 0;  // frames begun since start(), from 1
  uint32_t epoch = 0;   // camera epoch
  Camera camera;
  double time = 0.0;    // the instant the frame shows (the master's engine seconds)
};

// What a frame sees of what moves (a master sends the clients the frame's own, not the newest).
struct FrameWorld {
  uint32_t world_epoch = 0;
  WorldState world;
  uint32_t instances_epoch = 1;
  std::shared_ptr<const InstanceTop> instances;  // null: as built
};

// Everything of one pixel's state (PixelState) and its reflection level: whoever renders the
// pixel next continues from exactly this.
struct PixelRecord {
  uint32_t passes = 0, count = 0, epoch = 0;
  double mean[3] = {0.0, 0.0, 0.0};
  double m2 = 0.0;
  Vec3 sample{0.0f};
  float time = 0.0f;
  uint8_t levels = 0;
};

// Slots [begin, end) of a frame in conventional job order (the same make_tile_jobs list on every
// rank); slot i is stamped t_begin + (i - begin) * dt.
struct FramePiece {
  uint64_t serial = 0;
  uint32_t begin = 0, end = 0;
  double t_begin = 0.0, dt = 0.0;
};

struct FrameState;  // a frame as one rank renders it (engine internals)

// One piece on a client: what it renders under, the states it starts from when another rank
// rendered these pixels last (empty: this rank has them), and what it produced.
struct PieceJob {
  uint64_t id = 0;  // the master's handle
  std::shared_ptr<const FrameState> frame;
  FramePiece piece;
  std::vector<PixelRecord> in;   // handed-over states, one per slot, or empty
  std::vector<PixelRecord> out;  // filled by the render thread, one per slot
  uint64_t samples = 0, dropped = 0;  // filled by the render thread
};

// Where a client's render threads take pieces from (the cluster's queue). next() blocks until a
// piece comes and returns false once the feed is closed; the engine calls close() when it stops.
class PieceFeed {
 public:
  virtual ~PieceFeed() = default;
  virtual bool next(int thread, std::unique_ptr<PieceJob>& job) = 0;
  virtual void done(int thread, std::unique_ptr<PieceJob> job) = 0;
  virtual void close() = 0;
};

}  // namespace frameless
