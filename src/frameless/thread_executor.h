// An executor for the core's parallel loops (core/base/parallel_for.h) on threads of its own, for
// work that runs while nothing else does (a scene's BVH build at load, a volume's generation).
#pragma once
#include "core/base/parallel_for.h"

namespace frameless {

// Runs body(i) for every i in [0, n) on up to `threads` threads per call (the caller and
// threads - 1 new ones, joined before it returns), each taking the next index in turn.
// threads <= 0: one per hardware thread.
ParallelFor thread_executor(int threads);

}  // namespace frameless
