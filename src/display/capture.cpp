#include "display/capture.h"

#include <chrono>
#include <cmath>
#include <condition_variable>
#include <algorithm>
#include <cstdio>
#include <ctime>
#include <deque>
#include <filesystem>
#include <map>
#include <mutex>

#include "display/atomic_file.h"
#include "display/contact_sheet.h"
#include "display/display_thread.h"
#include "display/exr_io.h"
#include "display/gl_presenter.h"
#include "display/manifest.h"
#include "display/osmesa_context.h"
#include "display/png_io.h"
#include "frameless/engine.h"
#include "frameless/output_commit.h"

namespace frameless {
namespace {

std::string join(const std::string& dir, const std::string& name) {
  return (std::filesystem::path(dir) / name).string();
}

std::string local_date(const char* format) {
  const std::time_t now = std::time(nullptr);
  std::tm tm{};
  localtime_r(&now, &tm);
  char buf[64];
  std::strftime(buf, sizeof buf, format, &tm);
  return buf;
}

// Everything one capture run keeps between frames (capture thread only).
struct Writer {
  const CaptureOptions& opt;
  const CaptureHooks& hooks;
  GlPresenter& presenter;
  Manifest manifest;
  std::string manifest_path;
  std::vector<std::string> frame_paths;
  std::vector<ViewMode> views;  // opt.views, parsed
  std::vector<float> rgb;
  std::vector<std::vector<float>> view_rgb;  // each false-colour view of the frame, drawn before the files
  std::string settings_text;

  Result<bool> check_hook(const std::string& path) {
    if (hooks.before_write)
      if (auto message = hooks.before_write(path)) return Error{path + ": " + *message};
    return true;
  }

  Result<bool> write_manifest_now() {
    if (auto h = check_hook(manifest_path); !h.ok()) return h;
    return write_manifest(manifest_path, manifest);
  }

