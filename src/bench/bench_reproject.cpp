// `frameless bench reproject`: reprojection alone, per camera change (see bench_reproject.h).
#include "bench/bench_reproject.h"

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstring>
#include <limits>
#include <memory>
#include <vector>

#include <nlohmann/json.hpp>

#include "bench/bench_options.h"
#include "bench/bench_report.h"
#include "core/shading/render_sample.h"
#include "display/camera_controls.h"
#include "display/reproject.h"
#include "display/slot_image.h"
#include "frameless/partition.h"

namespace frameless::bench {
namespace {

// Each pixel's point as a render thread leaves it (trace_sample's primary hit at the pixel
// centre), held as the display holds moved content: relative to the camera.
std::vector<ViewPoint> primary_points(const Scene& scene, const Camera& camera, int w, int h) {
  std::vector<ViewPoint> points(size_t(w) * size_t(h));
  const CameraBasis b = make_camera_basis(camera, w, h);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      const SampleResult r = trace_sample(scene, b, float(x) + 0.5f, float(y) + 0.5f, uint64_t(y) * uint64_t(w) + uint64_t(x));
      size_t pixel = 0;
      const ViewPoint v = to_view(b, ScenePoint{r.position, r.object}, pixel);
      if (view_kind(v.bits) != kViewNone) points[pixel] = v;
    }
  return points;
}

struct Timing {
  double median_ms = 0, best_ms = 0;
  double moved = 0, disoccluded = 0;  // fractions of the pixels at the last change
  ReprojectTimes phases;              // medians of each phase over the changes
};

// `changes` reprojections along the orbit, the image moved each time (as the display does).
Timing time_changes(const Camera& start, const ReprojectOptions& o, int w, int h,
                    const uint32_t* pixel_of, const uint32_t* slot_of, std::vector<ViewPoint> points) {
  const size_t n = size_t(w) * size_t(h);
  std::vector<DisplayPixel> px(n), px_out(n);
  std::vector<ViewPoint> points_out(n);
  std::vector<uint8_t> marks(n, kMarkMoved), marks_out(n);
  // Epochs as a moving display shows them: each pixel the camera of its newest update, one of the
  // last dozen changes, at random from pixel to pixel (the threads' pixels are shuffled).
  for (size_t s = 0; s < n; ++s) px[s].epoch = 1 + uint32_t((uint64_t(s) * 0x9E3779B97F4A7C15ull) >> 60) % 12;
  Reprojector r;
  EpochCensus census;
  // What pushes the image's arrays out of the caches between changes beside the render threads.
  std::vector<uint8_t> other(size_t(o.evict_mb) << 20);
  uint8_t fill = 0;
  std::vector<double> ms, phase_ms[ReprojectTimes::kPhases];
  Camera camera = start;
  ReprojectStats last;
  for (int k = 0; k < o.changes + 2; ++k) {  // two untimed: first touches of the scratch memory
    const CameraBasis before = make_camera_basis(camera, w, h);
    camera = orbit_camera(camera, float(o.degrees / CameraControlConfig{}.orbit_deg_per_pixel), 0.0f);
    const SlotImage from{w, h, pixel_of, slot_of, px.data(), points.data(), marks.data(), nullptr};
    const SlotImage to{w, h, pixel_of, slot_of, px_out.data(), points_out.data(), marks_out.data(), nullptr};
    if (!other.empty()) std::memset(other.data(), ++fill, other.size());
    const auto t0 = std::chrono::steady_clock::now();
    census.clear();
    const ReprojectStats st = r.run(before, make_camera_basis(camera, w, h), from, to, true, 3, &census);
    const double t = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
    last = st;
    if (k >= 2) {
      ms.push_back(t);
      for (int i = 0; i < ReprojectTimes::kPhases; ++i) phase_ms[i].push_back(r.last_times().ms[i]);
    }
    px.swap(px_out), points.swap(points_out), marks.swap(marks_out);
  }
  Timing out;
  out.median_ms = median(ms);
  out.best_ms = *std::min_element(ms.begin(), ms.end());
  for (int i = 0; i < ReprojectTimes::kPhases; ++i) out.phases.ms[i] = median(phase_ms[i]);
  out.moved = double(last.moved) / double(n);
  out.disoccluded = double(last.disoccluded) / double(n);
  return out;
}

// This machine's memory speed beside the changes: the best of five copies of an image's pixels
// (16 bytes each, the size of what the pass by slot moves), milliseconds. A change then reads as
// so many image copies, a figure that travels between machines better than milliseconds
// (docs/benchmarks.md, section 34).
double image_copy_ms(size_t pixels) {
  std::vector<DisplayPixel> a(pixels), b(pixels);  // constructed: their pages are touched already
  double best = std::numeric_limits<double>::infinity();
  for (int k = 0; k < 5; ++k) {
    const auto t0 = std::chrono::steady_clock::now();
    std::memcpy(b.data(), a.data(), pixels * sizeof(DisplayPixel));
    best = std::min(best, std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count());
    a.swap(b);
  }
  return std::max(best, 1e-6);
}

}  // namespace

