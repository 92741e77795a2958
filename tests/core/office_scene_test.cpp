// The built-in office (issue 28; OpenRT's figure 1): it holds what the figure shows (plug-in
// wood and marble, a bump-mapped mirror, two light slabs of a sculpture, the volume shader's
// phantom, glass, soft shadows), the mirror shows the lightfield, and the phantom's shadow on the
// wall is transparent: darker than without it, not black.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstring>

#include "core/scene/scene_finalize.h"
#include "core/scenes/scene_load.h"
#include "shading_scenes.h"

namespace frameless {
namespace {

std::unique_ptr<Scene> office() {
  auto s = load_scene("office");
  EXPECT_TRUE(s) << s.error().message;
  return s ? std::move(*s) : nullptr;
}

TEST(OfficeScene, HoldsEverythingOfTheFigure) {
  auto s = office();
  ASSERT_TRUE(s);
  EXPECT_EQ(s->lightfields.size(), 2u);
  ASSERT_EQ(s->volumes.size(), 1u);
  EXPECT_EQ(s->volumes[0].mode, VolumeMode::kDirect);
  EXPECT_TRUE(s->see_through);
  EXPECT_EQ(s->settings.shadows, ShadowMode::kSoft);
  bool wood = false, marble = false, bumped_mirror = false, glass = false;
  for (const ShaderMaterial& m : s->shaders) {
    wood |= std::strcmp(m.shader->name, "wood") == 0;
    marble |= std::strcmp(m.shader->name, "marble") == 0;
  }
  for (const Material& m : s->materials) {
    bumped_mirror |= m.cls == MaterialClass::kMetal && m.bump_tex != kNoTexture;
    glass |= m.cls == MaterialClass::kDielectric;
  }
  EXPECT_TRUE(wood && marble && bumped_mirror && glass);
}

TEST(OfficeScene, TheMirrorShowsTheLightfieldAndThePhantomCastsATransparentShadow) {
  auto s = office();
  ASSERT_TRUE(s);
  auto bare = office();
  bare->lightfields.clear();
  bare->volumes.clear();
  finalize_scene(*bare);
  // Rays from the camera into the mirror's right half, where the sculpture's image stands.
  const Vec3 eye = s->camera.eye;
  int changed = 0, coloured = 0;
  for (int i = 0; i < 40; ++i) {
    const Vec3 target(-0.75f - 0.01f * float(i % 8), 1.0f + 0.1f * float(i / 8), -3.95f);
    const Vec3 with = testing::radiance_along(*s, eye, target - eye), without = testing::radiance_along(*bare, eye, target - eye);
    changed += glm::length(with - without) > 0.05f;
    coloured += std::max(with.x, with.z) > 1.5f * with.y;  // the helix's red or blue
  }
  EXPECT_GT(changed, 5);
  EXPECT_GT(coloured, 3);
  // The wood wall where the main light shines through the phantom: dimmed, not blacked out.
  const Vec3 from(-3.5f, 0.5f, 1.0f), wall(-4.0f, 0.74f, -1.9f);
  const Vec3 shaded = testing::radiance_along(*s, from, wall - from), lit = testing::radiance_along(*bare, from, wall - from);
  const float ratio = (shaded.x + shaded.y + shaded.z) / (lit.x + lit.y + lit.z);
  EXPECT_LT(ratio, 0.97f);
  EXPECT_GT(ratio, 0.2f);
}

}  // namespace
}  // namespace frameless
