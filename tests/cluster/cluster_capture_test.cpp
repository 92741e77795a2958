// The whole distribution layer over real Open MPI (mpirun on localhost): a deterministic capture
// of R clients x T threads writes the same frames, bit for bit, as one process with R*T threads;
// camera changes reach every client; a killed client ends the job in bounded time with the
// manifest matching the files; a client that cannot start stops every rank with one line.
#include <gtest/gtest.h>

#include <chrono>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <thread>

#include <nlohmann/json.hpp>

#include "display/exr_io.h"
#include "mpi_run_util.h"

namespace frameless::test {
namespace {

namespace fs = std::filesystem;

// The one-process runs compared with the cluster's turn off what a cluster does not do
// (reprojection needs hit points, closed loop asks the render threads).
const std::string kBase =
    "capture default --deterministic --size 48x36 --refresh 20 --layers all --no-mp4 "
    "--no-contact-sheet --no-reproject --no-closed-loop";
// An orbiting camera (a new camera every frame) with a cut.
const std::string kCapture = kBase + " --duration 1 --orbit 25 --cut-at 0.3 --seed 3";

std::vector<std::string> frames_in(const fs::path& dir) {
  std::vector<std::string> out;
  for (const auto& e : fs::directory_iterator(dir))
    if (e.path().extension() == ".exr") out.push_back(e.path().filename().string());
  std::sort(out.begin(), out.end());
  return out;
}

std::vector<std::string> manifest_frames(const fs::path& dir) {
  std::ifstream in(dir / "manifest.json");
  const nlohmann::json j = nlohmann::json::parse(in, nullptr, false);
  std::vector<std::string> out;
  if (j.is_discarded()) return {"<manifest unreadable>"};
  for (const auto& f : j["frames"]) out.push_back(f["file"].get<std::string>());
  std::sort(out.begin(), out.end());
  return out;
}

void expect_same_frames(const fs::path& a, const fs::path& b) {
  const std::vector<std::string> fa = frames_in(a), fb = frames_in(b);
  ASSERT_EQ(fa, fb);
  ASSERT_EQ(fa.size(), 20u);
  for (const std::string& f : fa) {
    auto ia = read_exr((a / f).string()), ib = read_exr((b / f).string());
    ASSERT_TRUE(ia.ok() && ib.ok()) << f;
    ASSERT_EQ(ia->channels.size(), 8u) << f;  // R G B + age count variance epoch levels
    for (const auto& [name, values] : ia->channels) {
      ASSERT_TRUE(ib->channels.count(name)) << f << " " << name;
      EXPECT_EQ(values, ib->channels.at(name)) << f << " channel " << name;
    }
  }
}

TEST(ClusterCapture, DeterministicThreeRanksEqualOneProcessWithTwoThreads) {
  FRAMELESS_REQUIRE_MPI();
  const fs::path dir = fresh_dir("cluster_det");
  const CommandResult c = run_cluster(3, kCapture + " --threads 1 --out " + (dir / "cluster").string());
  ASSERT_EQ(c.exit_code, 0) << c.output;
  const CommandResult s = run_frameless(kCapture + " --threads 2 --out " + (dir / "single").string());
  ASSERT_EQ(s.exit_code, 0) << s.output;
  expect_same_frames(dir / "cluster", dir / "single");
  // Another seed renders other frames: the comparison above can tell frames apart.
  const CommandResult o = run_frameless(kBase + " --duration 1 --orbit 25 --cut-at 0.3 --seed 4 --threads 2 --out " + (dir / "other").string());
  ASSERT_EQ(o.exit_code, 0) << o.output;
  auto x = read_exr((dir / "single" / "frame_00019.exr").string());
  auto y = read_exr((dir / "other" / "frame_00019.exr").string());
  ASSERT_TRUE(x.ok() && y.ok());
  EXPECT_NE(x->channels.at("R"), y->channels.at("R"));
}

TEST(ClusterCapture, DeterministicTwoClientsOfTwoThreadsEqualOneProcessWithFour) {
  FRAMELESS_REQUIRE_MPI();
  const fs::path dir = fresh_dir("cluster_det4");
  const CommandResult c = run_cluster(3, kCapture + " --threads 2 --out " + (dir / "cluster").string());
  ASSERT_EQ(c.exit_code, 0) << c.output;
  const CommandResult s = run_frameless(kCapture + " --threads 4 --out " + (dir / "single").string());
  ASSERT_EQ(s.exit_code, 0) << s.output;
  expect_same_frames(dir / "cluster", dir / "single");
}

TEST(ClusterCapture, CameraCutReachesEveryClientsPixels) {
  FRAMELESS_REQUIRE_MPI();
  const fs::path dir = fresh_dir("cluster_cut");
  const CommandResult c = run_cluster(3, kBase + " --duration 2 --cut-at 0.3 --threads 1 --out " + dir.string());
  ASSERT_EQ(c.exit_code, 0) << c.output;
  auto first = read_exr((dir / "frame_00000.exr").string());
  auto last = read_exr((dir / "frame_00039.exr").string());
  ASSERT_TRUE(first.ok() && last.ok());
  const std::vector<float>& e0 = first->channels.at("epoch");
  const std::vector<float>& e1 = last->channels.at("epoch");
  const float newest = *std::max_element(e1.begin(), e1.end());
  EXPECT_GT(newest, *std::max_element(e0.begin(), e0.end()));
  // Every pixel, whichever client owns it, shows the newest camera's samples at the end.
  size_t stale = 0;
  for (float v : e1) stale += v != newest;
  EXPECT_EQ(stale, 0u);
}

// The process of rank `rank` of the job writing into `marker` (found by its command line).
int find_rank_pid(const std::string& marker, int rank) {
  for (const auto& e : fs::directory_iterator("/proc")) {
    const std::string name = e.path().filename().string();
    if (name.find_first_not_of("0123456789") != std::string::npos) continue;
    std::ifstream cmd(e.path() / "cmdline"), env(e.path() / "environ");
    std::string c((std::istreambuf_iterator<char>(cmd)), {}), v((std::istreambuf_iterator<char>(env)), {});
    if (c.find(marker) == std::string::npos || c.find("mpirun") != std::string::npos) continue;
    if (v.find(std::string("OMPI_COMM_WORLD_RANK=") + std::to_string(rank) + '\0') != std::string::npos)
      return std::stoi(name);
  }
  return -1;
}

TEST(ClusterCapture, KilledClientEndsTheJobAndTheManifestMatchesTheFiles) {
  FRAMELESS_REQUIRE_MPI();
  const fs::path dir = fresh_dir("cluster_kill");
  const std::string out = (dir / "out").string();
  std::atomic<int> killed_pid{-1};
  std::chrono::steady_clock::time_point killed_at;
  std::thread killer([&] {
    const auto give_up = std::chrono::steady_clock::now() + std::chrono::seconds(60);
    while (std::chrono::steady_clock::now() < give_up) {
      std::this_thread::sleep_for(std::chrono::milliseconds(100));
      if (manifest_frames(out).size() < 3) continue;  // the capture is under way
      const int pid = find_rank_pid(out, 2);
      if (pid > 0) {
        killed_at = std::chrono::steady_clock::now();
        ::kill(pid, SIGKILL);
        killed_pid = pid;
        return;
      }
    }
  });
  const CommandResult r = run_cluster(
      3, "capture default --size 64x48 --threads 1 --refresh 10 --duration 100 --no-mp4 --out " + out);
  const auto ended = std::chrono::steady_clock::now();
  killer.join();
  ASSERT_GT(killed_pid.load(), 0) << r.output;
  EXPECT_NE(r.exit_code, 0) << r.output;
  EXPECT_LT(std::chrono::duration<double>(ended - killed_at).count(), 30.0);  // bounded, no hang
  EXPECT_NE(r.output.find("rank 2"), std::string::npos) << r.output;          // names the rank
  // Frames written before the fault stay, and the manifest lists exactly them.
  const std::vector<std::string> on_disk = frames_in(out), listed = manifest_frames(out);
  EXPECT_GE(listed.size(), 3u);
  EXPECT_EQ(on_disk, listed);
  for (const std::string& f : listed) EXPECT_TRUE(read_exr(out + "/" + f).ok()) << f;
}

// MPMD: rank 0 runs `master_args`, rank 1 `client_args` (with `client_env` set).
CommandResult run_pair(const std::string& master_args, const std::string& client_args,
                       const std::string& client_env = "") {
  return run_shell(std::string(kMpirun) + " -np 1 " + FRAMELESS_BINARY + " " + master_args + " : -np 1 " +
                   client_env + " " + FRAMELESS_BINARY + " " + client_args);
}

int lines_with(const std::string& text, const std::string& needle) {
  int n = 0;
  size_t at = 0;
  while ((at = text.find(needle, at)) != std::string::npos) ++n, ++at;
  return n;
}

TEST(ClusterCapture, ClientThatCannotStartStopsEveryRankWithOneLine) {
  FRAMELESS_REQUIRE_MPI();
  const fs::path dir = fresh_dir("cluster_bad");
  const std::string out = " --out " + (dir / "out").string();
  const std::string base = "capture --deterministic --size 32x24 --duration 0.2 --no-mp4";
  struct Case {
    std::string client, env, expect;
  };
  for (const Case& k : {Case{"no_such_scene.json", "", "frameless: cluster: rank 1: "},
                        Case{"balls", "", "rank 1 loaded another scene"},
                        Case{"default", "-x FRAMELESS_TEST_BUILD_ID=other-build", "rank 1 runs another build"}}) {
    const CommandResult r = run_pair(base + " default" + out, base + " " + k.client + out, k.env);
    EXPECT_NE(r.exit_code, 0) << r.output;
    EXPECT_NE(r.output.find(k.expect), std::string::npos) << r.output;
    EXPECT_EQ(lines_with(r.output, "frameless:"), 1) << r.output;  // one line, from the master
    EXPECT_TRUE(frames_in(dir / "out").empty());
  }
}

// Conventional frames, OpenRT's way: each tick's stretch of a frame is split over the clients'
// threads as one process splits it over its own, and pixel states travel with the pieces.
TEST(ClusterCapture, ConventionalDeterministicTwoClientsEqualOneProcess) {
  FRAMELESS_REQUIRE_MPI();
  const fs::path dir = fresh_dir("cluster_conv_det");
  // A still camera (pixels accumulate over frames) with a cut; 350 pixels a tick do not divide
  // the frame, so each pixel is rendered by other threads (and clients) from frame to frame.
  const std::string capture = kBase + " --duration 1 --cut-at 0.5 --seed 3 --samples-per-tick 700 --mode conventional";
  for (int t : {1, 2}) {
    const std::string tag = std::to_string(t);
    const CommandResult c = run_cluster(3, capture + " --threads " + tag + " --out " + (dir / ("cluster" + tag)).string());
    ASSERT_EQ(c.exit_code, 0) << c.output;
    const CommandResult s = run_frameless(capture + " --threads " + std::to_string(2 * t) + " --out " +
                                          (dir / ("single" + tag)).string());
    ASSERT_EQ(s.exit_code, 0) << s.output;
    expect_same_frames(dir / ("cluster" + tag), dir / ("single" + tag));
  }
  // The comparison bites: frameless frames of the same run differ from conventional ones.
  auto x = read_exr((dir / "single1" / "frame_00019.exr").string());
  const CommandResult f = run_frameless(kCapture + " --threads 2 --out " + (dir / "frameless").string());
  ASSERT_EQ(f.exit_code, 0) << f.output;
  auto y = read_exr((dir / "frameless" / "frame_00019.exr").string());
  ASSERT_TRUE(x.ok() && y.ok());
  EXPECT_NE(x->channels.at("R"), y->channels.at("R"));
}

// What a conventional frame sees of moving instances is the instant it began, not the newest
// (the capture moves them every tick): the clients get the frame's own.
TEST(ClusterCapture, ConventionalDeterministicWithMovingInstancesEqualsOneProcess) {
  FRAMELESS_REQUIRE_MPI();
  const fs::path dir = fresh_dir("cluster_conv_motion");
  const fs::path scene = dir / "bounce.json";
  std::ofstream(scene) << R"({
    "camera": {"eye": [0, 2.5, 6], "look": [0, 0.6, 0], "up": [0, 1, 0], "fov": 45},
    "lights": [{"type": "point", "position": [3, 6, 4], "color": [1, 1, 1]}],
    "materials": {"floor": {"class": "diffuse", "kd": [0.6, 0.6, 0.6]},
                  "red": {"class": "diffuse", "kd": [0.7, 0.1, 0.1]}},
    "meshes": {"tetra": {"type": "triangles", "material": "red",
        "vertices": [[-0.8, 0, -0.8], [0.8, 0, -0.8], [0, 0, 0.8], [0, 1.4, 0]],
        "indices": [[0, 2, 1], [0, 1, 3], [1, 2, 3], [2, 0, 3]]}},
    "objects": [
      {"type": "plane", "point": [0, 0, 0], "normal": [0, 1, 0], "size": 20, "material": "floor"},
      {"type": "instance", "mesh": "tetra", "transform": {"translate": [-1, 0, 0]},
       "motion": {"type": "bounce", "height": 1.0, "period": 0.7}},
      {"type": "instance", "mesh": "tetra", "transform": {"translate": [1, 0, 0]}}
    ]})";
  const std::string capture = "capture " + scene.string() +
                              " --deterministic --size 48x36 --refresh 20 --layers all --no-mp4 --no-contact-sheet"
                              " --duration 1 --seed 3 --samples-per-tick 864 --mode conventional";
  // 432 pixels a tick: every frame ends with a tick, so the next one begins before the capture
  // moves the instance for the next tick, and its first stretch is rendered after the move.
  const CommandResult c = run_cluster(3, capture + " --threads 1 --out " + (dir / "cluster").string());
  ASSERT_EQ(c.exit_code, 0) << c.output;
  const CommandResult s = run_frameless(capture + " --threads 2 --out " + (dir / "single").string());
  ASSERT_EQ(s.exit_code, 0) << s.output;
  expect_same_frames(dir / "cluster", dir / "single");
}

