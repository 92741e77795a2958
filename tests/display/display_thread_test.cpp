// Display thread: deterministic reproduction, no NaN/Inf displayed, coverage, conventional frames
// shown only when complete, the triple-buffer hand-off (an untaken image blended into again)
// and layout changes (the wall-clock run
// with real threads is tests/exchange).
#include "display/display_thread.h"

#include <gtest/gtest.h>

#include <atomic>
#include <chrono>
#include <cmath>
#include <cstring>
#include <thread>

#include "../engine/test_shaders.h"

namespace frameless {
namespace {

using namespace frameless::testing;

bool same_bits(const DisplayImage& a, const DisplayImage& b) {
  auto eq = [](const auto& x, const auto& y) {
    return x.size() == y.size() && std::memcmp(x.data(), y.data(), x.size() * sizeof(x[0])) == 0;
  };
  return a.width == b.width && a.height == b.height && eq(a.rgb, b.rgb) &&
         eq(a.last_update, b.last_update) && eq(a.sample_count, b.sample_count) &&
         eq(a.variance, b.variance) && eq(a.epoch, b.epoch);
}

EngineConfig deterministic_config(RenderMode mode, uint64_t seed, SampleResult (*fn)(const void*, const CameraBasis&, float, float, uint64_t) = noisy_shader) {
  EngineConfig c = test_config(48, 36, 3, fn);
  c.deterministic = true;
  c.mode = mode;
  c.seed = seed;
  c.samples_per_tick = 900;
  return c;
}

std::vector<DisplayImage> run_deterministic(RenderMode mode, uint64_t seed, int ticks) {
  Engine e(kEmptyScene, deterministic_config(mode, seed), camera_at(0));
  DisplayThread d(e, {});
  std::vector<DisplayImage> frames;
  for (int k = 0; k < ticks; ++k) {
    if (k == 8) e.publish_camera(camera_at(0.3f));
    d.step();
    frames.push_back(d.acquire_latest());
  }
  return frames;
}

TEST(DisplayThread, DeterministicRunsGiveIdenticalImages) {
  for (RenderMode mode : {RenderMode::frameless, RenderMode::conventional}) {
    const auto a = run_deterministic(mode, 3, 20);
    const auto b = run_deterministic(mode, 3, 20);
    const auto c = run_deterministic(mode, 4, 20);
    for (size_t k = 0; k < a.size(); ++k) {
      EXPECT_TRUE(same_bits(a[k], b[k])) << to_string(mode) << " tick " << k;
      EXPECT_EQ(a[k].info.virtual_time, b[k].info.virtual_time);
    }
    EXPECT_FALSE(same_bits(a.back(), c.back())) << "the comparison must be able to fail";
  }
}

TEST(DisplayThread, NonFiniteSamplesNeverDisplayed) {
  for (RenderMode mode : {RenderMode::frameless, RenderMode::conventional}) {
    Engine e(kEmptyScene, deterministic_config(mode, 1, nan_shader), camera_at(0));
    DisplayThread d(e, {});
    FrameInfo info;
    for (int k = 0; k < 15; ++k) info = d.step();
    const DisplayImage& img = d.acquire_latest();
    ASSERT_EQ(img.rgb.size(), size_t(3 * 48 * 36));
    for (float v : img.rgb) ASSERT_TRUE(std::isfinite(v));
    EXPECT_GT(info.dropped_samples, 0u);
  }
}

TEST(DisplayThread, CoverageRisesToOneAfterACameraChange) {
  Engine e(kEmptyScene, deterministic_config(RenderMode::frameless, 1), camera_at(0));
  DisplayThread d(e, {});
  for (int k = 0; k < 10; ++k) d.step();
  EXPECT_DOUBLE_EQ(d.step().coverage, 1.0);
  e.publish_camera(camera_at(0.5f));
  double last = 0.0;
  int ticks = 0;
  for (; ticks < 100 && last < 1.0; ++ticks) {
    const FrameInfo info = d.step();
    EXPECT_GE(info.coverage, last);
    last = info.coverage;
  }
  EXPECT_DOUBLE_EQ(last, 1.0);
  // 900 samples per tick = 450 updates over 1728 pixels: 4 ticks a sweep, plus the pickup delay.
  EXPECT_LE(ticks, 6);
}

TEST(DisplayThread, ConventionalShowsOnlyCompletedFrames) {
  EngineConfig c = deterministic_config(RenderMode::conventional, 1);
  c.samples_per_tick = 1000;  // 500 pixel updates per tick: a frame takes several ticks
  Engine e(kEmptyScene, c, camera_at(0));
  DisplayThread d(e, {});
  int frames = 0;
  for (int k = 0; k < 20; ++k) {
    if (k == 5) e.publish_camera(camera_at(0.5f));
    const FrameInfo info = d.step();
    const DisplayImage& img = d.acquire_latest();
    EXPECT_TRUE(info.pixels_updated == 0 || info.pixels_updated == img.pixels());
    if (info.pixels_updated) ++frames;
    // Every displayed pixel comes from the same frame: one epoch everywhere.
    for (uint32_t ep : img.epoch) EXPECT_EQ(ep, img.epoch[0]);
  }
  EXPECT_GE(frames, 4);
}

TEST(DisplayThread, StillImageShowsTheRunningMean) {
  EngineConfig c = deterministic_config(RenderMode::frameless, 1);
  c.track_variance = true;  // off by default: this test reads it
  Engine e(kEmptyScene, c, camera_at(0));
  DisplayThread d(e, {});
  for (int k = 0; k < 40; ++k) d.step();
  const DisplayImage& img = d.acquire_latest();
  PixelSnapshot p;
  ASSERT_TRUE(e.read_pixel(10, 20, p));
  const size_t i = 20 * 48 + 10;
  EXPECT_EQ(img.rgb[3 * i], p.mean.x);
  EXPECT_EQ(img.sample_count[i], p.count);
  EXPECT_GT(img.variance[i], 0.0f);
  EXPECT_LT(img.age(i), 1.0f);
}

// The consumer's image is patched from each image's change history when it covers the ticks
// since the last image taken, and rebuilt otherwise; the on-tick image is patched from each
// tick's change list. Both must equal each other bit for bit whatever the consumer skips, across
// camera changes, a new partition (every pixel changes slot) and mode switches.
TEST(DisplayThread, TripleBufferMatchesTheTickImage) {
  EngineConfig c = deterministic_config(RenderMode::frameless, 1);
  c.samples_per_tick = 120;  // a tick changes a few runs, not the whole image: patching applies
  Engine e(kEmptyScene, c, camera_at(0));
  DisplayThread d(e, {});
  DisplayImage seen;
  d.set_on_tick([&](const DisplayImage& img) { seen = img; });
  int taken = 0;
  for (int k = 0, skip = 0; k < 60; ++k) {
    if (k == 10) e.publish_camera(camera_at(0.5f));
    if (k == 25) e.set_threads(2);
    if (k == 40) e.set_mode(RenderMode::conventional);
    if (k == 50) e.set_mode(RenderMode::frameless);
    d.step();
    if (skip-- > 0) continue;  // the consumer skips 0..11 ticks (more than the history holds)
    skip = (k * 7) % 12;
    bool fresh = false;
    const DisplayImage& img = d.acquire_latest(&fresh);
    EXPECT_TRUE(fresh);
    EXPECT_TRUE(same_bits(img, seen)) << "tick " << k;
    EXPECT_EQ(img.info.index, uint64_t(k));
    ++taken;
  }
  EXPECT_GT(taken, 10);
  EXPECT_TRUE(same_bits(d.acquire_latest(), seen));  // the last tick, after a skip
  bool fresh = true;
  d.acquire_latest(&fresh);
  EXPECT_FALSE(fresh);
}

// With nobody taking images (headless runs, captures), each tick after the first kHistory (8)
// blends into the newest image again instead of copying it into another buffer (after a
// reprojection: the whole image); a consumer that takes every image gets no such tick. Both show
// the same image.
TEST(DisplayThread, AnUntakenImageIsBlendedIntoAgainNotCopied) {
  DisplayConfig dc;
  dc.blend.reproject = true;
  Engine alone(kEmptyScene, deterministic_config(RenderMode::frameless, 5), camera_at(0));
  Engine watched(kEmptyScene, deterministic_config(RenderMode::frameless, 5), camera_at(0));
  DisplayThread a(alone, dc), b(watched, dc);
  DisplayImage taken;
  for (int k = 0; k < 20; ++k) {
    if (k == 8 || k == 12) alone.publish_camera(camera_at(0.05f * float(k))), watched.publish_camera(camera_at(0.05f * float(k)));
    a.step();
    b.step();
    taken = b.acquire_latest();
  }
  EXPECT_EQ(a.stats().reclaimed, 12u);
  EXPECT_EQ(b.stats().reclaimed, 0u);
  EXPECT_GE(a.stats().reproject.reprojections, 1u);
  EXPECT_TRUE(same_bits(a.acquire_latest(), taken));
}

// A consumer that asks keeps its images: after each call the display leaves them in the middle
// buffer for 8 ticks (taking back a busy tick's image right after its publish would starve a
// consumer that polls then).
TEST(DisplayThread, AConsumerThatAsksStopsTheReclaim) {
  Engine e(kEmptyScene, deterministic_config(RenderMode::frameless, 6), camera_at(0));
  DisplayThread d(e, {});
  for (int k = 0; k < 12; ++k) d.step();
  const uint64_t before = d.stats().reclaimed;
  EXPECT_EQ(before, 4u);  // ticks 8 to 11
  bool fresh = false;
  EXPECT_EQ(d.acquire_latest(&fresh).info.index, 11u);
  EXPECT_TRUE(fresh);
  for (int k = 0; k < 8; ++k) d.step();  // ticks 12 to 19 see the call
  EXPECT_EQ(d.stats().reclaimed, before);
  d.step();
  EXPECT_EQ(d.stats().reclaimed, before + 1);
  EXPECT_EQ(d.acquire_latest(&fresh).info.index, 20u);
  EXPECT_TRUE(fresh);
}

// With reprojection, a tick that moves the image changes every pixel's content (a buffer catching
// up copies the whole image) while a consumer takes images at uneven intervals: it still sees the
// tick's image bit for bit.
TEST(DisplayThread, TripleBufferMatchesTheTickImageWhileReprojecting) {
  EngineConfig c = deterministic_config(RenderMode::frameless, 7);
  c.samples_per_tick = 120;
  Engine e(kEmptyScene, c, camera_at(0));
  DisplayConfig dc;
  dc.blend.reproject = true;
  DisplayThread d(e, dc);
  DisplayImage seen;
  d.set_on_tick([&](const DisplayImage& img) { seen = img; });
  int taken = 0;
  for (int k = 0, skip = 0; k < 40; ++k) {
    if (k % 3 == 1) e.publish_camera(camera_at(0.02f * float(k)));
    d.step();
    if (skip-- > 0) continue;
    skip = (k * 5) % 4;  // 0..3 ticks skipped: catch-ups span moves and plain ticks
    bool fresh = false;
    const DisplayImage& img = d.acquire_latest(&fresh);
    EXPECT_TRUE(fresh);
    EXPECT_TRUE(same_bits(img, seen)) << "tick " << k;
    ++taken;
  }
  EXPECT_GT(taken, 10);
  EXPECT_GE(d.stats().reproject.reprojections, 8u);
}

// A new partition moves every pixel to a new slot; the display carries its image over, so
// the pixels it already showed are neither lost nor blended twice.
TEST(DisplayThread, LayoutChangeKeepsTheDisplayedImage) {
  Engine e(kEmptyScene, deterministic_config(RenderMode::frameless, 2), camera_at(0));
  DisplayThread d(e, {});
  for (int k = 0; k < 6; ++k) d.step();
  const DisplayImage before = d.acquire_latest();
  e.set_threads(5);
  const FrameInfo info = d.tick();  // no new samples: the engine did not advance
  EXPECT_EQ(info.pixels_updated, 0u);
  EXPECT_TRUE(same_bits(d.acquire_latest(), before));
  d.step();
  EXPECT_GT(d.acquire_latest().info.pixels_updated, 0u);
}

}  // namespace
}  // namespace frameless