int run_reproject(const ReprojectOptions& o) {
  std::string error;
  int w = 0, h = 0;
  if (!parse_size(o.size, w, h, error)) return report_error(error);
  if (!valid_threads(o.threads, error)) return report_error(error);
  if (!(o.changes >= 1 && o.changes <= 10000)) return report_error("--changes: must be 1..10000");
  if (!(o.degrees > 0 && o.degrees <= 45)) return report_error("--degrees: must be in (0, 45]");
  // Caches are at most some hundreds of megabytes; gigabytes would only strain the memory.
  if (!(o.evict_mb >= 0 && o.evict_mb <= 2048)) return report_error("--evict: must be 0..2048 megabytes");
  if (o.order != "all" && o.order != "curve" && o.order != "slots" && o.order != "pixels")
    return report_error("--order: expected curve, slots, pixels or all, got '" + o.order + "'");
  std::unique_ptr<Scene> scene = load_scene_or_report(o.scene, nullptr);
  if (!scene) return 2;
  PartitionConfig pc;
  pc.width = w, pc.height = h, pc.threads = o.threads > 0 ? o.threads : hardware_threads();
  const Partition part = make_partition(pc);
  // The display's places, and the engine's slot order with its inverse.
  const LayoutPtr layout = make_layout(std::make_shared<const std::vector<uint32_t>>(slot_order(part)), w, h);
  const std::vector<ViewPoint> points = primary_points(*scene, scene->camera, w, h);
  const bool all = o.order == "all";
  Timing curve, slots, pixels;
  if (all || o.order == "curve")
    curve = time_changes(scene->camera, o, w, h, layout->pixel_of.data(), layout->slot_of.data(), points);
  if (all || o.order == "slots")
    slots = time_changes(scene->camera, o, w, h, layout->engine_order->data(), layout->engine_slot_of.data(), points);
  if (all || o.order == "pixels") pixels = time_changes(scene->camera, o, w, h, nullptr, nullptr, points);
  const double px = double(w) * double(h);
  const double copy_ms = image_copy_ms(size_t(w) * size_t(h));
  const double copy_gb_per_s = 2.0 * px * double(sizeof(DisplayPixel)) / (copy_ms * 1e6);  // read + written
  if (o.json) {
    nlohmann::json j = {{"scene", o.scene}, {"size", o.size}, {"threads", o.threads},
                        {"degrees", o.degrees}, {"changes", o.changes}, {"evict_mb", o.evict_mb},
                        {"vector_paths", Reprojector::vector_paths()}, {"image_copy_ms", copy_ms},
                        {"image_copy_gb_per_s", copy_gb_per_s}};
    for (const auto& [name, t] :
         {std::pair{"curve_order", curve}, std::pair{"slot_order", slots}, std::pair{"pixel_order", pixels}})
      if (t.median_ms > 0) {
        j[name] = {{"median_ms", t.median_ms}, {"best_ms", t.best_ms}, {"ns_per_pixel", 1e6 * t.median_ms / px},
                   {"image_copies", t.median_ms / copy_ms},
                   {"moved_fraction", t.moved}, {"disoccluded_fraction", t.disoccluded}};
        for (int i = 0; i < ReprojectTimes::kPhases; ++i) j[name]["phases_ms"][ReprojectTimes::kNames[i]] = t.phases.ms[i];
      }
    std::printf("%s\n", j.dump(1).c_str());
    return 0;
  }
  std::printf("reprojection of %s at %dx%d, %.2f degrees of orbit a change, one core, median of %d (%s paths)%s\n",
              o.scene.c_str(), w, h, o.degrees, o.changes, Reprojector::vector_paths(),
              o.evict_mb > 0 ? (", " + std::to_string(o.evict_mb) + " MB of other memory written between changes").c_str()
                             : "");
  std::printf("  a copy of the image's pixels (%.1f MB read, as many written) takes %.2f ms here: %.1f GB/s\n",
              px * double(sizeof(DisplayPixel)) / 1e6, copy_ms, copy_gb_per_s);
  for (const auto& [name, t] : {std::pair{"curve (the display's)", curve}, std::pair{"engine's slot order", slots},
                                std::pair{"pixel order", pixels}})
    if (t.median_ms > 0) {
      std::printf("  %-27s %6.2f ms (best %.2f), %5.1f ns a pixel, %.1f image copies, %3.0f %% of a core at 30 "
                  "changes/s; %.1f %% moved, %.2f %% disoccluded\n",
                  name, t.median_ms, t.best_ms, 1e6 * t.median_ms / px, t.median_ms / copy_ms, 3.0 * t.median_ms,
                  100.0 * t.moved, 100.0 * t.disoccluded);
      std::printf("  %-27s splat %.2f, cracks %.2f, disocclusions %.2f, gather by pixel %.2f, by slot %.2f ms\n",
                  "  phases (medians)", t.phases.ms[ReprojectTimes::splat], t.phases.ms[ReprojectTimes::cracks],
                  t.phases.ms[ReprojectTimes::disocclusions], t.phases.ms[ReprojectTimes::pixel_pass],
                  t.phases.ms[ReprojectTimes::slot_pass]);
    }
  return 0;
}

}  // namespace frameless::bench