// Wall clock: pieces handed out on demand; every pixel of the last frame shows the newest camera
// (the cut reached every client), and the frames are real renders (non-zero, finite).
TEST(ClusterCapture, ConventionalWallClockFramesCoverEveryPixel) {
  FRAMELESS_REQUIRE_MPI();
  for (const std::string wire : {"exact", "rgbe"}) {
    const fs::path dir = fresh_dir("cluster_conv_wall_" + wire);
    const CommandResult c = run_cluster(3, "capture default --mode conventional --size 64x48 --refresh 10 "
                                           "--duration 2 --cut-at 0.5 --threads 1 --no-mp4 --no-contact-sheet "
                                           "--layers all --cluster-wire " + wire + " --out " + dir.string());
    ASSERT_EQ(c.exit_code, 0) << c.output;
    const std::vector<std::string> frames = frames_in(dir);
    ASSERT_GE(frames.size(), 10u) << c.output;
    auto last = read_exr((dir / frames.back()).string());
    ASSERT_TRUE(last.ok());
    const std::vector<float>& epoch = last->channels.at("epoch");
    const float newest = *std::max_element(epoch.begin(), epoch.end());
    EXPECT_GE(newest, 2.0f) << wire;
    size_t stale = 0, lit = 0;
    for (size_t i = 0; i < epoch.size(); ++i) {
      stale += epoch[i] != newest;
      lit += last->channels.at("R")[i] > 0.0f;
      EXPECT_TRUE(std::isfinite(last->channels.at("R")[i]));
    }
    EXPECT_EQ(stale, 0u) << wire;
    EXPECT_GT(lit, epoch.size() / 2) << wire;
  }
}

}  // namespace
}  // namespace frameless::test

