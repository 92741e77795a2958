// Recording runs for the update statistics: deterministic (virtual clock) or wall clock.
#include "frameless/stats_run.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <stdexcept>
#include <thread>

#include "frameless/engine.h"

namespace frameless {
namespace {

SampleResult flat_sample(const void*, const CameraBasis&, float, float, uint64_t) {
  SampleResult r;
  r.color = Vec3(0.5f);
  r.depth = 1.0f;
  return r;
}

}  // namespace

EngineConfig engine_config(const StatsRunConfig& c) {
  EngineConfig e;
  e.width = c.width;
  e.height = c.height;
  e.threads = c.threads;
  e.chunk_size = c.chunk_size;
  e.update_percent = c.update_percent;
  e.seed = c.seed;
  e.order = c.order;
  e.deterministic = c.deterministic;
  e.shader = c.shader;
  return e;
}

namespace {

void check(const Engine& engine) {
  if (auto err = engine.error()) throw std::runtime_error(*err);
}

// Copies logs and counters out of a quiescent engine.
void collect(const Engine& engine, UpdateTrace& t) {
  const Partition& p = engine.partition();
  const EngineStats st = engine.stats();
  for (int i = 0; i < engine.thread_count(); ++i) {
    const UpdateLog& log = engine.update_log(i);
    t.logs.push_back(log.records);
    t.overflow += log.overflow;
    t.thread_pixels.push_back(p.pixels[size_t(i)].size());
    t.thread_samples_per_s.push_back(size_t(i) < st.threads.size() ? st.threads[size_t(i)].samples_per_s : 0.0);
    t.thread_busy_s.push_back(size_t(i) < st.threads.size() ? st.threads[size_t(i)].busy_seconds : 0.0);
  }
  t.samples_per_s = st.samples_per_s;
  t.run_seconds = st.seconds;
}

}  // namespace

SampleShader flat_shader() {
  SampleShader s;
  s.fn = &flat_sample;
  return s;
}

Camera moved_camera(const Camera& camera) {
  Camera c = camera;
  const Vec3 d = camera.look - camera.eye;
  const float dist = std::max(1e-3f, std::sqrt(d.x * d.x + d.y * d.y + d.z * d.z));
  c.eye.x += 0.1f * dist;
  return c;
}

UpdateTrace run_for_stats(const Scene& scene, const Camera& camera, const StatsRunConfig& c) {
  UpdateTrace t;
  t.width = c.width;
  t.height = c.height;
  t.chunk_size = c.chunk_size;
  t.order = c.order;
  t.seed = c.seed;
  t.update_percent = c.update_percent;
  EngineConfig ec = engine_config(c);
  const uint64_t n = uint64_t(c.width) * uint64_t(c.height);
  const double tick = 1.0 / c.refresh_hz;

  if (c.deterministic) {
    const uint64_t spu = uint64_t(samples_per_update(ec));
    const uint64_t tps = uint64_t(std::max(1, c.ticks_per_sweep));
    ec.samples_per_tick = std::max<uint64_t>(spu, n * spu / tps);
    const uint64_t per_tick = std::max<uint64_t>(1, ec.samples_per_tick / spu);  // as Engine::advance
    const double ticks_per_sweep = double(n) / double(per_tick);
    const double bound = 1.0 + c.update_percent / 100.0;
    const double length = c.change_at >= 0 ? std::max(c.sweeps, c.change_at + bound + 0.25) : c.sweeps;
    const uint64_t ticks = uint64_t(std::ceil(length * ticks_per_sweep));
    const int threads = std::max(1, c.threads);
    // Largest share: a thread owns at most ceil(n / threads) + one chunk pixels.
    const uint64_t most = (n + uint64_t(threads) - 1) / uint64_t(threads) + uint64_t(c.chunk_size);
    ec.update_log_capacity = size_t(ticks * per_tick * most / n + 16);
    Engine engine(scene, ec, camera);
    const int64_t change_tick = c.change_at >= 0 ? int64_t(std::llround(c.change_at * ticks_per_sweep)) : -1;
    for (uint64_t k = 0; k < ticks; ++k) {
      if (int64_t(k) == change_tick) {
        t.change_time = engine.now();
        t.change_epoch = engine.publish_camera(moved_camera(camera));
      }
      engine.note_display_tick(uint32_t(k));
      engine.advance(tick);
      check(engine);
    }
    t.sweep_seconds = ticks_per_sweep * tick;
    t.mask_ticks_begin = 0;
    t.mask_ticks_end = uint32_t(std::min<uint64_t>({ticks, 64, uint64_t(std::floor(ticks_per_sweep))}));
    collect(engine, t);
    engine.stop();
    return t;
  }

  ec.update_log_capacity = std::max<size_t>(1024, c.max_log_records / size_t(std::max(1, c.threads)));
  Engine engine(scene, ec, camera);
  engine.note_display_tick(0);
  engine.start();
  const auto t0 = std::chrono::steady_clock::now();
  const double change_s = c.change_at >= 0 ? c.duration / 3.0 : -1.0;
  uint32_t k = 0;
  for (;;) {
    const double elapsed = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    if (elapsed >= c.duration || engine.error()) break;
    if (change_s >= 0 && t.change_time < 0 && elapsed >= change_s) {
      t.change_time = engine.now();
      t.change_epoch = engine.publish_camera(moved_camera(camera));
    }
    std::this_thread::sleep_until(t0 + std::chrono::duration<double>(tick * (k + 1)));
    engine.note_display_tick(++k);
  }
  engine.stop();
  check(engine);
  collect(engine, t);
  uint64_t updates = t.overflow;
  for (const auto& log : t.logs) updates += log.size();
  t.sweep_seconds = updates > 0 ? t.run_seconds * double(n) / double(updates) : 0.0;
  // Masks: whole intervals (not the first or last), at most one sweep's worth.
  const uint32_t per_sweep = uint32_t(std::clamp(t.sweep_seconds * c.refresh_hz, 1.0, 64.0));
  t.mask_ticks_begin = 1;
  t.mask_ticks_end = std::max<uint32_t>(1, std::min<uint32_t>(k, 1 + per_sweep));
  return t;
}

double measure_samples_per_s(const Scene& scene, const Camera& camera, const StatsRunConfig& c,
                             double seconds) {
  EngineConfig ec = engine_config(c);
  ec.deterministic = false;
  Engine engine(scene, ec, camera);
  engine.start();
  std::this_thread::sleep_for(std::chrono::duration<double>(seconds));
  const EngineStats st = engine.stats();
  engine.stop();
  check(engine);
  return st.samples_per_s;
}

}  // namespace frameless
