// The engine's side of igi's discontinuity buffer: each pixel's mean indirect light is kept with
// the same samples as its colour mean (so it is a part of it), restarts with it, and exists only
// for igi.
#include <gtest/gtest.h>

#include "collecting_sink.h"
#include "core/scene/scene_finalize.h"
#include "core/scenes/builtin_scenes.h"
#include "frameless/engine.h"

namespace frameless {
namespace {

constexpr int kSize = 24;

std::unique_ptr<Scene> cornell(Integrator integrator) {
  auto s = make_cornell();
  s->settings.integrator = integrator;
  finalize_scene(*s);
  return s;
}

EngineConfig config(RenderMode mode) {
  EngineConfig c;
  c.width = c.height = kSize;
  c.threads = 2;
  c.mode = mode;
  c.deterministic = true;
  c.samples_per_tick = kSize * kSize * 2;
  return c;
}

struct Means {
  std::vector<Vec3> colour, indirect;
};

Means collect_means(Engine& e) {
  testing::CollectingSink sink;
  UpdateCursor cursor;
  const CollectResult r = e.collect(cursor, sink);
  Means m;
  if (!r.indirect) return m;
  EXPECT_GT(r.interleave, 1);
  for (int y = 0; y < kSize; ++y)
    for (int x = 0; x < kSize; ++x) {
      PixelSnapshot p;
      e.read_pixel(x, y, p);
      const size_t i = size_t(y) * kSize + size_t(x);
      m.colour.push_back(p.mean);
      m.indirect.push_back(Vec3(r.indirect[i].mean[0].load(), r.indirect[i].mean[1].load(), r.indirect[i].mean[2].load()));
    }
  return m;
}

void expect_indirect_is_part_of_the_mean(RenderMode mode) {
  auto s = cornell(Integrator::kIgi);
  Engine e(*s, config(mode), s->camera);
  for (int k = 0; k < 6; ++k) e.advance(0.05);
  Means m = collect_means(e);
  ASSERT_EQ(m.indirect.size(), size_t(kSize * kSize));
  int lit = 0;
  for (size_t i = 0; i < m.indirect.size(); ++i)
    for (int c = 0; c < 3; ++c) {
      ASSERT_GE(m.indirect[i][c], 0.0f) << i;
      // The same samples in both means: the VPLs' share never exceeds the whole.
      ASSERT_LE(m.indirect[i][c], m.colour[i][c] * 1.0001f + 1e-6f) << i << " channel " << c;
      lit += c == 0 && m.indirect[i][c] > 0.01f * m.colour[i][c] && m.indirect[i][c] > 0.0f;
    }
  EXPECT_GT(lit, kSize * kSize / 2);  // walls and blocks get light that bounced
  // A camera move restarts both means together (were the indirect one to keep its history, the
  // pixels that now see the dark inside of a block would hold more than their colour).
  Camera moved = s->camera;
  moved.eye.x += 1.0f;
  e.publish_camera(moved);
  for (int k = 0; k < 2; ++k) e.advance(0.05);
  m = collect_means(e);
  for (size_t i = 0; i < m.indirect.size(); ++i)
    for (int c = 0; c < 3; ++c) ASSERT_LE(m.indirect[i][c], m.colour[i][c] * 1.0001f + 1e-6f) << i;
}

TEST(IgiEngine, IndirectMeanIsPartOfTheColourMeanFrameless) { expect_indirect_is_part_of_the_mean(RenderMode::frameless); }
TEST(IgiEngine, IndirectMeanIsPartOfTheColourMeanConventional) {
  expect_indirect_is_part_of_the_mean(RenderMode::conventional);
}

TEST(IgiEngine, OtherIntegratorsKeepNoIndirectMeans) {
  auto s = cornell(Integrator::kPath);
  Engine e(*s, config(RenderMode::frameless), s->camera);
  e.advance(0.05);
  testing::CollectingSink sink;
  UpdateCursor cursor;
  const CollectResult r = e.collect(cursor, sink);
  EXPECT_EQ(r.indirect, nullptr);
  EXPECT_EQ(r.interleave, 0);
}

}  // namespace
}  // namespace frameless