namespace frameless::test {
namespace {

TEST(ClusterView, ViewerUnderXvfbShowsTheClientsPixels) {
  FRAMELESS_REQUIRE_MPI();
  if (run_shell("command -v xvfb-run").exit_code != 0) GTEST_SKIP() << "xvfb-run is not installed (apt-get install xvfb)";
  const fs::path dir = fresh_dir("cluster_view");
  for (const std::string mode : {"frameless", "conventional"}) {
    const std::string shot = (dir / (mode + ".png")).string(), script = (dir / "script.txt").string();
    std::ofstream(script) << "0.8 orbit 40 0\n1.0 key M\n2.0 screenshot " << shot << "\n2.1 quit\n";
    const CommandResult r = run_shell(kMpiEnv + " xvfb-run -a -s '-screen 0 640x480x24' timeout 120 mpirun "
                                      "--oversubscribe -np 3 " + FRAMELESS_BINARY + " view default --size 160x120 --threads 1 --mode " +
                                      mode + " --script " + script);
    ASSERT_EQ(r.exit_code, 0) << r.output;
    ASSERT_TRUE(fs::exists(shot)) << r.output;
    EXPECT_GT(fs::file_size(shot), 2000u) << mode;  // a rendered picture, not an empty frame
  }
}

}  // namespace
}  // namespace frameless::test

