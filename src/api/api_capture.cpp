// Headless captures and the statistics of the pixel-update distribution through the public API.
#include <cmath>

#include "api/api_impl.h"
#include "display/camera_path.h"
#include "display/capture.h"
#include "frameless/stats_analysis.h"
#include "frameless/stats_run.h"

namespace frameless::api {

Result<CaptureInfo> capture(const Scene& scene, const CaptureOptions& o) {
  return guarded<CaptureInfo>([&]() -> Result<CaptureInfo> {
    const ::frameless::Scene& s = *scene.impl().scene;
    if (o.out_dir.empty()) return Result<CaptureInfo>::failure("out_dir: a folder for the frames is needed");
    if (!(o.duration > 0.0 && o.duration <= 3600.0)) return Result<CaptureInfo>::failure("duration: must be in (0, 3600] seconds");
    if (!(o.refresh_hz >= 1.0 && o.refresh_hz <= 240.0)) return Result<CaptureInfo>::failure("refresh_hz: must be in [1, 240]");
    if (!std::isfinite(o.orbit_degrees)) return Result<CaptureInfo>::failure("orbit_degrees: must be finite");
    const auto mode = parse_render_mode(o.mode);
    if (!mode) return Result<CaptureInfo>::failure("mode: expected frameless or conventional, got '" + o.mode + "'");
    if (o.width < 0 || o.height < 0 || o.width > 16384 || o.height > 16384)
      return Result<CaptureInfo>::failure("size: width and height must be 1..16384");
    ::frameless::CaptureOptions c;
    c.out_dir = o.out_dir;
    c.duration = o.duration;
    c.refresh_hz = o.refresh_hz;
    c.engine.width = o.width > 0 ? o.width : s.settings.width;
    c.engine.height = o.height > 0 ? o.height : s.settings.height;
    c.engine.threads = o.threads;
    c.engine.mode = *mode;
    c.engine.deterministic = o.deterministic;
    c.engine.samples_per_tick = uint64_t(c.engine.width) * uint64_t(c.engine.height);
    c.blend.alpha = 0.5f;
    c.blend.reproject = *mode == RenderMode::frameless;
    c.camera = s.camera;
    if (o.orbit_degrees != 0.0) {
      PathShorthand p;
      p.orbit_deg = o.orbit_degrees;
      c.path = make_shorthand_path(s.camera, p, o.duration);
    }
    c.layers = o.layers;
    c.contact_sheet = o.contact_sheet;
    c.mp4 = false;
    auto r = run_capture(s, c);
    if (!r) return Result<CaptureInfo>::failure(r.error().message);
    return CaptureInfo{r->frames, r->manifest_path, r->contact_sheet_path};
  });
}

Result<UpdateStatistics> update_statistics(const Scene& scene, const UpdateStatisticsOptions& o) {
  return guarded<UpdateStatistics>([&]() -> Result<UpdateStatistics> {
    if (o.width < 1 || o.height < 1 || o.width > 4096 || o.height > 4096)
      return Result<UpdateStatistics>::failure("size: width and height must be 1..4096");
    if (o.threads < 1 || o.threads > 256) return Result<UpdateStatistics>::failure("threads: must be 1..256");
    if (!(o.sweeps >= 1.0 && o.sweeps <= 1000.0)) return Result<UpdateStatistics>::failure("sweeps: must be in [1, 1000]");
    if (!(o.update_percent >= 0.01 && o.update_percent <= 100.0))
      return Result<UpdateStatistics>::failure("update_percent: must be in [0.01, 100]");
    StatsRunConfig c;
    c.width = o.width;
    c.height = o.height;
    c.threads = o.threads;
    c.update_percent = o.update_percent;
    c.seed = o.seed;
    c.sweeps = o.sweeps;
    c.shader = o.shade ? SampleShader{} : flat_shader();  // where pixels update does not depend on shading
    const ::frameless::Scene& s = *scene.impl().scene;
    const UpdateTrace trace = run_for_stats(s, s.camera, c);
    const OrderStats st = analyze_trace(trace);
    UpdateStatistics out;
    out.updates_min = st.uniformity.min;
    out.updates_max = st.uniformity.max;
    out.updates_mean = st.uniformity.mean;
    out.updates_cv = st.uniformity.cv;
    out.chi2 = st.uniformity.chi2.chi2;
    out.chi2_dof = st.uniformity.chi2.dof;
    out.chi2_p = st.uniformity.chi2.p_value;
    out.interval_mean_sweeps = st.temporal.mean_sweeps;
    out.interval_cv = st.temporal.cv;
    out.interval_max_sweeps = st.temporal.max_sweeps;
    out.staleness_measured = st.staleness.measured;
    out.t50_sweeps = st.staleness.t50_sweeps;
    out.t95_sweeps = st.staleness.t95_sweeps;
    out.t100_sweeps = st.staleness.t100_sweeps;
    out.bound_sweeps = st.staleness.bound_sweeps;
    out.thread_pixels = st.balance.pixels;
    out.balanced = st.balance.within_one_chunk;
    return out;
  });
}

}  // namespace frameless::api
