// Blender's Cycles (Debian's `blender`, CPU) as the bench-only peer for light that bounces: the
// scene's triangles and diffuse/emissive materials written as a Blender script, rendered headless
// with settings that make Cycles an unbiased path tracer like ours. Control thread only.
#pragma once
#include <string>
#include <vector>

#include "core/base/error.h"
#include "core/scene/scene.h"

namespace frameless::bench {

// The blender executable found on PATH, or "" (the bench then says Cycles is absent).
std::string find_blender();

// Why `scene` cannot be rendered the same way by Cycles ("" when it can): only static triangles,
// diffuse materials (with emission), no Parker lights, no ambient, a constant background.
std::string cycles_unsupported(const Scene& scene);

struct CyclesRender {
  int width = 0, height = 0;
  std::vector<float> rgb;   // 3 floats per pixel, linear, row 0 at the top
  double seconds = 0;       // Cycles' own render time (bpy.ops.render.render), not start-up
  std::string version;      // Blender's version string
};

// Renders `scene` from its camera at width x height with spp samples on `threads` threads;
// work_dir receives the script and the EXR.
Result<CyclesRender> render_with_cycles(const std::string& blender, const Scene& scene, int width,
                                        int height, int spp, int threads, int seed,
                                        const std::string& work_dir);

}  // namespace frameless::bench
