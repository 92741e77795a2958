// Headless capture: deterministic captures are identical, the manifest matches the files, every
// layer round-trips through EXR, the frames equal the display thread's images, write failures
// leave a consistent sequence, and an unwritable folder is refused before rendering.
#include "display/capture.h"

#include <gtest/gtest.h>

#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <thread>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <set>

#include "core/scenes/scene_load.h"
#include "display/contact_sheet.h"
#include "display/display_thread.h"
#include "display/gl_presenter.h"
#include "display/manifest.h"
#include "display/osmesa_context.h"
#include "frameless/engine.h"
#include "frameless/output_commit.h"

namespace fs = std::filesystem;

namespace frameless {
namespace {

const char* const kRgb[3] = {"R", "G", "B"};

fs::path test_root() {
  return fs::temp_directory_path() / ("frameless_capture_test_" + std::to_string(getpid()));
}

// Removes this process's scratch folder when the suite ends.
struct ScratchCleanup : ::testing::Environment {
  void TearDown() override { fs::remove_all(test_root()); }
};
[[maybe_unused]] ::testing::Environment* const cleanup =
    ::testing::AddGlobalTestEnvironment(new ScratchCleanup);

std::string temp_dir(const std::string& name) {
  const fs::path p = test_root() / name;
  fs::remove_all(p);
  return p.string();
}

const Scene& scene() {
  static std::unique_ptr<Scene> s = [] {
    auto r = load_scene("default");
    EXPECT_TRUE(r.ok());
    return std::move(r.value());
  }();
  return *s;
}

CaptureOptions small_options(const std::string& out) {
  CaptureOptions o;
  o.out_dir = out;
  o.duration = 0.6;
  o.refresh_hz = 10.0;
  o.engine.width = 48;
  o.engine.height = 32;
  o.engine.threads = 2;
  o.engine.chunk_size = 16;
  o.engine.seed = 7;
  o.engine.deterministic = true;
  o.camera = scene().camera;
  o.layers = {"age", "count", "variance", "epoch"};
  o.mp4 = false;
  return o;
}

std::string slurp(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  return std::string(std::istreambuf_iterator<char>(in), {});
}

std::set<std::string> files_in(const std::string& dir) {
  std::set<std::string> names;
  for (const auto& e : fs::directory_iterator(dir)) names.insert(e.path().filename().string());
  return names;
}

TEST(Capture, DeterministicCapturesAreIdenticalFileForFile) {
  const std::string a = temp_dir("det_a"), b = temp_dir("det_b"), c = temp_dir("det_c");
  CaptureOptions o = small_options(a);
  PathShorthand sh;
  sh.orbit_deg = 20;
  o.path = make_shorthand_path(o.camera, sh, o.duration);
  ASSERT_TRUE(run_capture(scene(), o).ok());
  o.out_dir = b;
  auto r = run_capture(scene(), o);
  ASSERT_TRUE(r.ok()) << r.error().message;
  EXPECT_EQ(r->frames, 6);
  const std::set<std::string> names = files_in(a);
  ASSERT_EQ(names, files_in(b));
  EXPECT_TRUE(names.count("contact_sheet.png"));
  for (const std::string& n : names) EXPECT_EQ(slurp(fs::path(a) / n), slurp(fs::path(b) / n)) << n;
  // The comparison has teeth: another seed changes the frames, and frames change over time.
  o.out_dir = c;
  o.engine.seed = 8;
  ASSERT_TRUE(run_capture(scene(), o).ok());
  EXPECT_NE(slurp(fs::path(a) / "frame_00005.exr"), slurp(fs::path(c) / "frame_00005.exr"));
  EXPECT_NE(slurp(fs::path(a) / "frame_00001.exr"), slurp(fs::path(a) / "frame_00005.exr"));
}

TEST(Capture, ManifestListsExactlyTheFilesPresent) {
  const std::string dir = temp_dir("manifest");
  CaptureOptions o = small_options(dir);
  o.settings["scene"] = {{"spec", "default"}};
  ASSERT_TRUE(run_capture(scene(), o).ok());
  auto m = read_manifest(dir + "/manifest.json");
  ASSERT_TRUE(m.ok()) << m.error().message;
  std::set<std::string> listed;
  double last_time = -1;
  for (size_t i = 0; i < m->frames.size(); ++i) {
    const ManifestFrame& f = m->frames[i];
    EXPECT_EQ(f.index, int(i));
    EXPECT_EQ(f.file, capture_frame_name(int(i)));
    EXPECT_GT(f.virtual_time, last_time);
    last_time = f.virtual_time;
    EXPECT_LT(f.wall_time, 0.0);  // virtual clock: no wall times, so files stay reproducible
    EXPECT_EQ(f.mode, "frameless");
    EXPECT_GT(f.samples, 0u);
    EXPECT_GE(f.coverage, 0.0);
    EXPECT_LE(f.coverage, 1.0);
    EXPECT_TRUE(camera_is_valid(f.camera));
    listed.insert(f.file);
  }
  std::set<std::string> present;
  for (const std::string& n : files_in(dir))
    if (n.rfind("frame_", 0) == 0) present.insert(n);
  EXPECT_EQ(listed, present);
  EXPECT_EQ(listed.size(), 6u);
  for (const char* key : {"software", "seed", "scene", "refresh_hz", "size", "threads", "alpha",
                          "update_percent", "mode", "layers", "clock"})
    EXPECT_TRUE(m->settings.contains(key)) << key;
  EXPECT_EQ(m->settings["seed"].get<uint64_t>(), 7u);
}

TEST(Capture, EveryLayerRoundTripsThroughExr) {
  DisplayImage img;
  img.width = 5, img.height = 3;
  const size_t n = img.pixels();
  for (size_t i = 0; i < n; ++i) {
    img.rgb.insert(img.rgb.end(), {0.1f * float(i), 2.5f, 1e-3f * float(i)});
    img.last_update.push_back(i == 4 ? -1.0f : 0.01f * float(i));
    img.sample_count.push_back(uint32_t(i * 1000 + 1));
    img.variance.push_back(1e-4f * float(i));
    img.epoch.push_back(uint32_t(i % 3));
  }
  img.info.virtual_time = 1.0;
  ExrAttributes a;
  a.frames_per_second = 30.0;
  a.world_to_camera = world_to_camera_matrix(scene().camera);
  a.strings["seed"] = "7";
  const std::string path = temp_dir("roundtrip") + ".exr";
  fs::create_directories(fs::path(path).parent_path());
  ASSERT_TRUE(write_display_exr(path, img, nullptr, {"age", "count", "variance", "epoch"}, a).ok());
  auto back = read_exr(path);
  ASSERT_TRUE(back.ok()) << back.error().message;
  EXPECT_EQ(back->half_channels.size(), 3u);  // R, G, B half; the layers float
  for (size_t i = 0; i < n; ++i) {
    for (int c = 0; c < 3; ++c)
      EXPECT_NEAR(back->channels[kRgb[c]][i], img.rgb[i * 3 + c],
                  std::abs(img.rgb[i * 3 + c]) * 1e-3f + 1e-7f);
    EXPECT_EQ(back->channels["age"][i], img.age(i));
    EXPECT_EQ(back->channels["count"][i], float(img.sample_count[i]));
    EXPECT_EQ(back->channels["variance"][i], img.variance[i]);
    EXPECT_EQ(back->channels["epoch"][i], float(img.epoch[i]));
  }
  EXPECT_TRUE(std::isinf(back->channels["age"][4]));  // never updated
  ASSERT_TRUE(back->attributes.frames_per_second);
  EXPECT_DOUBLE_EQ(*back->attributes.frames_per_second, 30.0);
  ASSERT_TRUE(back->attributes.world_to_camera);
  EXPECT_EQ(*back->attributes.world_to_camera, *a.world_to_camera);
  EXPECT_EQ(back->attributes.strings["seed"], "7");
  EXPECT_FALSE(write_display_exr(path, img, nullptr, {"bogus"}, a).ok());
}

TEST(Capture, FramesEqualTheDisplayThreadImages) {
  const std::string dir = temp_dir("equal");
  CaptureOptions o = small_options(dir);
  ASSERT_TRUE(run_capture(scene(), o).ok());
  // The same deterministic run by hand: its display images, through OSMesa and straight.
  auto ctx = OsMesaContext::create(o.engine.width, o.engine.height);
  ASSERT_TRUE(ctx.ok()) << ctx.error().message;
  auto presenter = GlPresenter::create(&OsMesaContext::proc_address);
  ASSERT_TRUE(presenter.ok()) << presenter.error().message;
  Engine engine(scene(), o.engine, o.camera);
  DisplayConfig dc;
  dc.refresh_hz = o.refresh_hz;
  dc.blend = o.blend;
  DisplayThread display(engine, dc);
  engine.start();
  for (int k = 0; k < 6; ++k) {
    display.step();
    const DisplayImage& img = display.acquire_latest();
    presenter.value()->upload(img, ViewMode::shaded);
    std::vector<float> readback;
    ASSERT_TRUE(presenter.value()->render_linear(readback).ok());
    ASSERT_EQ(readback.size(), img.rgb.size());
    EXPECT_TRUE(readback == img.rgb) << "OSMesa readback differs from the display image at frame " << k;
    // The frame on disk holds exactly the display image at half precision.
    const std::string ref_path = dir + "_ref.exr";
    ASSERT_TRUE(write_display_exr(ref_path, img, nullptr, {}, {}).ok());
    auto frame = read_exr(dir + "/" + capture_frame_name(k));
    auto ref = read_exr(ref_path);
    ASSERT_TRUE(frame.ok() && ref.ok());
    size_t off = 0;
    for (const char* c : kRgb) off += frame->channels[c] != ref->channels[c];
    EXPECT_EQ(off, 0u) << "frame " << k;
  }
}

TEST(Capture, WriteFailureMidCaptureLeavesAConsistentSequence) {
  for (const char* failing : {"frame_00003.exr", "manifest.json"}) {
    const std::string dir = temp_dir(std::string("fail_") + failing);
    int manifest_writes = 0;
    CaptureHooks hooks;
    hooks.before_write = [&](const std::string& path) -> std::optional<std::string> {
      const std::string name = fs::path(path).filename().string();
      // The manifest fails on its 5th write: after frame 3's EXR (writes: initial, 0, 1, 2, 3).
      if (name == "manifest.json" && ++manifest_writes == 5 && std::string(failing) == name)
        return "No space left on device (injected)";
      if (name == failing && name != "manifest.json") return "No space left on device (injected)";
      return std::nullopt;
    };
    auto r = run_capture(scene(), small_options(dir), hooks);
    ASSERT_FALSE(r.ok()) << failing;
    EXPECT_NE(r.error().message.find("No space left on device"), std::string::npos);
    EXPECT_NE(r.error().message.find("3 frames written"), std::string::npos) << r.error().message;
    EXPECT_EQ(r.error().message.find('\n'), std::string::npos);
    auto m = read_manifest(dir + "/manifest.json");
    ASSERT_TRUE(m.ok());
    ASSERT_EQ(m->frames.size(), 3u);
    EXPECT_EQ(files_in(dir), (std::set<std::string>{"frame_00000.exr", "frame_00001.exr",
                                                     "frame_00002.exr", "manifest.json"}));
    for (const ManifestFrame& f : m->frames) EXPECT_TRUE(read_exr(dir + "/" + f.file).ok());
  }
}

// The cluster's fatal path (MPI_Abort) freezes output commits before it ends the process: a frame
// caught between its EXR and the manifest that lists it is finished first.
TEST(Capture, FreezingCommitsWaitsForTheFrameBeingListed) {
  const std::string dir = temp_dir("freeze");
  std::atomic<int> manifest_writes{0};
  std::atomic<bool> in_commit{false};
  CaptureHooks hooks;
  hooks.before_write = [&](const std::string& path) -> std::optional<std::string> {
    // The 4th manifest write lists frame 2, whose EXR is already on disk: linger there.
    if (fs::path(path).filename() == "manifest.json" && ++manifest_writes == 4) {
      in_commit = true;
      std::this_thread::sleep_for(std::chrono::milliseconds(300));
    }
    return std::nullopt;
  };
  std::set<std::string> on_disk;
  std::vector<std::string> listed;
  std::thread fatal([&] {
    while (!in_commit) std::this_thread::sleep_for(std::chrono::milliseconds(1));
    const std::unique_lock<std::mutex> frozen = freeze_output_commits();
    for (const std::string& f : files_in(dir))
      if (f.rfind("frame_", 0) == 0) on_disk.insert(f);
    auto m = read_manifest(dir + "/manifest.json");
    ASSERT_TRUE(m.ok());
    for (const ManifestFrame& f : m->frames) listed.push_back(f.file);
  });
  auto r = run_capture(scene(), small_options(dir), hooks);
  fatal.join();
  ASSERT_TRUE(r.ok()) << r.error().message;
  EXPECT_EQ(on_disk, std::set<std::string>(listed.begin(), listed.end()));
  EXPECT_GE(listed.size(), 3u);
}

TEST(Capture, UnwritableFolderIsRefusedBeforeRendering) {
  const std::string base = temp_dir("unwritable");
  fs::create_directories(base);
  const std::string file = base + "/a_file";
  std::ofstream(file) << "x";
  // A folder below a regular file cannot exist, whoever runs the test (root included).
  CaptureOptions o = small_options(file + "/out");
  int writes = 0;
  CaptureHooks hooks;
  hooks.before_write = [&](const std::string&) -> std::optional<std::string> {
    ++writes;
    return std::nullopt;
  };
  auto r = run_capture(scene(), o, hooks);
  ASSERT_FALSE(r.ok());
  EXPECT_NE(r.error().message.find(file), std::string::npos) << r.error().message;
  EXPECT_EQ(writes, 0);
  EXPECT_TRUE(prepare_output_dir(base + "/fresh/nested").ok());
  // The command's one-line report: tests/cli/capture_view_cli_test.cpp.
}

TEST(Capture, BadSettingsAreRejected) {
  CaptureOptions o = small_options(temp_dir("bad"));
  o.layers = {"age", "colour"};
  EXPECT_FALSE(run_capture(scene(), o).ok());
  o = small_options(temp_dir("bad"));
  o.refresh_hz = 0;
  EXPECT_FALSE(run_capture(scene(), o).ok());
  o = small_options(temp_dir("bad"));
  o.duration = -1;
  EXPECT_FALSE(run_capture(scene(), o).ok());
}

// The optional MP4 (only when ffmpeg is installed): an odd-sized capture is padded to even
// sizes and encoded; the file is an MP4 (an `ftyp` box first) and no temporary file is left.
TEST(Capture, Mp4WhenFfmpegIsInstalled) {
  if (!ffmpeg_available()) GTEST_SKIP() << "ffmpeg is not installed (apt-get install ffmpeg)";
  const std::string dir = temp_dir("mp4");
  CaptureOptions o = small_options(dir);
  o.engine.width = 47;  // odd: H.264 needs the padding
  o.engine.height = 31;
  o.layers.clear();
  o.mp4 = true;
  auto r = run_capture(scene(), o);
  ASSERT_TRUE(r.ok()) << r.error().message;
  EXPECT_EQ(r->note, "");
  ASSERT_EQ(r->mp4_path, (fs::path(dir) / "sequence.mp4").string());
  const std::string mp4 = slurp(r->mp4_path);
  ASSERT_GT(mp4.size(), 8u);
  EXPECT_EQ(mp4.substr(4, 4), "ftyp");
  for (const std::string& n : files_in(dir)) EXPECT_EQ(n.find(".tmp"), std::string::npos) << n;
}

}  // namespace
}  // namespace frameless
