// The cluster's exchange without the network: client engines that render a share of the
// threads, their ChangeCollector, and a master engine that renders nothing and ingests what they
// send (what cluster::Session does over MPI). Deterministic: the master's display frames equal a
// single process's with as many threads, bit for bit, through camera changes and instance moves.
// Wall clock: clients, a feeder (the communication thread), a 240 Hz display and a camera
// publisher at once, race-free (CI runs this suite under ThreadSanitizer).
#include <gtest/gtest.h>

#include <atomic>
#include <chrono>
#include <cmath>
#include <memory>
#include <thread>

#include "cluster/change_collector.h"
#include "core/scenes/scene_load.h"
#include "display/display_thread.h"
#include "frameless/engine.h"

namespace frameless {
namespace {

constexpr const char* kScene = R"({
  "camera": {"eye": [0, 3, 7], "look": [0, 0.5, 0], "up": [0, 1, 0], "fov": 45},
  "lights": [{"type": "point", "position": [3, 6, 4], "color": [1, 1, 1]}],
  "materials": {"floor": {"class": "diffuse", "kd": [0.6, 0.6, 0.6]},
                "red": {"class": "diffuse", "kd": [0.7, 0.1, 0.1]},
                "glass": {"class": "dielectric", "ior": 1.5}},
  "meshes": {"tetra": {"type": "triangles", "material": "red",
      "vertices": [[-0.8, 0, -0.8], [0.8, 0, -0.8], [0, 0, 0.8], [0, 1.4, 0]],
      "indices": [[0, 2, 1], [0, 1, 3], [1, 2, 3], [2, 0, 3]]}},
  "objects": [
    {"type": "plane", "point": [0, 0, 0], "normal": [0, 1, 0], "size": 20, "material": "floor"},
    {"type": "sphere", "center": [0, 1, 1.5], "radius": 0.6, "material": "glass"},
    {"type": "instance", "mesh": "tetra", "transform": {"translate": [-2, 0, 0]}},
    {"type": "instance", "mesh": "tetra", "transform": {"translate": [2, 0, 0]}}
  ]})";

std::unique_ptr<Scene> load() {
  auto s = parse_scene_json(kScene, "t.json", ".");
  EXPECT_TRUE(s) << s.error().message;
  return s ? std::move(*s) : nullptr;
}

// Clients of an in-process cluster: client k renders threads [k * t, (k + 1) * t).
struct Clients {
  std::vector<std::unique_ptr<Engine>> engines;
  std::vector<std::unique_ptr<cluster::ChangeCollector>> collectors;
  Clients(const Scene& s, EngineConfig c, int clients, int threads) {
    c.threads = clients * threads;
    c.owned_count = threads;
    for (int k = 0; k < clients; ++k) {
      c.owned_first = k * threads;
      engines.push_back(std::make_unique<Engine>(s, c, s.camera));
      collectors.push_back(std::make_unique<cluster::ChangeCollector>(*engines.back(), k * threads, threads));
      engines.back()->start();
    }
  }
  // The master's differential updates, as Session sends them.
  void sync(const Engine& master) {
    uint32_t epoch = 0;
    const Camera cam = master.camera(&epoch);
    for (auto& e : engines) {
      e->publish_camera_as(cam, epoch);
      std::vector<InstanceMove> moves;
      for (uint32_t i = 0; i < 2; ++i) {
        const Affine a = master.instance_transform(i), b = e->instance_transform(i);
        if (a.m != b.m || a.t != b.t) moves.push_back({i, a});
      }
      if (!moves.empty()) e->move_instances(moves);
    }
  }
  void feed(Engine& master) {
    for (size_t k = 0; k < engines.size(); ++k)
      for (const RemoteBatch& b : collectors[k]->take(*engines[k])) master.ingest(b);
  }
};

void expect_same(const DisplayImage& a, const DisplayImage& b, int frame) {
  ASSERT_EQ(a.rgb.size(), b.rgb.size());
  size_t differ = 0;
  for (size_t i = 0; i < a.rgb.size(); ++i) differ += a.rgb[i] != b.rgb[i];
  EXPECT_EQ(differ, 0u) << "frame " << frame;
  EXPECT_EQ(a.epoch, b.epoch) << "frame " << frame;
  EXPECT_EQ(a.sample_count, b.sample_count) << "frame " << frame;
  EXPECT_EQ(a.last_update, b.last_update) << "frame " << frame;
  EXPECT_EQ(a.levels, b.levels) << "frame " << frame;
}

