// vdb_render against frameless on one level set: files, the two renders, their agreement.
#include "bench/volume_peer.h"

#include <chrono>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <thread>

#include "bench/bench_report.h"
#include "core/io/image_io.h"
#include "core/io/scene_json.h"
#include "core/scene/scene_volumes.h"

namespace frameless::bench {
namespace {

// The field as numpy makes it: distance from the centre minus the radius, x fastest on disk (ours)
// and [x][y][z] for OpenVDB (its index order); a narrow-band level set of 3 voxels' background.
constexpr const char* kScript = R"(import sys, numpy as np, pyopenvdb as vdb
n, r, raw, out = int(sys.argv[1]), float(sys.argv[2]), sys.argv[3], sys.argv[4]
c = (n - 1) / 2.0
z, y, x = np.meshgrid(np.arange(n), np.arange(n), np.arange(n), indexing='ij')
d = (np.sqrt((x - c) ** 2 + (y - c) ** 2 + (z - c) ** 2) - r).astype(np.float32)
d.tofile(raw)
g = vdb.FloatGrid(background=3.0)
g.copyFromArray(np.ascontiguousarray(d.transpose(2, 1, 0)))
g.gridClass = vdb.GridClass.LEVEL_SET
g.name = 'sdf'
vdb.write(out, grids=[g])
)";

}  // namespace

nlohmann::json compare_with_vdb_render(int n, int w, int h, int threads, const std::string& dir) {
  nlohmann::json j;
  std::string out;
  if (run_command("command -v vdb_render", out) != 0) return {{"skipped", "vdb_render not found (apt-get install libopenvdb-tools)"}};
  if (run_command("/usr/bin/python3 -c 'import numpy, pyopenvdb'", out) != 0)
    return {{"skipped", "Debian's python3-openvdb and python3-numpy are needed to write the level set"}};
  const std::string script = dir + "/sdf_to_vdb.py", raw = dir + "/sdf.raw", vdb = dir + "/sdf.vdb", exr = dir + "/vdb_position.exr";
  std::ofstream(script) << kScript;
  const double radius = 0.3 * (n - 1), c = 0.5 * (n - 1);
  char cmd[1024];
  std::snprintf(cmd, sizeof cmd, "/usr/bin/python3 %s %d %g %s %s", script.c_str(), n, radius, raw.c_str(), vdb.c_str());
  if (run_command(cmd, out) != 0) return {{"skipped", "writing the level set failed: " + out.substr(0, 200)}};
  // The same camera: on +z, four radii from the centre, looking at it, 40 degrees (square image: vdb_render's
  // horizontal field of view is ours, vertical).
  const double eye_z = c + 4.0 * radius;
  std::snprintf(cmd, sizeof cmd,
                "vdb_render %s %s -res %dx%d -translate %g,%g,%g -lookat %g,%g,%g -up 0,1,0 -fov 40 -shader position "
                "-compression none -cpus %d -v",
                vdb.c_str(), exr.c_str(), w, h, c, c, eye_z, c, c, c, threads);
  if (run_command(cmd, out) != 0) return {{"skipped", "vdb_render failed: " + out.substr(0, 200)}};
  // "ray-tracing sdf...\n...completed in X sec": the render alone, not reading or writing.
  const size_t at = out.find("ray-tracing");
  const size_t done = at == std::string::npos ? at : out.find("completed in", at);
  if (done == std::string::npos) return {{"skipped", "vdb_render printed no render time"}};
  const double vdb_seconds = std::atof(out.c_str() + done + 12);
  // frameless: the raw grid as an isosurface at 0 (inside below), primary hits on `threads`.
  char scene[1024];
  std::snprintf(scene, sizeof scene,
                R"({"camera": {"eye": [%g, %g, %g], "look": [%g, %g, %g], "fov": 40},
      "materials": {"m": {"class": "diffuse"}},
      "objects": [{"type": "volume", "file": "%s", "dims": [%d, %d, %d], "format": "float32",
                   "isovalue": 0, "inside": "below", "material": "m"}]})",
                c, c, eye_z, c, c, c, raw.c_str(), n, n, n);
  auto s = parse_scene_json(scene, dir + "/sdf.json", dir);
  if (!s) return {{"skipped", s.error().message}};
  const CameraBasis cam = make_camera_basis((*s)->camera, w, h);
  std::vector<Vec3> ours(size_t(w) * h, Vec3(kInfinity));
  const auto t0 = std::chrono::steady_clock::now();
  std::vector<std::thread> pool;
  for (int t = 0; t < threads; ++t)
    pool.emplace_back([&, t] {
      for (int y = t; y < h; y += threads)
        for (int x = 0; x < w; ++x) {
          const Ray r = camera_ray(cam, float(x) + 0.5f, float(y) + 0.5f);
          Hit hit;
          if (merge_volume_hits(**s, r, hit)) ours[size_t(y) * w + x] = r.org + hit.t * r.dir;
        }
    });
  for (std::thread& th : pool) th.join();
  const double our_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  // Agreement: pixels both hit, and the distance between the two hit points there.
  auto img = load_image(exr);
  if (!img || (*img)->width != w || (*img)->height != h || (*img)->hdr.empty())
    return {{"skipped", "vdb_render's image could not be read back"}};
  const Image& im = **img;
  size_t both = 0, only_one = 0, within = 0;
  double worst = 0.0, sum = 0.0;
  for (size_t i = 0; i < ours.size(); ++i) {
    const float* q = &im.hdr[i * size_t(im.channels)];
    const bool theirs = !(q[0] == 0.0f && q[1] == 0.0f && q[2] == 0.0f);  // the background is black
    const bool mine = ours[i].x < kInfinity;
    if (theirs != mine) {
      ++only_one;
      continue;
    }
    if (!mine) continue;
    // vdb_render's position shader writes the point relative to the grid's active bounding box
    // ([0, n - 1] on every axis here, all voxels active): back to index (= world) units.
    const double d = glm::length(ours[i] - float(n - 1) * Vec3(q[0], q[1], q[2]));
    ++both;
    within += d <= 1.0;
    worst = std::max(worst, d);
    sum += d;
  }
  char grid[96];
  std::snprintf(grid, sizeof grid, "%d^3 sphere distance field, radius %.1f voxels", n, radius);
  j["grid"] = grid;
  j["vdb_render_seconds"] = vdb_seconds;
  j["frameless_seconds"] = our_seconds;
  j["vdb_render_rays_per_s"] = double(w) * h / vdb_seconds;
  j["frameless_rays_per_s"] = double(w) * h / our_seconds;
  j["frameless_over_vdb_render_speed"] = vdb_seconds / our_seconds;
  j["pixels_hit_by_both"] = both;
  j["pixels_hit_by_one"] = only_one;
  j["hits_within_one_voxel"] = both ? double(within) / double(both) : 0.0;
  j["mean_distance_voxels"] = both ? sum / double(both) : 0.0;
  j["max_distance_voxels"] = worst;
  return j;
}

}  // namespace frameless::bench
