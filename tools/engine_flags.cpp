#include "tools/engine_flags.h"

#include "tools/tool_options.h"

namespace frameless::cli {

void EngineFlags::add_to(CLI::App& app) {
  app.add_option("--threads", threads, "render threads (default: all cores)");
  app.add_option("--chunk", chunk, "pixels per Hilbert chunk")->capture_default_str();
  app.add_option("--update-percent", update_percent,
                 "a thread picks up a new camera after this % of its pixels (0.01..100)")
      ->capture_default_str();
  app.add_option("--seed", seed, "seed of samples and shuffles")->capture_default_str();
  app.add_option("--mode", mode, "frameless or conventional")->capture_default_str();
  app.add_option("--alpha", alpha, "decay: displayed <- displayed (1-a) + sample a")
      ->capture_default_str();
  app.add_flag("--time-decay", time_decay, "alpha from the time since a pixel's last blend");
  app.add_flag("--reproject,!--no-reproject", reproject,
               "on a camera change, move what is shown to the new view (the render cache; default on)");
  app.add_option("--reproject-budget", reproject_budget,
                 "most of one core the display spends reprojecting, 0..1 (0: unlimited; a change "
                 "over budget merges into the next)")
      ->capture_default_str();
  app.add_option("--max-samples-per-s", max_samples_per_s,
                 "frameless: render threads trace at most this many samples a second together "
                 "(0: as fast as they can)")
      ->capture_default_str();
  app.add_option("--render-nice", render_nice,
                 "render threads' nice value above the display's and the window's, 0..19, so those "
                 "get a core as soon as they wake (Linux; docs/engine.md)")
      ->capture_default_str();
  app.add_flag("--temporal,!--no-temporal", temporal,
               "per-pixel temporal blend weight: alpha/2 where samples agree, up to 1 where they "
               "differ (default on)");
  app.add_flag("--closed-loop,!--no-closed-loop", closed_loop,
               "render threads also serve the runs the display asks for (disocclusions, what "
               "moves; default off)");
  app.add_flag("--no-jitter", no_jitter, "sample pixel centres only");
  app.add_flag("--no-packets", no_packets,
               "trace camera rays one by one instead of as 8-ray packets (same image, slower)");
  app.add_flag("--denoise", denoise,
               "show the image through an edge-avoiding a-trous filter guided by normals, positions "
               "and albedo (for noisy light: --integrator path or igi)");
  app.add_flag("--no-discontinuity", no_discontinuity,
               "igi: show the indirect light without OpenRT's discontinuity buffer (the same-surface "
               "average over the interleaving pattern's n x n window)");
  app.add_flag("--adaptive", adaptive,
               "adaptive frameless sampling: skip converged pixels (at most 7 visits in a row)");
}

bool EngineFlags::apply(EngineConfig& e, BlendConfig& blend, std::string& error) const {
  const auto parsed = parse_render_mode(mode);
  if (!parsed) {
    error = "--mode: expected frameless or conventional, got '" + mode + "'";
    return false;
  }
  if (!(alpha > 0.0f && alpha <= 1.0f)) {
    error = "--alpha: must be in (0, 1]";
    return false;
  }
  if (!(reproject_budget >= 0.0f && reproject_budget <= 1.0f)) {
    error = "--reproject-budget: must be in [0, 1]";
    return false;
  }
  if (!(max_samples_per_s >= 0.0 && max_samples_per_s < 1e12)) {
    error = "--max-samples-per-s: must be 0 (no cap) or positive";
    return false;
  }
  if (render_nice < 0 || render_nice > kMaxRenderNice) {
    error = "--render-nice: must be 0..19";
    return false;
  }
  e.mode = *parsed;
  e.threads = threads > 0 ? threads : hardware_threads();
  e.chunk_size = chunk;
  e.update_percent = update_percent;
  e.seed = seed;
  e.jitter = !no_jitter;
  e.packets = !no_packets;
  e.adaptive.enabled = adaptive;  // converged pixels skipped (docs/adaptive.md)
  e.closed_loop = closed_loop;
  blend.alpha = alpha;
  blend.time_decay = time_decay;
  blend.reproject = reproject;
  blend.reproject_budget = reproject_budget;
  e.max_samples_per_s = max_samples_per_s;
  e.render_nice = render_nice;
  blend.temporal = temporal;
  blend.denoise = denoise;
  blend.discontinuity = !no_discontinuity;
  if (denoise) e.track_variance = true;  // the filter's luminance weights read it
  return true;
}

}  // namespace frameless::cli
