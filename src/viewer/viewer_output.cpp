// What the viewer shows and writes: the window's picture (image, overlay, panels), saved images,
// captures from the window, screenshots, the live figures and the reference they are measured by.
#include <cmath>
#include <cstdio>
#include <filesystem>

#define GLFW_INCLUDE_NONE
#include <GLFW/glfw3.h>

#include "display/capture.h"
#include "display/exr_io.h"
#include "display/levels_view.h"
#include "display/png_io.h"
#include "frameless/image_error.h"
#include "viewer/panels.h"
#include "viewer/viewer_state.h"

namespace frameless {
namespace {

const std::vector<std::string> kHelp = {
    "Tab: panels  drag: orbit  right/middle drag: pan",  "wheel: zoom  WASD, Q/E: fly  R: reset",
    "M: frameless/conventional  V: view",                "[ ]: alpha -/+   - =: refresh -/+",
    ", .: update % -/+   G T: threads -/+",               "P: save EXR snapshot  H/F1: help",
    "arrows, PgUp/PgDn: move the light (or the grabbed instance)",
    "I: grab/release the instance at the centre of the view",     "O: overlay on/off  Esc: quit",
    "J: reprojection on/off  K: temporal blend weights on/off",
    "Z X: isovalue -/+   B: next transfer function (volumes)"};

// The first free NAME_NNN.EXT (or folder) in dir.
std::string next_free(const std::string& dir, const char* stem, const char* ext) {
  for (int i = 0;; ++i) {
    char name[80];
    std::snprintf(name, sizeof name, "%s_%03d%s", stem, i, ext);
    const std::string p = (std::filesystem::path(dir) / name).string();
    if (!std::filesystem::exists(p)) return p;
  }
}

void push_limited(std::vector<float>& v, float x) {
  if (v.size() >= ViewerRates::kHistory) v.erase(v.begin());
  v.push_back(std::isfinite(x) ? x : 0.0f);
}

}  // namespace

std::string si(double v) {
  char buf[32];
  if (v >= 1e6) std::snprintf(buf, sizeof buf, "%.2fM", v * 1e-6);
  else if (v >= 1e3) std::snprintf(buf, sizeof buf, "%.1fk", v * 1e-3);
  else std::snprintf(buf, sizeof buf, "%.0f", v);
  return buf;
}

void Viewer::save_image(const std::string& format) {
  const DisplayImage& img = display->acquire_latest();
  std::error_code ec;
  std::filesystem::create_directories(opt.snapshot_dir, ec);
  Result<bool> r = true;
  std::string path;
  if (format == "png") {
    path = next_free(opt.snapshot_dir, "snapshot", ".png");
    r = write_png(path, img.width, img.height, img.rgb.data());
  } else {
    path = next_free(opt.snapshot_dir, "snapshot", ".exr");
    ExrAttributes a;
    a.world_to_camera = world_to_camera_matrix(camera);
    a.doubles["frameTime"] = img.info.virtual_time;
    a.strings["renderMode"] = to_string(img.info.mode);
    a.strings["seed"] = std::to_string(engine_config.seed);
    r = write_display_exr(path, img, nullptr, {"age", "count", "variance", "epoch", "levels"}, a);
  }
  status = r.ok() ? "saved " + path : r.error().message;
  std::fprintf(stderr, "frameless: %s\n", status.c_str());
  dirty = true;
}

void Viewer::start_capture() {
  if (!capture_dir.empty()) return;
  const std::string dir = next_free(opt.snapshot_dir, "window_capture", "");
  if (auto r = prepare_output_dir(dir); !r.ok()) {
    status = r.error().message;
  } else {
    capture_dir = dir, capture_frames = 0;
    status = "capturing into " + dir;
  }
  std::fprintf(stderr, "frameless: %s\n", status.c_str());
  dirty = true;
}

void Viewer::stop_capture() {
  if (capture_dir.empty()) return;
  char buf[300];
  std::snprintf(buf, sizeof buf, "captured %d frames into %s", capture_frames, capture_dir.c_str());
  status = buf;
  std::fprintf(stderr, "frameless: %s\n", status.c_str());
  capture_dir.clear();
  dirty = true;
}

// Each display tick's image once (the window may present a tick more than once).
void Viewer::capture_frame() {
  bool fresh = false;
  const DisplayImage& img = display->acquire_latest(&fresh);
  dirty |= fresh;  // taken here: the loop would not see it as new
  if (capture_dir.empty() || img.pixels() == 0 || img.info.index == captured_tick) return;
  captured_tick = img.info.index;
  const std::string path = (std::filesystem::path(capture_dir) / capture_frame_name(capture_frames)).string();
  const std::string png = path.substr(0, path.rfind('.')) + ".png";
  if (auto r = write_png(png, img.width, img.height, img.rgb.data()); !r.ok()) {
    status = r.error().message + " (capture stopped after " + std::to_string(capture_frames) + " frames)";
    std::fprintf(stderr, "frameless: %s\n", status.c_str());
    capture_dir.clear();
    return;
  }
  ++capture_frames;
}

void Viewer::screenshot(const std::string& path) {
  int fw = 0, fh = 0;
  glfwGetFramebufferSize(window, &fw, &fh);
  draw(fw, fh);
  std::vector<unsigned char> rgb8;
  presenter->read_rgb8(fw, fh, rgb8);
  // .exr: the window's 8-bit sRGB values as floats in [0, 1] (tests read them back); else PNG.
  Result<bool> r = true;
  if (path.size() > 4 && path.substr(path.size() - 4) == ".exr") {
    std::vector<float> f(rgb8.size());
    for (size_t i = 0; i < f.size(); ++i) f[i] = float(rgb8[i]) / 255.0f;
    r = write_exr(path, fw, fh, {{"R", false, f.data(), 3}, {"G", false, f.data() + 1, 3},
                                 {"B", false, f.data() + 2, 3}});
  } else {
    r = write_png_rgb8(path, fw, fh, rgb8.data());
  }
  std::fprintf(stderr, "frameless: %s\n", r.ok() ? ("screenshot " + path).c_str() : r.error().message.c_str());
}

// Renders the current view with `spp` samples on one thread beside the engine (the plots' error).
void Viewer::request_reference(int spp) {
  // Refusals first, each said in one line (a request while one renders used to vanish silently).
  if (world_edited) {  // the reference renders the Scene, which the world channel's edits do not change
    status = "reference: the lights, materials or objects were edited; it would show the scene as loaded";
    std::fprintf(stderr, "frameless: %s\n", status.c_str());
    return;
  }
  if (reference_job.valid()) {
    status = "reference: one is being rendered already";
    std::fprintf(stderr, "frameless: %s\n", status.c_str());
    return;
  }
  ReferenceSpec spec;
  spec.camera = reference_camera = camera;
  spec.width = engine->width(), spec.height = engine->height();
  spec.spp = spp;
  const Scene* s = scene;
  reference_job = std::async(std::launch::async, [s, spec] {
    return load_or_render_reference(*s, spec, "", 1);
  });
  status = "rendering a reference of this view (" + std::to_string(spp) + " spp, one thread)";
  dirty = true;
}

void Viewer::update_rates() {
  const double t = now();
  if (reference_job.valid() &&
      reference_job.wait_for(std::chrono::seconds(0)) == std::future_status::ready) {
    auto r = reference_job.get();
    if (reference_outdated) {
      reference_outdated = false;
      status = "reference dropped: the world changed while it rendered";
    } else {
      if (r.ok()) reference = std::make_shared<const Reference>(std::move(r.value()));
      status = r.ok() ? "reference ready: the error plot compares against it" : r.error().message;
    }
  }
  if (rates.time >= 0 && t - rates.time < 0.25) return;
  const EngineStats es = engine->stats();
  const DisplayStats ds = display->stats();
  bool fresh = false;
  const DisplayImage& img = display->acquire_latest(&fresh);
  dirty |= fresh;  // taken here: the loop would not see it as new
  if (rates.time >= 0) {
    const double dt = t - rates.time;
    push_limited(rates.samples_per_s, float(double(es.samples - std::min(es.samples, rates.samples)) / dt));
    push_limited(rates.updates_per_s, float(double(ds.pixels_updated - std::min(ds.pixels_updated, rates.updates)) / dt));
    push_limited(rates.display_cpu, float(100.0 * std::max(0.0, ds.cpu_seconds - rates.display_cpu_seconds) / dt));
    push_limited(rates.coverage, float(100.0 * img.info.coverage));
    const bool comparable = reference && reference->width == img.width &&
                            reference->height == img.height && reference_camera == camera;
    if (comparable) push_limited(rates.error, float(image_error(img.rgb, reference->rgb).rmse));
  }
  rates.time = t, rates.samples = es.samples, rates.updates = ds.pixels_updated;
  rates.display_cpu_seconds = ds.cpu_seconds;
}

std::vector<std::string> Viewer::overlay(const ViewScale& s) {
  const EngineConfig ec = engine->config();
  const DisplayConfig dc = display->config();
  const DisplayStats ds = display->stats();
  char l1[200], l2[160], l3[160], l4[160];
  std::snprintf(l1, sizeof l1, "%s %dx%d %s", scene_label.c_str(), engine->width(), engine->height(),
                to_string(ec.mode));
  std::snprintf(l2, sizeof l2, "view %s  threads %d  update %.2g%%", to_string(view),
                engine->thread_count(), ec.update_percent);
  std::snprintf(l3, sizeof l3, "alpha %.2f%s  %.0f Hz (got %.1f)%s%s", dc.blend.alpha,
                dc.blend.temporal ? " temporal" : "", dc.refresh_hz,
                ds.mean_interval > 0 ? 1.0 / ds.mean_interval : 0.0, dc.blend.reproject ? "  reproject" : "",
                ec.closed_loop ? "  closed loop" : "");
  std::snprintf(l4, sizeof l4, "%s samples/s  coverage %.1f%%",
                si(rates.last(rates.samples_per_s)).c_str(), 100.0 * s.coverage);
  std::vector<std::string> lines = {l1, l2, l3, l4};
  if (view == ViewMode::age) lines.push_back("age: black 0 .. white " + std::to_string(s.max_age).substr(0, 5) + " s");
  if (view == ViewMode::count) lines.push_back("count: log, white = " + si(s.max_count));
  if (view == ViewMode::variance) lines.push_back("variance: log scale");
  if (view == ViewMode::epoch) lines.push_back("epoch: green newest, red older");
  if (view == ViewMode::levels) {
    lines.push_back("reflection levels (max " + std::to_string(s.max_levels) + "):");
    lines.push_back(kLevelsLegend);
  }
  if (help) lines.insert(lines.end(), kHelp.begin(), kHelp.end());
  else lines.push_back(panels ? "Tab: panels  H: help" : "H: help");
  if (!status.empty()) lines.push_back(status);
  return lines;
}

void Viewer::draw(int fw, int fh) {
  const DisplayImage& img = display->acquire_latest();
  const ViewScale s = presenter->upload(img, view);
  presenter->draw(fw, fh, true);
  // The bitmap overlay where the panels are hidden or ImGui cannot run.
  const bool panels_shown = panels && panels->visible();
  if (overlay_on && !panels_shown) presenter->draw_text(overlay(s), fw, fh, fw >= 1600 ? 2 : 1);
  if (panels_shown) panels->draw(*this, s);
}

}  // namespace frameless