namespace frameless::test {
namespace {

TEST(ClusterCapture, RgbeWireOnTheWallClockAndRefusedWhenDeterministic) {
  FRAMELESS_REQUIRE_MPI();
  const fs::path dir = fresh_dir("cluster_rgbe");
  const CommandResult r = run_cluster(
      3, "capture default --size 64x48 --threads 1 --refresh 10 --duration 1.5 --no-mp4 --no-contact-sheet "
         "--cluster-wire rgbe --out " + (dir / "a").string());
  ASSERT_EQ(r.exit_code, 0) << r.output;
  const std::vector<std::string> frames = manifest_frames(dir / "a");
  ASSERT_GE(frames.size(), 3u);
  auto img = read_exr((dir / "a" / frames.back()).string());
  ASSERT_TRUE(img.ok());
  double sum = 0;
  for (float v : img->channels.at("G")) sum += v;
  EXPECT_GT(sum / double(img->channels.at("G").size()), 0.05);  // a lit picture arrived
  const CommandResult d = run_cluster(
      2, "capture default --deterministic --size 32x24 --duration 0.2 --cluster-wire rgbe --out " + (dir / "b").string());
  EXPECT_NE(d.exit_code, 0);
  EXPECT_NE(d.output.find("--cluster-wire rgbe: deterministic runs need the exact wire format"), std::string::npos)
      << d.output;
  EXPECT_EQ(lines_with(d.output, "frameless:"), 1) << d.output;
}

}  // namespace
}  // namespace frameless::test

