// Baking a light slab (frameless/lightfield_bake.h): the views cover the model (alpha 1 where
// the lines meet it, 0 where they miss), the bake is the same on any number of threads, and from a
// novel viewpoint inside the slab's range the baked slab alone looks like the model rendered
// directly, while a slab placed a little off does not.
#include <gtest/gtest.h>

#include <memory>
#include <thread>

#include "core/io/scene_json.h"
#include "core/scene/scene_finalize.h"
#include "frameless/image_error.h"
#include "core/shading/lightfield_bake.h"
#include "frameless/tile_render.h"

namespace frameless {
namespace {

std::unique_ptr<Scene> model() {
  auto s = parse_scene_json(
      R"({"camera":{"eye":[0,0,6],"look":[0,0,0]},"settings":{"background":[0.1,0.1,0.2],"shadows":"hard"},
          "ambient":{"type":"constant","color":0.1},
          "lights":[{"type":"point","position":[4,5,6],"color":0.9}],
          "materials":{"a":{"class":"diffuse","kd":[0.8,0.3,0.2]},"b":{"class":"polished","kd":[0.2,0.5,0.8],"kh":0.3,"phong_exponent":30}},
          "objects":[{"type":"sphere","center":[-0.4,0,0],"radius":0.6,"material":"a"},
                     {"type":"sphere","center":[0.5,0.3,0.2],"radius":0.4,"material":"b"}]})",
      "model.json", "/nonexistent");
  EXPECT_TRUE(s) << s.error().message;
  return std::move(*s);
}

std::vector<float> render(const Scene& s, const Camera& c) {
  TileRenderOptions o;
  o.spp = 1;
  o.jitter = false;
  return render_tiles(s, make_camera_basis(c, 64, 64), o).rgb;
}

std::unique_ptr<Scene> slab_only(const Scene& m, std::shared_ptr<const LightField> lf, const Affine& where) {
  auto s = std::make_unique<Scene>();
  s->settings = m.settings;
  s->lightfields.push_back(place_lightfield(std::move(lf), where));
  finalize_scene(*s);
  return s;
}

TEST(LightfieldBake, ViewsCoverTheModelAndMatchItFromNovelViewpoints) {
  auto m = model();
  Affine slab;
  ASSERT_TRUE(slab_around_scene(*m, slab));
  EXPECT_GT(slab.m[2].z, 0.99f * glm::length(slab.m[2])) << "z faces the camera on +z";
  LightfieldBakeOptions o;
  o.nu = o.nv = 8;
  o.ns = o.nt = 48;
  o.spp = 4;
  auto lf = std::make_shared<LightField>(bake_lightfield(*m, slab, o));
  ASSERT_EQ(check_lightfield(*lf), "");
  // The middle of the middle view meets the model; the corners of the st plane miss it.
  EXPECT_NEAR(lf->texel(4, 4, 24, 24).alpha, 1.0f, 1e-3f);
  EXPECT_EQ(lf->texel(4, 4, 0, 0).alpha, 0.0f);
  EXPECT_EQ(lf->texel(0, 7, 47, 0).rgb, Vec3(0.0f));
  // Views baked in any order, at once: the same table.
  const ParallelFor backwards_in_pairs = [](size_t n, const std::function<void(size_t)>& body) {
    for (size_t k = n; k > 0; k -= std::min<size_t>(k, 2)) {
      std::thread other([&] { body(k - 1); });
      if (k >= 2) body(k - 2);
      other.join();
    }
  };
  EXPECT_EQ(bake_lightfield(*m, slab, o, backwards_in_pairs).rgba, lf->rgba);

  const float eyes[][3] = {{0.13f, 0.07f, 3.0f}, {-0.4f, 0.25f, 2.4f}};
  for (const auto& e : eyes) {
    Camera c;
    c.eye = slab.point(Vec3(e[0], e[1], e[2]));
    c.look = slab.t;
    c.fov_deg = 40.0f;
    const std::vector<float> direct = render(*m, c);
    const double good = image_error(render(*slab_only(*m, lf, Affine{}), c), direct, 64 * 64).rmse;
    Affine off;
    off.t = Vec3(0.08f, 0.0f, 0.0f);  // the same slab, a tenth of the small sphere's size aside
    const double bad = image_error(render(*slab_only(*m, lf, off), c), direct, 64 * 64).rmse;
    EXPECT_LT(good, 0.04) << e[0];
    EXPECT_GT(bad, 2.0 * good) << e[0];
  }
}

}  // namespace
}  // namespace frameless
