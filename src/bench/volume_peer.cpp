// vdb_render against frameless: one level set (primary hits) and one fog volume (emission-
// absorption), each written by python3-openvdb, read by frameless from the same .vdb file (and the
// level set also from a raw copy), with the same camera; times and the images' agreement.
#include "bench/volume_peer.h"

#include <chrono>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <functional>
#include <thread>

#include "bench/bench_report.h"
#include "core/io/image_io.h"
#include "core/io/scene_json.h"
#include "core/scene/scene_volumes.h"
#include "display/png_io.h"

namespace frameless::bench {
namespace {

// The level set as numpy makes it: distance from the centre minus the radius, clamped to the
// narrow band of 3 voxels (OpenVDB keeps only the voxels that differ from the background 3), x
// fastest on disk (the raw copy) and [x][y][z] for OpenVDB (its index order). The fog: a cloud of
// Gaussian blobs, zero below 0.02 (sparse), a fog volume.
constexpr const char* kScript = R"(import sys, numpy as np, pyopenvdb as vdb
kind, n, r, raw, out = sys.argv[1], int(sys.argv[2]), float(sys.argv[3]), sys.argv[4], sys.argv[5]
c = (n - 1) / 2.0
z, y, x = np.meshgrid(np.arange(n), np.arange(n), np.arange(n), indexing='ij')
if kind == 'sdf':
    d = np.clip(np.sqrt((x - c) ** 2 + (y - c) ** 2 + (z - c) ** 2) - r, -3.0, 3.0).astype(np.float32)
    g = vdb.FloatGrid(background=3.0)
    g.gridClass = vdb.GridClass.LEVEL_SET
else:
    d = np.zeros((n, n, n), np.float32)
    rng = np.random.default_rng(27)
    for i in range(12):
        p = c + (rng.random(3) - 0.5) * 0.9 * r
        s = r * (0.12 + 0.2 * rng.random())
        d += np.exp(-((x - p[0]) ** 2 + (y - p[1]) ** 2 + (z - p[2]) ** 2) / (2 * s * s)).astype(np.float32)
    d = np.where(d < 0.02, 0.0, np.minimum(d, 1.0)).astype(np.float32)
    g = vdb.FloatGrid(background=0.0)
    g.gridClass = vdb.GridClass.FOG_VOLUME
d.tofile(raw)
g.copyFromArray(np.ascontiguousarray(d.transpose(2, 1, 0)))
g.name = kind
vdb.write(out, grids=[g])
lo, hi = g.evalActiveVoxelBoundingBox()
print('bbox', *lo, *hi)
)";

// Seconds to run pixel(x, y) over a w x h image on `threads` (rows dealt round-robin).
double time_pixels(int w, int h, int threads, const std::function<void(int, int)>& pixel) {
  const auto t0 = std::chrono::steady_clock::now();
  std::vector<std::thread> pool;
  for (int t = 0; t < threads; ++t)
    pool.emplace_back([&, t] {
      for (int y = t; y < h; y += threads)
        for (int x = 0; x < w; ++x) pixel(x, y);
    });
  for (std::thread& th : pool) th.join();
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

// Both tools present, and the field written: "" or why the comparison is skipped.
std::string write_field(const std::string& kind, int n, double radius, const std::string& dir,
                        std::string& raw, std::string& vdb, int bbox[6]) {
  std::string out;
  if (run_command("command -v vdb_render", out) != 0)
    return "vdb_render not found (apt-get install libopenvdb-tools)";
  if (run_command("/usr/bin/python3 -c 'import numpy, pyopenvdb'", out) != 0)
    return "Debian's python3-openvdb and python3-numpy are needed to write the volume";
  const std::string script = dir + "/field_to_vdb.py";
  raw = dir + "/" + kind + ".raw", vdb = dir + "/" + kind + ".vdb";
  std::ofstream(script) << kScript;
  char cmd[1024];
  std::snprintf(cmd, sizeof cmd, "/usr/bin/python3 %s %s %d %g %s %s", script.c_str(), kind.c_str(),
                n, radius, raw.c_str(), vdb.c_str());
  if (run_command(cmd, out) != 0) return "writing the volume failed: " + out.substr(0, 200);
  const size_t at = out.find("bbox ");
  if (at == std::string::npos || std::sscanf(out.c_str() + at, "bbox %d %d %d %d %d %d", &bbox[0], &bbox[1], &bbox[2],
                                             &bbox[3], &bbox[4], &bbox[5]) != 6)
    return "the volume's bounding box was not printed";
  return "";
}

// vdb_render's time for the render alone ("ray-tracing ... completed in X sec"), or a negative
// value.
double render_with_vdb_render(const std::string& args, std::string& out) {
  if (run_command("vdb_render " + args + " -compression none -v", out) != 0) return -1.0;
  const size_t at = out.find("ray-tracing");
  const size_t done = at == std::string::npos ? at : out.find("completed in", at);
  return done == std::string::npos ? -1.0 : std::atof(out.c_str() + done + 12);
}

// "{" and the camera of both comparisons (on +z, looking at the centre).
std::string scene_start(double c, double eye_z) {
  char s[256];
  std::snprintf(s, sizeof s, R"({"camera": {"eye": [%g, %g, %g], "look": [%g, %g, %g], "fov": 40})",
                c, c, eye_z, c, c, c);
  return s;
}

}  // namespace

nlohmann::json compare_with_vdb_render(int n, int w, int h, int threads, const std::string& dir) {
  const double radius = 0.3 * (n - 1), c = 0.5 * (n - 1), eye_z = c + 4.0 * radius;
  std::string raw, vdb, out;
  int box[6];
  if (std::string why = write_field("sdf", n, radius, dir, raw, vdb, box); !why.empty()) return {{"skipped", why}};
  const Vec3 box_lo{float(box[0]), float(box[1]), float(box[2])};
  const Vec3 box_size = Vec3(float(box[3]), float(box[4]), float(box[5])) - box_lo;
  // The same camera: on +z, four radii from the centre, looking at it, 40 degrees (square image:
  // vdb_render's horizontal field of view is ours, vertical).
  const std::string exr = dir + "/vdb_position.exr";
  char args[1024];
  std::snprintf(args, sizeof args,
                "%s %s -res %dx%d -translate %g,%g,%g -lookat %g,%g,%g -up 0,1,0 -fov 40 -shader "
                "position -cpus %d",
                vdb.c_str(), exr.c_str(), w, h, c, c, eye_z, c, c, c, threads);
  const double vdb_seconds = render_with_vdb_render(args, out);
  if (vdb_seconds <= 0.0)
    return {{"skipped", "vdb_render failed or printed no time: " + out.substr(0, 200)}};
  auto img = load_image(exr);
  if (!img || (*img)->width != w || (*img)->height != h || (*img)->hdr.empty())
    return {{"skipped", "vdb_render's image could not be read back"}};
  const Image& im = **img;
  nlohmann::json j;
  char grid[96];
  std::snprintf(grid, sizeof grid, "%d^3 sphere level set, radius %.1f voxels", n, radius);
  j["grid"] = grid;
  j["vdb_render_seconds"] = vdb_seconds;
  j["vdb_render_rays_per_s"] = double(w) * h / vdb_seconds;
  // frameless: the isosurface at 0 (inside below), primary hits on `threads`, from the raw copy
  // (a dense grid) and from the .vdb itself (bricked).
  for (const bool from_vdb : {false, true}) {
    char object[512];
    if (from_vdb)
      std::snprintf(object, sizeof object, R"({"type": "volume", "file": "%s", "material": "m"})",
                    vdb.c_str());
    else
      std::snprintf(
          object, sizeof object,
          R"({"type": "volume", "file": "%s", "dims": [%d, %d, %d], "format": "float32", "isovalue": 0,
                        "inside": "below", "material": "m"})",
          raw.c_str(), n, n, n);
    auto s = parse_scene_json(scene_start(c, eye_z) +
                                  R"(, "materials": {"m": {"class": "diffuse"}}, "objects": [)" +
                                  object + "]}",
                              dir + "/sdf.json", dir);
    if (!s) return {{"skipped", s.error().message}};
    const CameraBasis cam = make_camera_basis((*s)->camera, w, h);
    std::vector<Vec3> ours(size_t(w) * h, Vec3(kInfinity));
    const double seconds = time_pixels(w, h, threads, [&](int x, int y) {
      const Ray r = camera_ray(cam, float(x) + 0.5f, float(y) + 0.5f);
      Hit hit;
      if (merge_volume_hits(**s, r, hit)) ours[size_t(y) * w + x] = r.org + hit.t * r.dir;
    });
    // Agreement: pixels both hit, and the distance between the two hit points there.
    size_t both = 0, only_one = 0, within = 0;
    double worst = 0.0, sum = 0.0;
    for (size_t i = 0; i < ours.size(); ++i) {
      const float* q = &im.hdr[i * size_t(im.channels)];
      const bool theirs =
          !(q[0] == 0.0f && q[1] == 0.0f && q[2] == 0.0f);  // the background is black
      const bool mine = ours[i].x < kInfinity;
      if (theirs != mine) {
        ++only_one;
        continue;
      }
      if (!mine) continue;
      // vdb_render's position shader writes the point relative to the level set's bounding box
      // of active voxels: back to index (= world) units.
      const double d = glm::length(ours[i] - (box_lo + box_size * Vec3(q[0], q[1], q[2])));
      ++both;
      within += d <= 1.0;
      worst = std::max(worst, d);
      sum += d;
    }
    const std::string key = from_vdb ? "frameless_vdb" : "frameless";
    j[key + "_seconds"] = seconds;
    j[key + "_rays_per_s"] = double(w) * h / seconds;
    j[key + "_over_vdb_render_speed"] = vdb_seconds / seconds;
    j[key + "_grid_bytes"] = (*s)->volumes[0].grid->bytes();
    j[key + "_pixels_hit_by_both"] = both;
    j[key + "_pixels_hit_by_one"] = only_one;
    j[key + "_hits_within_one_voxel"] = both ? double(within) / double(both) : 0.0;
    j[key + "_mean_distance_voxels"] = both ? sum / double(both) : 0.0;
    j[key + "_max_distance_voxels"] = worst;
  }
  return j;
}

