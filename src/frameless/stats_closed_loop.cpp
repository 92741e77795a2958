#include "frameless/stats_closed_loop.h"

#include <algorithm>
#include <stdexcept>

#include "frameless/engine.h"

namespace frameless {
namespace {

// The display's stand-in: asks for every slot holding a pixel of the top half, each collection.
struct TopHalfAsker final : UpdateSink {
  size_t limit = 0;  // pixels below this index are asked for
  void begin(const CollectResult& r) override {
    if (!r.wanted || !r.slot_pixel) return;
    const std::vector<uint32_t>& order = *r.slot_pixel;
    for (size_t s = 0; s < order.size(); ++s)
      if (order[s] < limit) r.wanted->want(s);
    r.wanted->publish();
  }
  void slots(size_t, const PixelState*, size_t) override {}
  void frame(const std::vector<PixelSnapshot>&) override {}
};

}  // namespace

ClosedLoopStats closed_loop_stats(const Scene& scene, const Camera& camera, const StatsRunConfig& c) {
  EngineConfig ec = engine_config(c);
  ec.threads = std::max(1, c.threads);
  ec.deterministic = true;
  ec.closed_loop = true;
  ec.shader = flat_shader();
  const uint64_t n = uint64_t(c.width) * uint64_t(c.height);
  const uint64_t spu = uint64_t(samples_per_update(ec));
  const uint64_t tps = uint64_t(std::max(1, c.ticks_per_sweep));
  ec.samples_per_tick = std::max<uint64_t>(spu, n * spu / tps);
  const double sweeps = std::max(4.0, c.sweeps);
  const uint64_t ticks = uint64_t(sweeps * double(tps)) + 1;
  const uint64_t most = (n + uint64_t(ec.threads) - 1) / uint64_t(ec.threads) + uint64_t(c.chunk_size);
  ec.update_log_capacity = size_t(ticks * (ec.samples_per_tick / spu + 1) * most / n + 64);
  Engine engine(scene, ec, camera);
  engine.start();
  UpdateCursor cursor;
  TopHalfAsker asker;
  asker.limit = size_t(n / 2);
  for (uint64_t k = 0; k < ticks; ++k) {
    engine.collect(cursor, asker);
    engine.advance(1.0 / c.refresh_hz);
    if (engine.error()) throw std::runtime_error(*engine.error());
  }
  engine.stop();
  ClosedLoopStats out;
  out.asked_fraction = double(n / 2) / double(n);
  out.sweeps = sweeps;
  const std::vector<std::vector<uint32_t>>& lists = engine.partition().pixels;
  for (int t = 0; t < ec.threads; ++t) {
    const UpdateLog& log = engine.update_log(t);
    ClosedLoopStats::Thread th;
    th.pixels = lists[size_t(t)].size();
    th.updates = log.records.size();
    th.bound = 2 * th.pixels + 2 * kRunLength;
    std::vector<size_t> last(n, ~size_t(0));
    size_t asked = 0;
    for (size_t k = 0; k < log.records.size(); ++k) {
      const uint32_t p = log.records[k].pixel;
      const size_t gap = last[p] == ~size_t(0) ? k + 1 : k - last[p];
      th.worst_gap = std::max(th.worst_gap, gap);
      last[p] = k;
      asked += p < n / 2;
    }
    for (uint32_t p : lists[size_t(t)]) {
      if (last[p] == ~size_t(0)) ++th.never_updated;
      else th.worst_gap = std::max(th.worst_gap, log.records.size() - last[p]);  // still waiting at the end
    }
    th.asked_share = th.updates ? double(asked) / double(th.updates) : 0.0;
    out.bound_holds = out.bound_holds && th.worst_gap <= th.bound && th.never_updated == 0;
    out.threads.push_back(th);
  }
  return out;
}

}  // namespace frameless
