// `frameless bench volume`: load, memory and speed of a big volume in its three modes.
#include "bench/bench_volume.h"

#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>

#include "bench/bench_live.h"
#include "bench/bench_options.h"
#include "bench/bench_report.h"
#include "bench/bench_volume_mesh.h"
#include "bench/volume_peer.h"
#include "core/io/scene_json.h"
#include "core/scene/scene_volumes.h"
#include "core/volume/volume_generators.h"
#include "display/png_io.h"
#include "frameless/tile_render.h"

namespace frameless::bench {
namespace {

using Clock = std::chrono::steady_clock;
double since(Clock::time_point t0) {
  return std::chrono::duration<double>(Clock::now() - t0).count();
}

// The scene around the raw file: the phantom standing on a floor, lit by one soft light.
std::string scene_json(const std::string& raw, int nx, int ny, int nz, const std::string& mode) {
  std::string render;
  if (mode == "isosurface")
    render = R"("isovalue": 1600, "material": "bone")";
  else if (mode == "direct")
    render = R"("mode": "direct", "transfer": "ct-bone")";
  else
    render = R"("mode": "mip", "transfer": "grayscale")";
  const std::string volume = mode == "mesh" ? "" : ",\n      {\"type\": \"volume\"";
  // The phantom fills [-1, 1] on every axis, whatever the voxel counts (as the generator samples
  // it): the spacing says so, and the head stands up (its z is our y) around the origin.
  char place[256];
  std::snprintf(
      place, sizeof place,
      R"("spacing": [%.9g, %.9g, %.9g], "transform": {"translate": [-1, -1, 1], "rotate": {"axis": [1, 0, 0], "degrees": -90}})",
      2.0 / (nx - 1), 2.0 / (ny - 1), 2.0 / (nz - 1));
  return std::string(R"({"camera": {"eye": [1.6, 0.9, 3.6], "look": [0, -0.1, 0], "fov": 38},
    "settings": {"background": [0.12, 0.13, 0.16], "shadows": "hard"},
    "lights": [{"type": "spherical", "position": [2.5, 4, 3], "radius": 0.3, "color": 0.9}],
    "materials": {"bone": {"class": "polished", "kd": [0.9, 0.85, 0.72], "r0": 0.04}, "floor": {"class": "diffuse", "kd": 0.55}},
    "objects": [{"type": "plane", "point": [0, -1.05, 0], "normal": [0, 1, 0], "size": 8, "material": "floor"})") +
         (mode == "mesh"
              ? std::string("]}")
              : volume + R"(, "file": ")" + raw + R"(", "dims": [)" + std::to_string(nx) + ", " +
                    std::to_string(ny) + ", " + std::to_string(nz) + R"(], "format": "uint16", )" +
                    place + ", " + render + "}]}");
}

// Macrocells the mode skips outright: ranges without the isovalue, or of zero opacity.
double skipped_fraction(const VolumeObject& v) {
  size_t skip = 0;
  const Macrocells& m = *v.cells;
  for (size_t i = 0; i < m.lo.size(); ++i)
    skip += v.mode == VolumeMode::kIsosurface
                ? !(m.lo[i] <= v.isovalues[0] && v.isovalues[0] <= m.hi[i])
            : v.mode == VolumeMode::kDirect ? v.cell_opacity[i] <= 0.0f
                                            : 0;
  return m.lo.empty() ? 0.0 : double(skip) / double(m.lo.size());
}

}  // namespace

int run_volume(const VolumeOptions& a) {
  std::string error;
  int w = 0, h = 0;
  if (!parse_size(a.quick ? "128x128" : a.size, w, h, error)) return report_error(error);
  if (!valid_threads(a.threads, error)) return report_error(error);
  const int threads = a.threads > 0 ? a.threads : hardware_threads();
  const std::string dims = a.quick ? "128x128x128" : a.dims;
  auto spec_grid = make_builtin_volume("volume:shepp-logan:" + dims);  // checks the dims' form
  if (!spec_grid) return report_error("--dims: " + spec_grid.error().message);
  const int nx = (*spec_grid)->nx, ny = (*spec_grid)->ny, nz = (*spec_grid)->nz;
  const std::string dir = a.out.empty() ? std::filesystem::temp_directory_path().string() : a.out;
  if (!a.out.empty() && !prepare_out_dir(a.out, error)) return report_error(error);
  nlohmann::json j = bench_header("volume", nullptr, "volume:shepp-logan:" + dims,
                                  {{"dims", dims},
                                   {"size", std::to_string(w) + "x" + std::to_string(h)},
                                   {"threads", threads},
                                   {"spp", a.spp},
                                   {"seconds", a.seconds},
                                   {"quick", a.quick}});
  try {
    // 1. The phantom, generated and written as raw 16-bit voxels (the generator's own time apart).
    bench_progress("volume", "writing the " + dims + " phantom");
    const std::string raw = dir + "/phantom_" + dims + ".raw";
    {
      auto t0 = Clock::now();
      auto grid = make_builtin_volume("volume:shepp-logan:" + dims, thread_parallel_for(threads));
      j["generate_seconds"] = since(t0);
      std::ofstream f(raw, std::ios::binary);
      f.write(reinterpret_cast<const char*>((*grid)->storage->data()),
              std::streamsize((*grid)->storage->size()));
      if (!f) return report_error(raw + ": cannot write the phantom");
    }
    spec_grid = Error{""};  // release the first grid too
    const double data_bytes = double(nx) * ny * nz * 2.0;
    j["data_bytes"] = data_bytes;
    // 2. Load and build, per mode (the file is mapped once per scene; the first load reads it).
    const double rss0 = rss_bytes();
    nlohmann::json modes = nlohmann::json::object();
    for (const char* mode : {"isosurface", "direct", "mip"}) {
      bench_progress("volume", std::string("loading and rendering the ") + mode);
      auto t0 = Clock::now();
      auto scene = parse_scene_json(scene_json(raw, nx, ny, nz, mode), dir + "/volume.json", dir);
      if (!scene) return report_error(scene.error().message);
      nlohmann::json mj;
      mj["load_and_build_seconds"] = since(t0);
      mj["resident_over_data"] = (rss_bytes() - rss0) / data_bytes;
      const VolumeObject& v = (*scene)->volumes[0];
      mj["macrocells"] = v.cells->lo.size();
      mj["macrocells_skipped_fraction"] = skipped_fraction(v);
      // 3. One frame at w x h, spp samples per pixel, on the threads.
      TileRenderOptions o;
      o.spp = a.spp;
      o.threads = threads;
      const CameraBasis cam = make_camera_basis((*scene)->camera, w, h);
      const RenderedImage img = render_tiles(**scene, cam, o);
      mj["frame_seconds"] = img.seconds;
      mj["samples_per_s"] = double(w) * h * a.spp / img.seconds;
      if (v.mode != VolumeMode::kIsosurface) {  // volume samples per second in that frame
        uint64_t samples = 0;
        for (int y = 0; y < h; ++y)
          for (int x = 0; x < w; ++x)
            samples +=
                volumes_along(**scene, camera_ray(cam, x + 0.5f, y + 0.5f), kInfinity, nullptr)
                    .samples;
        mj["volume_samples_per_frame_spp1"] = samples;
        mj["volume_samples_per_s"] = double(samples) * a.spp / img.seconds;
      }
      if (v.mode == VolumeMode::kDirect) {  // adaptive sampling's price: the frame without it
        (*scene)->volumes[0].adaptive = false;
        const RenderedImage exact = render_tiles(**scene, cam, o);
        (*scene)->volumes[0].adaptive = true;
        double sq = 0.0;
        for (size_t i = 0; i < exact.rgb.size(); ++i) sq += double(exact.rgb[i] - img.rgb[i]) * (exact.rgb[i] - img.rgb[i]);
        mj["without_adaptive_frame_seconds"] = exact.seconds;
        mj["adaptive_speedup"] = exact.seconds / img.seconds;
        mj["adaptive_rmse"] = std::sqrt(sq / double(exact.rgb.size()));
      }
      if (!a.out.empty()) {
        if (auto wr = write_png(a.out + "/volume_" + mode + ".png", w, h, img.rgb.data()); !wr)
          return report_error(wr.error().message);
      }
      // 4. The live frameless engine and display at w x h.
      LiveMode live;
      live.name = live.kind = "frameless";
      live.engine.width = w;
      live.engine.height = h;
      live.engine.threads = threads;
      const std::vector<float> black(size_t(w) * h * 3, 0.0f);
      LiveSchedule sched;
      sched.poses = {(*scene)->camera};
      sched.references = {&black};
      sched.noise_mse = {0.0};
      sched.duration = a.quick ? 0.5 : a.seconds;
      const LiveResult r = run_live(**scene, live, sched);
      mj["live_samples_per_s"] = r.samples_per_s;
      if (v.mode == VolumeMode::kIsosurface)
        mj["volume_bytes_with_macrocells"] = data_bytes + double(v.cells->lo.size()) * 8.0;
      mj["live_image_refreshes_per_s"] =
          r.samples_per_s / 2.0 / (double(w) * h);  // 2 jittered samples a visit
      mj["resident_over_data_after_rendering"] = (rss_bytes() - rss0) / data_bytes;
      modes[mode] = mj;
    }
    // 5. The same isosurface as a mesh through the BVH, last (its memory would count in the
    // modes' figures otherwise), against a fresh frame of Parker's isosurface.
    {
      bench_progress("volume", "meshing the isosurface (marching tetrahedra) and tracing it");
      auto scene =
          parse_scene_json(scene_json(raw, nx, ny, nz, "isosurface"), dir + "/volume.json", dir);
      if (!scene) return report_error(scene.error().message);
      TileRenderOptions o;
      o.spp = a.spp;
      o.threads = threads;
      const RenderedImage img = render_tiles(**scene, make_camera_basis((*scene)->camera, w, h), o);
      modes["isosurface"]["mesh"] =
          compare_with_mesh(**scene, scene_json(raw, nx, ny, nz, "mesh"), dir, w, h, a.spp, threads,
                            img.rgb, img.seconds);
    }
    j["modes"] = modes;
    // 6. OpenVDB's vdb_render on the same level set and camera (bench-only peer).
    bench_progress("volume", "vdb_render on the same level set");
    j["peer"] = compare_with_vdb_render(a.quick ? 64 : 256, w, h, threads, dir);
    bench_progress("volume", "vdb_render on a fog volume");
    j["peer_fog"] = compare_fog_with_vdb_render(a.quick ? 64 : 256, w, h, threads, dir);
    if (!a.keep) std::filesystem::remove(raw);
  } catch (const std::exception& e) {
    return report_error(e.what());
  }
  if (!a.out.empty() && !write_json(a.out + "/volume.json", j, error)) return report_error(error);
  if (a.json) {
    std::printf("%s\n", j.dump(2).c_str());
    return 0;
  }
  std::printf(
      "bench volume: Shepp-Logan phantom %s (%.0f MB of 16-bit voxels), %dx%d, %d threads\n",
      dims.c_str(), j["data_bytes"].get<double>() / 1e6, w, h, threads);
  std::printf("  generated in %.1f s (then written as raw; each mode maps the file)\n",
              j["generate_seconds"].get<double>());
  for (const auto& [mode, m] : j["modes"].items()) {
    std::printf(
        "  %-10s load+build %5.2f s, resident %.2fx the data (%.2fx after rendering), %zu "
        "macrocells, %.0f %% skipped\n",
        mode.c_str(), m["load_and_build_seconds"].get<double>(),
        m["resident_over_data"].get<double>(),
        m["resident_over_data_after_rendering"].get<double>(), m["macrocells"].get<size_t>(),
        100 * m["macrocells_skipped_fraction"].get<double>());
    std::printf("             frame %.3f s: %.2f M samples/s", m["frame_seconds"].get<double>(),
                m["samples_per_s"].get<double>() / 1e6);
    if (m.contains("volume_samples_per_s"))
      std::printf(", %.1f M volume samples/s", m["volume_samples_per_s"].get<double>() / 1e6);
    if (m.contains("adaptive_speedup"))
      std::printf(" (adaptive sampling: %.2fx faster than %.3f s without, RMSE %.4f)", m["adaptive_speedup"].get<double>(),
                  m["without_adaptive_frame_seconds"].get<double>(), m["adaptive_rmse"].get<double>());
    std::printf("; live: %.2f M samples/s, %.1f image refreshes/s\n",
                m["live_samples_per_s"].get<double>() / 1e6,
                m["live_image_refreshes_per_s"].get<double>());
    if (m.contains("mesh")) {
      const auto& me = m["mesh"];
      std::printf(
          "             as a mesh (marching tetrahedra): %.2f M triangles in %.1f s, BVH %.1f s, "
          "%.0f MB "
          "(the volume: %.0f MB); frame %.3f s (%.2f M samples/s): Parker's isosurface takes %.2fx "
          "its time; "
          "RMSE between the two %.4f\n",
          me["triangles"].get<double>() / 1e6, me["mesh_seconds"].get<double>(),
          me["bvh_build_seconds"].get<double>(),
          me["resident_bytes_mesh_and_bvh"].get<double>() / 1e6,
          m["volume_bytes_with_macrocells"].get<double>() / 1e6, me["frame_seconds"].get<double>(),
          me["samples_per_s"].get<double>() / 1e6, me["isosurface_over_mesh_time"].get<double>(),
          me["rmse_against_isosurface"].get<double>());
    }
  }
  const auto& peer = j["peer"];
  if (peer.contains("skipped")) {
    std::printf("  peer vdb_render: skipped (%s)\n", peer["skipped"].get<std::string>().c_str());
  } else {
    std::printf(
        "  peer vdb_render on a %s, primary hits at %dx%d: vdb_render %.3f s (%.2f M rays/s)\n",
        peer["grid"].get<std::string>().c_str(), w, h, peer["vdb_render_seconds"].get<double>(),
        peer["vdb_render_rays_per_s"].get<double>() / 1e6);
    for (const char* key : {"frameless", "frameless_vdb"}) {
      const auto at = [&](const char* field) { return peer[std::string(key) + field]; };
      std::printf(
          "    frameless from the %s (%.1f MB): %.3f s (%.2f M rays/s), %.2fx its speed; hit "
          "points within a "
          "voxel %.1f %% (mean %.3f, max %.2f voxels), %zu pixels hit by only one\n",
          std::string(key) == "frameless" ? "raw copy, dense" : ".vdb, bricked",
          at("_grid_bytes").get<double>() / 1e6, at("_seconds").get<double>(),
          at("_rays_per_s").get<double>() / 1e6, at("_over_vdb_render_speed").get<double>(),
          100 * at("_hits_within_one_voxel").get<double>(),
          at("_mean_distance_voxels").get<double>(), at("_max_distance_voxels").get<double>(),
          at("_pixels_hit_by_one").get<size_t>());
    }
  }
  const auto& fog = j["peer_fog"];
  if (fog.contains("skipped")) {
    std::printf("  peer vdb_render (fog): skipped (%s)\n",
                fog["skipped"].get<std::string>().c_str());
  } else {
    std::printf(
        "  peer vdb_render on a %s, %.1f MB bricked, emission-absorption at %dx%d: vdb_render %.3f "
        "s, frameless "
        "%.3f s (%.1f M volume samples/s; vdb_render %.1f M for the same count): %.2fx its speed; "
        "alpha "
        "differs by %.4f on average (max %.3f)\n",
        fog["grid"].get<std::string>().c_str(), fog["grid_bytes"].get<double>() / 1e6, w, h,
        fog["vdb_render_seconds"].get<double>(), fog["frameless_seconds"].get<double>(),
        fog["frameless_samples_per_s"].get<double>() / 1e6,
        fog["vdb_render_samples_per_s_same_count"].get<double>() / 1e6,
        fog["frameless_over_vdb_render_speed"].get<double>(),
        fog["mean_alpha_difference"].get<double>(), fog["max_alpha_difference"].get<double>());
  }
  return 0;
}

}  // namespace frameless::bench
