// The closed-loop order for `frameless stats`: a deterministic run with closed-loop sampling on,
// asked for the top half of the image at every display tick (the heaviest steady ask a display
// makes: a region that never stops changing), and the starvation bound checked on its log.
#pragma once
#include <vector>

#include "core/scene/camera.h"
#include "core/scene/scene.h"
#include "frameless/stats_run.h"

namespace frameless {

struct ClosedLoopStats {
  struct Thread {
    size_t pixels = 0;          // list length n
    size_t updates = 0;         // logged updates
    size_t worst_gap = 0;       // longest run of the thread's updates between two of one pixel's
    size_t bound = 0;           // 2 n + 2 run lengths: what the interleaving guarantees
    size_t never_updated = 0;   // pixels of the list with no update at all
    double asked_share = 0;     // fraction of updates spent on asked pixels
  };
  std::vector<Thread> threads;
  double asked_fraction = 0;    // fraction of the image asked for
  double sweeps = 0;            // run length in sweeps of the whole image
  bool bound_holds = true;      // every thread within its bound, every pixel updated
};

// Runs it (flat shader, deterministic); throws std::runtime_error on an engine error.
ClosedLoopStats closed_loop_stats(const Scene& scene, const Camera& camera, const StatsRunConfig& config);

}  // namespace frameless