  // Draws the image exactly as the window would (linear float target), reads it back and writes
  // the false-colour views' PNGs, the EXR, then the manifest that lists them. On failure nothing
  // new is left behind.
  Result<bool> write_frame(const DisplayImage& img, uint64_t samples, double wall_time,
                           const Camera& camera) {
    // GL first, without the commit lock: the driver takes locks of its own.
    view_rgb.resize(views.size());
    for (size_t v = 0; v < views.size(); ++v) {
      presenter.upload(img, views[v]);
      if (auto r = presenter.render_linear(view_rgb[v]); !r.ok()) return r;
    }
    presenter.upload(img, ViewMode::shaded);
    if (auto r = presenter.render_linear(rgb); !r.ok()) return r;
    // A fatal abort (a cluster rank failed) waits for this frame's files and manifest to agree.
    const std::lock_guard<std::mutex> commit(output_commit_mutex());
    const int index = int(manifest.frames.size());
    const std::string name = capture_frame_name(index);
    const std::string path = join(opt.out_dir, name);
    std::vector<std::string> written;  // this frame's files so far, removed if a later one fails
    auto fail = [&](Result<bool> r) {
      for (const std::string& p : written) std::remove(p.c_str());
      return r;
    };
    std::map<std::string, std::string> view_files;
    for (size_t v = 0; v < views.size(); ++v) {
      const std::string view_name = capture_view_name(opt.views[v], index);
      const std::string view_path = join(opt.out_dir, view_name);
      if (auto h = check_hook(view_path); !h.ok()) return fail(h);
      if (auto p = write_png(view_path, img.width, img.height, view_rgb[v].data()); !p.ok()) return fail(p);
      written.push_back(view_path);
      view_files[opt.views[v]] = view_name;
    }
    ExrAttributes a;
    a.frames_per_second = opt.refresh_hz;
    if (wall_time >= 0) {
      a.cap_date = local_date("%Y:%m:%d %H:%M:%S");
      a.doubles["wallTime"] = wall_time;
    }
    a.world_to_camera = world_to_camera_matrix(camera);
    a.doubles["frameTime"] = img.info.virtual_time;
    a.ints["frameIndex"] = index;
    a.ints["displayTick"] = int(img.info.index);
    a.ints["cameraEpoch"] = int(img.info.newest_epoch);
    a.doubles["coverage"] = img.info.coverage;
    a.strings["renderMode"] = to_string(img.info.mode);
    a.strings["seed"] = std::to_string(opt.engine.seed);
    a.strings["software"] = std::string("frameless ") + FRAMELESS_VERSION;
    a.strings["settings"] = settings_text;
    if (auto h = check_hook(path); !h.ok()) return fail(h);
    if (auto w = write_display_exr(path, img, rgb.data(), opt.layers, a); !w.ok()) return fail(w);
    written.push_back(path);
    ManifestFrame f;
    f.index = index;
    f.file = name;
    f.display_tick = img.info.index;
    f.wall_time = wall_time;
    f.virtual_time = img.info.virtual_time;
    f.camera = camera;
    f.camera_epoch = img.info.newest_epoch;
    f.samples = samples;
    f.coverage = img.info.coverage;
    f.mode = to_string(img.info.mode);
    f.views = std::move(view_files);
    manifest.frames.push_back(f);
    if (auto m = write_manifest_now(); !m.ok()) {
      // The old manifest stays; the frame it does not list must go so the two agree.
      manifest.frames.pop_back();
      return fail(m);
    }
    frame_paths.push_back(path);
    return true;
  }
};

}  // namespace

Result<bool> write_display_exr(const std::string& path, const DisplayImage& img, const float* rgb,
                               const std::vector<std::string>& layers, const ExrAttributes& attributes) {
  if (!rgb) rgb = img.rgb.data();
  const size_t n = img.pixels();
  std::vector<ExrChannel> channels = {
      {"R", true, rgb + 0, 3}, {"G", true, rgb + 1, 3}, {"B", true, rgb + 2, 3}};
  std::vector<float> planes(n * layers.size(), 0.0f);
  for (size_t l = 0; l < layers.size(); ++l) {
    float* dst = planes.data() + l * n;
    const std::string& name = layers[l];
    if (name == "age") {
      for (size_t i = 0; i < n; ++i) dst[i] = img.age(i);
    } else if (name == "count") {
      for (size_t i = 0; i < n; ++i) dst[i] = float(img.sample_count[i]);
    } else if (name == "variance") {
      std::copy(img.variance.begin(), img.variance.begin() + ptrdiff_t(n), dst);
    } else if (name == "epoch") {
      for (size_t i = 0; i < n; ++i) dst[i] = float(img.epoch[i]);
    } else if (name == "levels") {
      for (size_t i = 0; i < n; ++i) dst[i] = i < img.levels.size() ? float(img.levels[i]) : 0.0f;
    } else {
      return Error{path + ": unknown layer '" + name + "'"};
    }
    channels.push_back({name, false, dst, 1});
  }
  return write_exr(path, img.width, img.height, channels, attributes);
}

std::string capture_frame_name(int index) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "frame_%05d.exr", index);
  return buf;
}

std::string capture_view_name(const std::string& view, int index) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "_%05d.png", index);
  return view + buf;
}

Result<bool> prepare_output_dir(const std::string& dir) {
  if (dir.empty()) return Error{"--out: empty output folder"};
  std::error_code ec;
  std::filesystem::create_directories(dir, ec);
  if (ec) return Error{dir + ": cannot create output folder: " + ec.message()};
  std::string error;
  if (!directory_writable(dir, error)) return Error{error};
  // access() can be fooled (read-only mounts, root): try a real file.
  if (auto probe = write_text_file_atomic(join(dir, ".frameless_write_test"), "ok\n"); !probe.ok())
    return Error{dir + ": output folder cannot be written (" + probe.error().message + ")"};
  std::filesystem::remove(join(dir, ".frameless_write_test"), ec);
  return true;
}

