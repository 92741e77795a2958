// Tests of the reference cache: keys, file round trip, cache hits and misses.
#include "frameless/reference_cache.h"

#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>

#include "core/scenes/scene_load.h"
#include "frameless/image_error.h"
#include "frameless/tile_render.h"

namespace frameless {
namespace {

struct TempDir {
  std::string path;
  TempDir() {
    path = (std::filesystem::temp_directory_path() /
            ("frameless_refcache_" + std::to_string(::getpid()) + "_" +
             std::to_string(reinterpret_cast<uintptr_t>(this))))
               .string();
    std::filesystem::remove_all(path);
    std::filesystem::create_directories(path);
  }
  ~TempDir() { std::filesystem::remove_all(path); }
  size_t files() const {
    size_t n = 0;
    for (const auto& e : std::filesystem::directory_iterator(path))
      n += e.is_regular_file() ? 1 : 0;
    return n;
  }
};

std::unique_ptr<Scene> small_scene() {
  auto s = load_scene("spheres:20");
  EXPECT_TRUE(s.ok());
  return std::move(s.value());
}

ReferenceSpec spec_for(const Scene& scene) {
  ReferenceSpec s;
  s.scene_id = "spheres:20";
  s.code_version = "test+" + renderer_fingerprint(scene);
  s.camera = scene.camera;
  s.width = 12;
  s.height = 9;
  s.spp = 4;
  return s;
}

TEST(ReferenceCache, KeyChangesWithEveryInput) {
  ReferenceSpec a;
  a.scene_id = "default";
  a.code_version = "v1";
  a.width = 10;
  a.height = 10;
  const std::string h = reference_key_hash(a);
  EXPECT_EQ(h, reference_key_hash(a));
  EXPECT_EQ(h.size(), 16u);
  auto differs = [&](auto change) {
    ReferenceSpec b = a;
    change(b);
    return reference_key_hash(b) != h;
  };
  EXPECT_TRUE(differs([](ReferenceSpec& b) { b.scene_id = "balls"; }));
  EXPECT_TRUE(differs([](ReferenceSpec& b) { b.code_version = "v2"; }));
  EXPECT_TRUE(differs([](ReferenceSpec& b) { b.width = 11; }));
  EXPECT_TRUE(differs([](ReferenceSpec& b) { b.spp = 65; }));
  EXPECT_TRUE(
      differs([](ReferenceSpec& b) { b.camera.eye.x = std::nextafter(b.camera.eye.x, 1.0f); }));
  EXPECT_TRUE(differs([](ReferenceSpec& b) { b.camera.fov_deg = 46.0f; }));
}

TEST(ReferenceCache, SceneIdentityHashesFileBytes) {
  TempDir dir;
  const std::string f = dir.path + "/scene.json";
  std::ofstream(f) << "{\"a\": 1}";
  const std::string id1 = scene_identity(f);
  std::ofstream(f) << "{\"a\": 2}";
  EXPECT_NE(id1, scene_identity(f));
  EXPECT_EQ(scene_identity("default"), "default");  // not a file: the spec itself
}

TEST(ReferenceCache, RendersOnceThenReadsTheSameImage) {
  TempDir dir;
  auto scene = small_scene();
  const ReferenceSpec spec = spec_for(*scene);
  auto first = load_or_render_reference(*scene, spec, dir.path, 2);
  ASSERT_TRUE(first.ok()) << first.error().message;
  EXPECT_FALSE(first->from_cache);
  EXPECT_EQ(first->rgb.size(), 12u * 9u * 3u);
  EXPECT_EQ(dir.files(), 1u);
  auto second = load_or_render_reference(*scene, spec, dir.path, 1);
  ASSERT_TRUE(second.ok());
  EXPECT_TRUE(second->from_cache);
  EXPECT_EQ(second->rgb, first->rgb);
  EXPECT_EQ(second->noise_mse, first->noise_mse);
  // A different camera is a miss and a second file.
  ReferenceSpec moved = spec;
  moved.camera.eye += Vec3(0.5f, 0.0f, 0.0f);
  auto third = load_or_render_reference(*scene, moved, dir.path, 1);
  ASSERT_TRUE(third.ok());
  EXPECT_FALSE(third->from_cache);
  EXPECT_EQ(dir.files(), 2u);
}

TEST(ReferenceCache, ReferenceIsTheMeanOfAllItsSamples) {
  // The two halves together are exactly a render of all spp samples with the same indices.
  auto scene = small_scene();
  const ReferenceSpec spec = spec_for(*scene);
  auto ref = load_or_render_reference(*scene, spec, "", 2);
  ASSERT_TRUE(ref.ok());
  EXPECT_TRUE(ref->path.empty());
  TileRenderOptions o;
  o.spp = spec.spp;
  o.threads = 1;
  const RenderedImage full =
      render_tiles(*scene, make_camera_basis(spec.camera, spec.width, spec.height), o);
  EXPECT_LT(image_error(ref->rgb, full.rgb).rmse, 1e-5);
  EXPECT_GE(ref->noise_mse, 0.0);
}

TEST(ReferenceCache, RejectsWrongKeyAndTruncatedFiles) {
  TempDir dir;
  Reference r;
  r.width = 2;
  r.height = 1;
  r.rgb = {1, 2, 3, 4, 5, 6};
  r.noise_mse = 0.25;
  const std::string f = dir.path + "/r.bin";
  ASSERT_TRUE(write_reference_file(f, "key-a", r).ok());
  auto back = read_reference_file(f, "key-a");
  ASSERT_TRUE(back.ok());
  EXPECT_EQ(back->rgb, r.rgb);
  EXPECT_EQ(back->noise_mse, 0.25);
  EXPECT_FALSE(read_reference_file(f, "key-b").ok());
  std::filesystem::resize_file(f, std::filesystem::file_size(f) - 4);
  EXPECT_FALSE(read_reference_file(f, "key-a").ok());
  EXPECT_FALSE(read_reference_file(dir.path + "/missing.bin", "key-a").ok());
  // A truncated cache file is re-rendered, not trusted.
  auto scene = small_scene();
  const ReferenceSpec spec = spec_for(*scene);
  ASSERT_TRUE(load_or_render_reference(*scene, spec, dir.path, 1).ok());
  const std::string cached = dir.path + "/ref_" + reference_key_hash(spec) + ".bin";
  std::filesystem::resize_file(cached, 40);
  auto again = load_or_render_reference(*scene, spec, dir.path, 1);
  ASSERT_TRUE(again.ok());
  EXPECT_FALSE(again->from_cache);
}

TEST(ReferenceCache, DefaultDirectoryFollowsXdg) {
  const char* old = std::getenv("XDG_CACHE_HOME");
  const std::string saved = old ? old : "";
  setenv("XDG_CACHE_HOME", "/tmp/xdg", 1);
  EXPECT_EQ(default_reference_cache_dir("out"), "/tmp/xdg/frameless/references");
  unsetenv("XDG_CACHE_HOME");
  EXPECT_EQ(default_reference_cache_dir("out"), "out/cache");
  if (old) setenv("XDG_CACHE_HOME", saved.c_str(), 1);
}

}  // namespace
}  // namespace frameless
