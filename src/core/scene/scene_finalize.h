// Finalizing a loaded scene (loading thread): analyse its features, build what soft shadows need
// and its acceleration structure; and the command line's later changes to those settings.
#pragma once
#include "core/accel/accel_types.h"
#include "core/scene/scene.h"

namespace frameless {

// Builds the acceleration structure (of kind scene.settings.accel) and analyses features. Call
// once after loading. config supplies the build parameters; its kind is ignored. A config
// without an executor builds through the default one below.
void finalize_scene(Scene& scene, const AccelConfig& config = {});

// The executor scene builds fan out through when their config brings none (empty: serial, the
// default). The core owns no threads: the application sets one at start-up
// (frameless/thread_executor.h), so that loading a big mesh builds on every core. Any thread.
void set_default_build_executor(ParallelFor executor);
ParallelFor default_build_executor();

// Sets the flags of what rays composite on their way (see-through volumes, lightfields) from the
// scene's volumes and lightfields; finalize_scene calls it, and so may code that adds
// lightfields to a finalized scene (nothing else depends on them).
void refresh_see_through(Scene& scene);

// Rebuilds a finalized scene's acceleration structure as `kind` (command-line --accel).
void set_accel(Scene& scene, AccelKind kind, const AccelConfig& config = {});

// Changes the shadow settings of a finalized scene (command-line overrides): re-analyses its
// features and builds the edge adjacency soft shadows need, without rebuilding the BVH.
void set_shadow_settings(Scene& scene, ShadowMode mode, int samples, bool transparent);

}  // namespace frameless
