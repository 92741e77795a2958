// The headless OSMesa path: the GL presenter's float readback equals the image it was given,
// the false-colour views and the overlay draw, and the presenter survives resizes.
#include <gtest/gtest.h>

#include "core/base/rng.h"
#include "display/gl_presenter.h"
#include "display/osmesa_context.h"

namespace frameless {
namespace {

DisplayImage random_image(int w, int h, uint64_t seed) {
  DisplayImage img;
  img.width = w, img.height = h;
  Rng rng(seed);
  const size_t n = size_t(w) * h;
  img.rgb.resize(n * 3);
  // Values well outside [0, 1] too: the capture path must not clamp radiance.
  for (float& v : img.rgb) v = rng.next_float() * 4.0f - 0.5f;
  img.last_update.assign(n, 0.5f);
  img.sample_count.assign(n, 3);
  img.variance.assign(n, 0.01f);
  img.epoch.assign(n, 2);
  img.info.newest_epoch = 2;
  img.info.virtual_time = 1.0;
  for (size_t i = 0; i < n; i += 7) img.epoch[i] = 1;
  return img;
}

struct Gl {
  std::unique_ptr<OsMesaContext> ctx;
  std::unique_ptr<GlPresenter> presenter;
};

Gl make_gl(int w, int h) {
  Gl g;
  auto ctx = OsMesaContext::create(w, h);
  EXPECT_TRUE(ctx.ok()) << (ctx.ok() ? "" : ctx.error().message);
  if (!ctx.ok()) return g;
  g.ctx = std::move(ctx.value());
  auto p = GlPresenter::create(&OsMesaContext::proc_address);
  EXPECT_TRUE(p.ok()) << (p.ok() ? "" : p.error().message);
  if (p.ok()) g.presenter = std::move(p.value());
  return g;
}

TEST(OsMesaReadback, FloatReadbackEqualsTheImageBitForBit) {
  Gl g = make_gl(64, 48);
  ASSERT_TRUE(g.presenter);
  for (auto [w, h] : {std::pair{64, 48}, std::pair{37, 21}, std::pair{1, 1}}) {
    const DisplayImage img = random_image(w, h, uint64_t(w * 1000 + h));
    g.presenter->upload(img, ViewMode::shaded);
    std::vector<float> back;
    auto r = g.presenter->render_linear(back);
    ASSERT_TRUE(r.ok()) << r.error().message;
    ASSERT_EQ(back.size(), img.rgb.size());
    size_t mismatches = 0;
    for (size_t i = 0; i < back.size(); ++i) mismatches += back[i] != img.rgb[i];
    EXPECT_EQ(mismatches, 0u) << w << "x" << h << " (row order or filtering broken?)";
  }
  std::fprintf(stderr, "renderer: %s\n", g.presenter->renderer().c_str());
}

TEST(OsMesaReadback, ReadbackDetectsAChangedPixel) {
  // The comparison above can fail: one changed texel shows up at the right place.
  Gl g = make_gl(16, 8);
  ASSERT_TRUE(g.presenter);
  DisplayImage img = random_image(16, 8, 5);
  img.rgb[(3 * 16 + 5) * 3 + 1] = 42.0f;
  g.presenter->upload(img, ViewMode::shaded);
  std::vector<float> back;
  ASSERT_TRUE(g.presenter->render_linear(back).ok());
  EXPECT_EQ(back[(3 * 16 + 5) * 3 + 1], 42.0f);
  EXPECT_NE(back[(4 * 16 + 5) * 3 + 1], 42.0f);
}

// The shaded view (the default) reads only the colour and the epochs: it gives the coverage the
// other views give and leaves their scales at 0. A view shown after the image changed size while
// the shaded one was up gets its layer texture at the new size: what a fresh presenter shows.
TEST(OsMesaReadback, TheShadedViewLeavesTheLayersToTheViewsThatShowThem) {
  DisplayImage small = random_image(32, 24, 4);
  for (size_t i = 0; i < small.sample_count.size(); ++i) small.sample_count[i] = uint32_t(i % 50);
  std::vector<float> fresh, back;
  {
    Gl h = make_gl(32, 24);
    ASSERT_TRUE(h.presenter);
    h.presenter->upload(small, ViewMode::count);
    ASSERT_TRUE(h.presenter->render_linear(fresh).ok());
  }
  Gl g = make_gl(64, 48);
  ASSERT_TRUE(g.presenter);
  DisplayImage big = random_image(64, 48, 3);
  big.epoch[10] = big.epoch[20] = 5;  // newer than info.newest_epoch (2): the coverage counts these
  const ViewScale shaded = g.presenter->upload(big, ViewMode::shaded);
  const ViewScale count = g.presenter->upload(big, ViewMode::count);
  EXPECT_DOUBLE_EQ(shaded.coverage, 2.0 / (64.0 * 48.0));
  EXPECT_EQ(shaded.coverage, count.coverage);
  EXPECT_EQ(shaded.max_count, 0.0f);
  EXPECT_EQ(count.max_count, 3.0f);
  g.presenter->upload(small, ViewMode::shaded);
  g.presenter->upload(small, ViewMode::count);
  ASSERT_TRUE(g.presenter->render_linear(back).ok());
  EXPECT_TRUE(back == fresh);
}

TEST(OsMesaReadback, ViewsAndOverlayDrawSomething) {
  Gl g = make_gl(64, 48);
  ASSERT_TRUE(g.presenter);
  const DisplayImage img = random_image(64, 48, 9);
  for (int m = 0; m < kViewModeCount; ++m) {
    const ViewScale s = g.presenter->upload(img, ViewMode(m));
    EXPECT_NEAR(s.coverage, 1.0 - std::ceil(64.0 * 48 / 7) / (64.0 * 48), 1e-9);
    std::vector<float> back;
    ASSERT_TRUE(g.presenter->render_linear(back).ok());
    double sum = 0;
    for (float v : back) sum += v;
    EXPECT_GT(sum, 0.0) << to_string(ViewMode(m));
  }
  // Text on a black screen lights some pixels, and only near the top-left corner.
  DisplayImage black = img;
  std::fill(black.rgb.begin(), black.rgb.end(), 0.0f);
  g.presenter->upload(black, ViewMode::shaded);
  g.presenter->draw(64, 48, true);
  g.presenter->draw_text({"Hi"}, 64, 48);
  std::vector<unsigned char> px;
  g.presenter->read_rgb8(64, 48, px);
  int lit = 0, lit_far = 0;
  for (int y = 0; y < 48; ++y)
    for (int x = 0; x < 64; ++x)
      if (px[(size_t(y) * 64 + x) * 3] > 128) (x < 30 && y < 30 ? lit : lit_far)++;
  EXPECT_GT(lit, 10);
  EXPECT_EQ(lit_far, 0);
}

}  // namespace
}  // namespace frameless