// Runs `frames` display steps of a single process with `threads` threads and of a master fed by
// `clients` x `per_client` threads, changing camera and instances on the way.
void compare(int clients, int per_client, bool variance) {
  auto s = load();
  ASSERT_TRUE(s);
  EngineConfig c;
  c.width = 40;
  c.height = 30;
  c.deterministic = true;
  c.update_percent = 5.0;
  c.track_variance = variance;
  c.seed = 7;
  c.threads = clients * per_client;
  Engine single(*s, c, s->camera);
  EngineConfig mc = c;
  mc.owned_count = 0;
  Engine master(*s, mc, s->camera);
  Clients cl(*s, c, clients, per_client);
  master.set_remote_advance([&](uint64_t, double dt) {
    cl.sync(master);
    for (auto& e : cl.engines) e->advance(dt);
    cl.feed(master);
  });
  DisplayConfig dc;
  dc.refresh_hz = 30;
  DisplayThread ds(single, dc), dm(master, dc);
  single.start();
  master.start();
  for (int k = 0; k < 24; ++k) {
    if (k == 8 || k == 9 || k == 16) {  // two cameras before one tick: clients jump an epoch
      Camera cam = s->camera;
      cam.eye.x += 0.3f * float(k);
      single.publish_camera(cam);
      master.publish_camera(cam);
    }
    if (k == 12) {
      Affine a = single.instance_transform(1);
      a.t.z += 0.7f;
      single.move_instances({{1, a}});
      master.move_instances({{1, a}});
    }
    ds.step();
    dm.step();
    expect_same(ds.acquire_latest(), dm.acquire_latest(), k);
    if (::testing::Test::HasFailure()) return;
  }
  EXPECT_GT(dm.acquire_latest().epoch[0], 2u);  // the cameras reached the clients
  EXPECT_FALSE(master.error());
}

TEST(ClusterExchange, DeterministicMasterFramesEqualOneProcessThreeClientsOfOne) { compare(3, 1, false); }
TEST(ClusterExchange, DeterministicMasterFramesEqualOneProcessTwoClientsOfTwo) { compare(2, 2, true); }

TEST(ClusterExchange, WallClockClientsFeederDisplayAndCameraAtOnce) {
  auto s = load();
  ASSERT_TRUE(s);
  EngineConfig c;
  c.width = 48;
  c.height = 36;
  c.update_percent = 2.0;
  c.threads = 4;
  EngineConfig mc = c;
  mc.owned_count = 0;
  Engine master(*s, mc, s->camera);
  Clients cl(*s, c, 2, 2);
  DisplayConfig dc;
  dc.refresh_hz = 240;
  DisplayThread d(master, dc);
  master.start();
  d.start();
  std::atomic<bool> stop{false};
  std::thread feeder([&] {  // the communication thread: camera out, updates in
    while (!stop.load()) {
      cl.sync(master);
      cl.feed(master);
      std::this_thread::sleep_for(std::chrono::milliseconds(2));
    }
  });
  for (int k = 0; k < 150; ++k) {
    Camera cam = s->camera;
    cam.eye.x = 2.0f * std::sin(0.05f * float(k));
    master.publish_camera(cam);
    std::this_thread::sleep_for(std::chrono::milliseconds(5));
  }
  std::this_thread::sleep_for(std::chrono::milliseconds(200));  // the last camera settles
  stop = true;
  feeder.join();
  d.stop();
  for (auto& e : cl.engines) e->stop();
  master.stop();
  const DisplayImage& img = d.acquire_latest();
  ASSERT_EQ(img.rgb.size(), size_t(48 * 36 * 3));
  size_t newest = 0;
  for (uint32_t ep : img.epoch) newest += ep == master.camera_epoch();
  EXPECT_GT(newest, img.epoch.size() / 2);  // the clients render the newest camera
  for (float v : img.rgb) ASSERT_TRUE(std::isfinite(v));
  EXPECT_GT(master.stats().samples, 1000u);
  EXPECT_FALSE(master.error());
}

}  // namespace
}  // namespace frameless
