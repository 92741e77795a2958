// The built-in office (issue 28; OpenRT's figure 1): it holds what the figure shows (plug-in
// wood and marble, a bump-mapped mirror, two light slabs of a sculpture, the volume shader's
// phantom, glass, soft shadows), the mirror shows the lightfield, and the phantom's shadow on the
// wall is transparent: darker than without it, not black.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstring>
#include <vector>

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

// One test, one load: the office bakes its two light slabs when it loads (about 12 s under
// ASan), so the scene is checked whole, measured with its lightfields and phantom, then stripped
// of them and measured again.
TEST(OfficeScene, HoldsEverythingOfTheFigureAndTheMirrorShowsTheLightfieldAndThePhantomCastsATransparentShadow) {
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

  // Rays from the camera into the mirror's right half, where the sculpture's image stands, and
  // from the room onto the wood wall where the main light shines through the phantom.
  const Vec3 eye = s->camera.eye;
  std::vector<Vec3> targets;
  for (int i = 0; i < 40; ++i) targets.emplace_back(-0.75f - 0.01f * float(i % 8), 1.0f + 0.1f * float(i / 8), -3.95f);
  const Vec3 from(-3.5f, 0.5f, 1.0f), wall(-4.0f, 0.74f, -1.9f);
  std::vector<Vec3> with;
  for (const Vec3& t : targets) with.push_back(testing::radiance_along(*s, eye, t - eye));
  const Vec3 shaded = testing::radiance_along(*s, from, wall - from);
  // The same scene without its lightfields and volume.
  s->lightfields.clear();
  s->volumes.clear();
  finalize_scene(*s);
  int changed = 0, coloured = 0;
  for (size_t i = 0; i < targets.size(); ++i) {
    const Vec3 without = testing::radiance_along(*s, eye, targets[i] - eye);
    changed += glm::length(with[i] - without) > 0.05f;
    coloured += std::max(with[i].x, with[i].z) > 1.5f * with[i].y;  // the helix's red or blue
  }
  EXPECT_GT(changed, 5);
  EXPECT_GT(coloured, 3);
  // The wood wall behind the phantom: dimmed, not blacked out.
  const Vec3 lit = testing::radiance_along(*s, from, wall - from);
  const float ratio = (shaded.x + shaded.y + shaded.z) / (lit.x + lit.y + lit.z);
  EXPECT_LT(ratio, 0.97f);
  EXPECT_GT(ratio, 0.2f);
}

}  // namespace
}  // namespace frameless
