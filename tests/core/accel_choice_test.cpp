// The structure choice (seed section 2): --accel bvh|grid|auto give the same hits, auto's
// trial counts work (so its choice is the same on every run and machine), and the grid steps
// aside for cut-out textures it cannot test.
#include <gtest/gtest.h>

#include "core/base/rng.h"
#include "core/scene/scene_finalize.h"
#include "core/scenes/scene_load.h"

namespace frameless {
namespace {

std::vector<Ray> camera_rays(const Scene& s, int w, int h) {
  std::vector<Ray> rays;
  const CameraBasis b = make_camera_basis(s.camera, w, h);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) rays.push_back(camera_ray(b, x + 0.5f, y + 0.5f));
  return rays;
}

TEST(AccelChoice, EveryStructureGivesTheSameHits) {
  for (const char* spec : {"default", "spheres:2000", "teapot"}) {
    auto scene = load_scene(spec);
    if (!scene && std::string(spec) == "teapot") GTEST_SKIP() << scene.error().message;
    ASSERT_TRUE(scene) << scene.error().message;
    Scene& s = **scene;
    const std::vector<Ray> rays = camera_rays(s, 48, 36);
    std::vector<Hit> reference(rays.size());
    for (size_t i = 0; i < rays.size(); ++i) s.accel.intersect(rays[i], reference[i]);
    for (AccelKind k : {AccelKind::kGrid, AccelKind::kAuto, AccelKind::kBvh}) {
      set_accel(s, k);
      EXPECT_NE(s.accel.stats().structure, AccelKind::kAuto);
      if (k != AccelKind::kAuto) {
        EXPECT_EQ(s.accel.stats().structure, k) << spec;
      }
      int differ = 0;
      for (size_t i = 0; i < rays.size(); ++i) {
        Hit h;
        s.accel.intersect(rays[i], h);
        // The same surface at the same distance (primitive ids may be renumbered by a rebuild).
        differ += h.valid() != reference[i].valid() ||
                  (h.valid() && std::fabs(h.t - reference[i].t) > 1e-4f * reference[i].t);
      }
      EXPECT_EQ(differ, 0) << spec << " " << accel_kind_name(k);
    }
  }
}

TEST(AccelChoice, AutoTrialCountsWorkNotTimeSoTheChoiceRepeats) {
  auto a = load_scene("spheres:5000");
  ASSERT_TRUE(a) << a.error().message;
  set_accel(**a, AccelKind::kAuto);
  const AccelStats first = (*a)->accel.stats();
  ASSERT_TRUE(first.trial);
  EXPECT_GE(first.trial_rays, size_t(64 * 48));  // camera rays, plus shadow rays from their hits
  EXPECT_GT(first.bvh_counts.nodes, 0u);
  EXPECT_GT(first.grid_counts.nodes, 0u);
  for (int k = 0; k < 2; ++k) {
    auto b = load_scene("spheres:5000");
    ASSERT_TRUE(b);
    set_accel(**b, AccelKind::kAuto);
    const AccelStats& again = (*b)->accel.stats();
    EXPECT_EQ(again.bvh_counts.nodes, first.bvh_counts.nodes);
    EXPECT_EQ(again.grid_counts.prims, first.grid_counts.prims);
    EXPECT_EQ(again.structure, first.structure);
  }
  // The choice follows the weighted work: the cheaper structure wins.
  EXPECT_EQ(first.structure, first.grid_cost < first.bvh_cost ? AccelKind::kGrid : AccelKind::kBvh);
}

TEST(AccelChoice, SettingsAndErrors) {
  auto ok = parse_scene_json(R"({"settings": {"accel": "grid"},
      "materials": {"m": {"class": "diffuse"}},
      "objects": [{"type": "sphere", "center": [0, 0, 0], "radius": 1, "material": "m"}]})",
                             "g.json", ".");
  ASSERT_TRUE(ok) << ok.error().message;
  EXPECT_EQ((*ok)->accel.stats().structure, AccelKind::kGrid);
  auto bad = parse_scene_json(R"({"settings": {"accel": "kdtree"},
      "materials": {"m": {"class": "diffuse"}},
      "objects": [{"type": "sphere", "center": [0, 0, 0], "radius": 1, "material": "m"}]})",
                              "g.json", ".");
  ASSERT_FALSE(bad);
  EXPECT_NE(bad.error().message.find("settings.accel"), std::string::npos);
  AccelKind k;
  EXPECT_FALSE(parse_accel_kind("BVH", k));
  EXPECT_TRUE(parse_accel_kind("auto", k));
  EXPECT_EQ(k, AccelKind::kAuto);
}

TEST(AccelChoice, CutOutsKeepTheBvh) {
  auto scene = load_scene("showcase");  // has a cut-out texture
  if (!scene) GTEST_SKIP() << scene.error().message;
  set_accel(**scene, AccelKind::kGrid);
  EXPECT_EQ((*scene)->accel.stats().structure, AccelKind::kBvh);
}

}  // namespace
}  // namespace frameless