Result<CaptureResult> run_capture(const Scene& scene, const CaptureOptions& opt,
                                  const CaptureHooks& hooks) {
  if (!(opt.duration > 0.0) || !std::isfinite(opt.duration))
    return Error{"--duration: must be a positive number of seconds"};
  if (!(opt.refresh_hz >= 1.0 && opt.refresh_hz <= 240.0))
    return Error{"--refresh: must be between 1 and 240 Hz"};
  for (const std::string& l : opt.layers) {
    bool known = false;
    for (const char* k : kCaptureLayers) known |= l == k;
    if (!known)
      return Error{"--layers: unknown layer '" + l + "' (age, count, variance, epoch, levels)"};
  }
  std::vector<ViewMode> views;
  for (const std::string& v : opt.views) {
    ViewMode m = ViewMode::shaded;
    if (!parse_view(v, m) || m == ViewMode::shaded)
      return Error{"--view: unknown view '" + v + "' (levels, age, count, variance, epoch)"};
    if (std::find(views.begin(), views.end(), m) != views.end())
      return Error{"--view: '" + v + "' is named twice"};
    views.push_back(m);
  }
  if (const std::string bad = validate(opt.engine); !bad.empty()) return Error{bad};
  const Camera start = opt.path.keyframes.empty() ? opt.camera : evaluate_camera_path(opt.path, 0.0);
  if (!camera_is_valid(start)) return Error{"camera: invalid start camera"};
  if (auto d = prepare_output_dir(opt.out_dir); !d.ok()) return d.error();

  // The GL context before any rendering, so a machine without OSMesa fails at once.
  auto ctx = OsMesaContext::create(opt.engine.width, opt.engine.height);
  if (!ctx.ok()) return ctx.error();
  auto presenter = GlPresenter::create(&OsMesaContext::proc_address);
  if (!presenter.ok()) return presenter.error();

  CaptureResult result;
  result.gl_renderer = presenter.value()->renderer();
  Writer w{opt, hooks, *presenter.value()};
  w.views = std::move(views);
  w.manifest_path = join(opt.out_dir, "manifest.json");
  nlohmann::json& s = w.manifest.settings;
  s = opt.settings;
  s["software"] = std::string("frameless ") + FRAMELESS_VERSION;
  s["scene"]["name"] = scene.name;
  s["clock"] = opt.engine.deterministic ? "virtual" : "wall";
  if (!opt.engine.deterministic) s["date"] = local_date("%Y-%m-%d %H:%M:%S");
  s["duration_s"] = opt.duration;
  s["refresh_hz"] = opt.refresh_hz;
  s["size"] = {opt.engine.width, opt.engine.height};
  s["threads"] = opt.engine.threads;
  s["chunk_size"] = opt.engine.chunk_size;
  s["update_percent"] = opt.engine.update_percent;
  s["seed"] = opt.engine.seed;
  s["scene_seed"] = scene.settings.seed;
  s["mode"] = to_string(opt.engine.mode);
  s["jitter"] = opt.engine.jitter;
  s["samples_per_tick"] = opt.engine.samples_per_tick;
  s["alpha"] = opt.blend.alpha;
  s["time_decay"] = opt.blend.time_decay;
  s["decay_seconds"] = opt.blend.decay_seconds;
  s["converge"] = opt.blend.converge;
  s["layers"] = opt.layers;
  s["views"] = opt.views;
  s["camera_path_keyframes"] = opt.path.keyframes.size();
  s["gl_renderer"] = result.gl_renderer;
  w.settings_text = s.dump();
  if (auto m = w.write_manifest_now(); !m.ok()) return m.error();

  Engine engine(scene, opt.engine, start);
  DisplayConfig dc;
  dc.refresh_hz = opt.refresh_hz;
  dc.blend = opt.blend;
  DisplayThread display(engine, dc);
  std::map<uint32_t, Camera> cameras = {{engine.camera_epoch(), start}};  // epoch -> camera
  Camera published = start;
  auto publish_at = [&](double t) {
    engine.animate_instances(t);  // instances with a "motion" (nothing when the scene has none)
    const Camera c = evaluate_camera_path(opt.path, t, opt.camera);
    if (c == published) return;  // republishing would restart every pixel's average
    cameras[engine.publish_camera(c)] = c;
    published = c;
  };
  auto camera_of = [&](uint32_t epoch) {
    auto it = cameras.upper_bound(epoch);
    return it == cameras.begin() ? start : std::prev(it)->second;
  };
  const int total = std::max(1, int(std::lround(opt.duration * opt.refresh_hz)));
  auto progress = [&](int k) {
    if (opt.progress) std::fprintf(stderr, "\rcapture: frame %d/%d", k, total);
  };
  Result<bool> status = true;
  auto cancelled = [&] { return opt.cancel && opt.cancel->load(std::memory_order_relaxed); };
  auto started = [&] {
    engine.start();
    if (opt.engine_hook) opt.engine_hook(&engine);
  };

  if (opt.engine.deterministic) {
    // Virtual clock: frame k shows the samples rendered in [k, k+1) / refresh with camera(k / refresh).
    started();
    for (int k = 0; k < total && status.ok() && !cancelled(); ++k) {
      publish_at(double(k) / opt.refresh_hz);
      const FrameInfo info = display.step();
      const DisplayImage& img = display.acquire_latest();
      status = w.write_frame(img, info.samples, -1.0, camera_of(img.info.newest_epoch));
      progress(k + 1);
    }
  } else {
    // Wall clock: the display thread ticks on its own; every tick this thread keeps up with is
    // written (a slow disk drops ticks, as a slow monitor would; display_tick shows the gaps).
    std::mutex mutex;
    std::condition_variable cv;
    std::deque<FrameInfo> ticks;
    display.set_on_tick_info([&](const FrameInfo& info) {
      std::lock_guard<std::mutex> lock(mutex);
      ticks.push_back(info);
      cv.notify_one();
    });
    started();
    display.start();
    const auto t0 = std::chrono::steady_clock::now();
    auto elapsed = [&] {
      return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    };
    int written = 0;
    while (status.ok() && elapsed() < opt.duration && written < total && !cancelled()) {
      publish_at(elapsed());
      {
        std::unique_lock<std::mutex> lock(mutex);
        cv.wait_for(lock, std::chrono::milliseconds(100), [&] { return !ticks.empty(); });
      }
      bool is_new = false;
      const DisplayImage& img = display.acquire_latest(&is_new);
      if (!is_new || img.pixels() == 0) continue;
      uint64_t samples = 0;
      {
        // Sum the samples of every tick up to this image's (its own callback may still be coming).
        std::unique_lock<std::mutex> lock(mutex);
        cv.wait_for(lock, std::chrono::milliseconds(200),
                    [&] { return !ticks.empty() && ticks.back().index >= img.info.index; });
        while (!ticks.empty() && ticks.front().index <= img.info.index) {
          samples += ticks.front().samples;
          ticks.pop_front();
        }
      }
      status = w.write_frame(img, samples, img.info.wall_time, camera_of(img.info.newest_epoch));
      progress(++written);
    }
    display.stop();
    engine.stop();
    display.set_on_tick_info(nullptr);
  }
  if (opt.engine_hook) opt.engine_hook(nullptr);
  engine.stop();
  if (opt.progress) std::fprintf(stderr, "\n");
  result.frames = int(w.manifest.frames.size());
  result.manifest_path = w.manifest_path;
  if (!status.ok())
    return Error{status.error().message + " (capture stopped; " + std::to_string(result.frames) +
                 " frames written and listed in " + w.manifest_path + ")"};
  if (auto e = engine.error()) return Error{"render thread failed: " + *e};
  if (cancelled())
    return Error{"stopped by a signal (" + std::to_string(result.frames) + " frames written and listed in " +
                 w.manifest_path + ")"};
  if (result.frames == 0) return Error{opt.out_dir + ": no display refresh arrived to capture"};

  if (opt.contact_sheet) {
    const std::string png = join(opt.out_dir, "contact_sheet.png");
    if (auto h = w.check_hook(png); !h.ok()) return h.error();
    if (auto c = write_contact_sheet(w.frame_paths, png); !c.ok()) return c.error();
    result.contact_sheet_path = png;
  }
  if (opt.mp4) {
    if (ffmpeg_available()) {
      const std::string mp4 = join(opt.out_dir, "sequence.mp4");
      if (auto m = write_mp4(w.frame_paths, opt.refresh_hz, mp4); m.ok())
        result.mp4_path = mp4;
      else
        result.note = m.error().message;
    } else {
      result.note = "no MP4: ffmpeg is not installed";
    }
  }
  return result;
}

}  // namespace frameless