namespace frameless::test {
namespace {

// Plug-in shaders (docs/shaders.md) under the cluster: every rank loads the scene and its
// shaders; a client without the library on its shader path stops every rank with one line.
TEST(ClusterCapture, PluginShadersLoadOnEveryRankOrStopTheJobWithOneLine) {
  FRAMELESS_REQUIRE_MPI();
  const fs::path dir = fresh_dir("cluster_shaders");
  // The example scene with its bricks under a name only the root's --shader-path holds (the
  // examples beside the program are on every rank's default path).
  std::ifstream in(fs::path(FRAMELESS_TEST_DATA).parent_path().parent_path() / "docs" / "scenes" / "shaders.json");
  std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  text.replace(text.find("\"bricks\""), 8, "\"bricks_copy\"");
  fs::create_directories(dir / "scene");
  fs::create_directories(dir / "lib");
  std::ofstream(dir / "scene" / "shaders.json") << text;
  fs::copy_file(fs::path(FRAMELESS_SHADER_DIR) / "bricks.so", dir / "lib" / "bricks_copy.so");
  const std::string scene = (dir / "scene" / "shaders.json").string();
  const std::string base = "capture " + scene + " --deterministic --size 32x24 --duration 0.2 --no-mp4 --no-contact-sheet";
  const std::string path = " --shader-path " + (dir / "lib").string();
  const std::string good = " --out " + (dir / "good").string(), bad = " --out " + (dir / "bad").string();
  const CommandResult ok = run_pair(base + path + good, base + path + good);
  EXPECT_EQ(ok.exit_code, 0) << ok.output;
  EXPECT_FALSE(frames_in(dir / "good").empty());
  const CommandResult r = run_pair(base + path + bad, base + bad);
  EXPECT_NE(r.exit_code, 0) << r.output;
  EXPECT_NE(r.output.find("rank 1: "), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("shader 'bricks_copy': no bricks_copy.so"), std::string::npos) << r.output;
  EXPECT_EQ(lines_with(r.output, "frameless:"), 1) << r.output;
  EXPECT_TRUE(!fs::exists(dir / "bad") || frames_in(dir / "bad").empty());
}

}  // namespace
}  // namespace frameless::test
