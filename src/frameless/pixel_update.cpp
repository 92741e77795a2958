// A batch of pixel updates traced together (coherent packets when on), render threads.
#include "frameless/pixel_update.h"

namespace frameless {
namespace render_detail {

void trace_batch(Engine::Impl& e, PacketBatch& b, const CameraBasis& basis, DynamicFrame* world,
                 const WorldState* world_state) {
  const int spu = e.cfg.jitter ? 2 : 1;
  const SampleShader& custom = e.cfg.shader;
  const bool packets = e.cfg.packets && !custom.fn;
  UpdateSamples u[PacketBatch::kMax];
  float px[2 * PacketBatch::kMax], py[2 * PacketBatch::kMax];
  Hit hits[2 * PacketBatch::kMax];
  for (int k = 0; k < b.n; ++k) {
    prepare_samples(e, b.idx[k], b.state[k]->passes.load(std::memory_order_relaxed), u[k]);
    for (int j = 0; j < spu; ++j) px[k * spu + j] = u[k].px[j], py[k * spu + j] = u[k].py[j];
  }
  if (packets) primary_hits(e.scene, basis, b.n * spu, px, py, hits, world);
  for (int k = 0; k < b.n; ++k) {
    if (world && world_state && world->time != b.t[k])
      advance_frame(e.scene, *world_state, b.t[k], *world);
    for (int j = 0; j < spu; ++j)
      b.r[k][j] = custom.fn ? custom.fn(custom.context, basis, u[k].px[j], u[k].py[j], u[k].seed[j])
                            : trace_sample(e.scene, basis, u[k].px[j], u[k].py[j], u[k].seed[j],
                                           world, packets ? &hits[k * spu + j] : nullptr, u[k].index[j]);
  }
}

}  // namespace render_detail
}  // namespace frameless