nlohmann::json compare_fog_with_vdb_render(int n, int w, int h, int threads,
                                           const std::string& dir) {
  const double radius = 0.45 * (n - 1), c = 0.5 * (n - 1), eye_z = c + 3.0 * radius;
  std::string raw, vdb, out;
  int box[6];
  if (std::string why = write_field("fog", n, radius, dir, raw, vdb, box); !why.empty()) return {{"skipped", why}};
  // Extinction sigma = 0.1 per voxel at density 1, steps of one voxel, no scattering; vdb_render's
  // shadow rays cut to one step (a step longer than the grid), as it always casts them.
  constexpr double kSigma = 0.1;
  const std::string exr = dir + "/vdb_fog.exr";
  char args[1024];
  std::snprintf(args, sizeof args,
                "%s %s -res %dx%d -translate %g,%g,%g -lookat %g,%g,%g -up 0,1,0 -fov 40 -absorb "
                "%g,%g,%g -scatter 0,0,0 "
                "-step 1 -shadowstep %d -cutoff 0.001 -cpus %d",
                vdb.c_str(), exr.c_str(), w, h, c, c, eye_z, c, c, c, kSigma, kSigma, kSigma, 4 * n,
                threads);
  const double vdb_seconds = render_with_vdb_render(args, out);
  if (vdb_seconds <= 0.0)
    return {{"skipped", "vdb_render failed or printed no time: " + out.substr(0, 200)}};
  auto img = load_image(exr);
  if (!img || (*img)->width != w || (*img)->height != h || (*img)->channels < 4)
    return {{"skipped", "vdb_render's image (RGBA) could not be read back"}};
  // frameless: the volume shader, unlit, opacity per voxel 1 - exp(-sigma v) (17 points), rate 1,
  // every sample taken (no adaptive sampling: the same samples as vdb_render's).
  std::string points;
  for (int i = 0; i <= 16; ++i) {
    char p[96];
    std::snprintf(p, sizeof p, R"(%s{"value": %g, "opacity": %.6f})", i ? ", " : "", i / 16.0,
                  1.0 - std::exp(-kSigma * i / 16.0));
    points += p;
  }
  auto s = parse_scene_json(
      scene_start(c, eye_z) + R"(, "objects": [{"type": "volume", "file": ")" + vdb +
          R"(", "mode": "direct", "shade": false, "adaptive": false, "sampling_rate": 1, "transfer": [)" + points +
          "]}]}",
      dir + "/fog.json", dir);
  if (!s) return {{"skipped", s.error().message}};
  const VolumeObject& v = (*s)->volumes[0];
  const MarchSetup setup = v.march();
  const CameraBasis cam = make_camera_basis((*s)->camera, w, h);
  std::vector<float> alpha(size_t(w) * h);
  std::vector<uint64_t> samples(static_cast<size_t>(h));
  const double seconds = time_pixels(w, h, threads, [&](int x, int y) {
    const Ray r = camera_ray(cam, float(x) + 0.5f, float(y) + 0.5f);
    const VolumeSegment seg = march_volume(setup, v.to_index.point(r.org), v.to_index.vector(r.dir),
                                           0.0f, kInfinity, nullptr);
    alpha[size_t(y) * w + x] = 1.0f - seg.transmittance;
    samples[size_t(y)] += seg.samples;
  });
  double diff = 0.0, worst = 0.0, covered = 0.0;
  uint64_t total = 0;
  for (uint64_t k : samples) total += k;
  for (size_t i = 0; i < alpha.size(); ++i) {
    const double a = (*img)->hdr[i * size_t((*img)->channels) + 3];
    diff += std::abs(a - alpha[i]);
    worst = std::max(worst, std::abs(a - alpha[i]));
    covered += a;
  }
  // The two alpha images side by side (vdb_render left), to look at.
  std::vector<float> pair(size_t(2 * w) * h * 3);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x)
      for (int k = 0; k < 3; ++k) {
        pair[(size_t(y) * 2 * w + x) * 3 + k] = (*img)->hdr[(size_t(y) * w + x) * size_t((*img)->channels) + 3];
        pair[(size_t(y) * 2 * w + w + x) * 3 + k] = alpha[size_t(y) * w + x];
      }
  const std::string picture = dir + "/fog_alpha_vdb_render_left_frameless_right.png";
  if (!write_png(picture, 2 * w, h, pair.data())) return {{"skipped", "cannot write " + picture}};
  char grid[128];
  std::snprintf(grid, sizeof grid,
                "%d^3 fog volume (12 Gaussian blobs, %.0f %% of the image covered)", n,
                100.0 * covered / double(alpha.size()));
  return {{"grid", grid},
          {"grid_bytes", v.grid->bytes()},
          {"vdb_render_seconds", vdb_seconds},
          {"frameless_seconds", seconds},
          {"frameless_over_vdb_render_speed", vdb_seconds / seconds},
          {"frameless_samples", total},
          {"frameless_samples_per_s", double(total) / seconds},
          {"vdb_render_samples_per_s_same_count", double(total) / vdb_seconds},
          {"mean_alpha_difference", diff / double(alpha.size())},
          {"max_alpha_difference", worst},
          {"picture", picture}};
}

}  // namespace frameless::bench
