// Conventional frames across an in-process cluster, without the network: client engines whose
// render threads take pieces from a PieceQueue, a master engine that renders nothing and
// assembles frames from what comes back (what cluster::Session does over MPI). Deterministic:
// the master's frames equal one process's, bit for bit, with pixel states handed between
// clients. Wall clock: the TileScheduler's pieces on demand, client threads, a communication
// thread, a 240 Hz display and a camera publisher at once, race-free (CI runs this suite under
// ThreadSanitizer).
#include <gtest/gtest.h>

#include <atomic>
#include <chrono>
#include <cmath>
#include <map>
#include <memory>
#include <thread>

#include "cluster/piece_queue.h"
#include "cluster/tile_scheduler.h"
#include "core/scenes/scene_load.h"
#include "display/display_thread.h"
#include "frameless/engine.h"

namespace frameless {
namespace {

constexpr const char* kScene = R"({
  "camera": {"eye": [0, 3, 7], "look": [0, 0.5, 0], "up": [0, 1, 0], "fov": 45},
  "lights": [{"type": "point", "position": [3, 6, 4], "color": [1, 1, 1]}],
  "materials": {"floor": {"class": "diffuse", "kd": [0.6, 0.6, 0.6]},
                "glass": {"class": "dielectric", "ior": 1.5}},
  "objects": [
    {"type": "plane", "point": [0, 0, 0], "normal": [0, 1, 0], "size": 20, "material": "floor"},
    {"type": "sphere", "center": [0, 1, 1.5], "radius": 0.6, "material": "glass"}
  ]})";

std::unique_ptr<Scene> load() {
  auto s = parse_scene_json(kScene, "t.json", ".");
  EXPECT_TRUE(s) << s.error().message;
  return s ? std::move(*s) : nullptr;
}

// Client k of an in-process cluster renders threads [k t, (k + 1) t) from its queue.
struct Client {
  std::unique_ptr<cluster::PieceQueue> queue;
  std::unique_ptr<Engine> engine;
  std::map<uint64_t, std::shared_ptr<const FrameState>> frames;
  Client(const Scene& s, EngineConfig c, int k, int t, bool wait) {
    c.owned_first = k * t;
    c.owned_count = t;
    queue = std::make_unique<cluster::PieceQueue>(wait);
    engine = std::make_unique<Engine>(s, c, s.camera);
    engine->set_piece_feed(queue.get());
    engine->start();
  }
  void hand(const Engine& master, uint64_t id, const FramePiece& p, bool states) {
    auto job = std::make_unique<PieceJob>();
    job->id = id;
    job->frame = frames.at(p.serial);
    job->piece = p;
    if (states) {
      job->in.resize(p.end - p.begin);
      master.read_records(p.begin, p.end, job->in.data());
    }
    queue->push(std::move(job));
  }
  std::vector<std::unique_ptr<PieceJob>> finished() {
    size_t held = 0;
    uint64_t idle = 0;
    return queue->take_finished(held, idle);
  }
};

EngineConfig config(bool deterministic) {
  EngineConfig c;
  c.width = 40;
  c.height = 30;
  c.mode = RenderMode::conventional;
  c.deterministic = deterministic;
  c.seed = 5;
  c.samples_per_tick = 2 * 170;  // does not divide the frame: pixels change threads
  return c;
}

TEST(ClusterConventional, DeterministicMasterFramesEqualOneProcess) {
  auto s = load();
  ASSERT_TRUE(s);
  const int clients = 2, per = 2;
  EngineConfig c = config(true);
  c.threads = clients * per;
  Engine single(*s, c, s->camera);
  EngineConfig mc = c;
  mc.owned_count = 0;
  Engine master(*s, mc, s->camera);
  std::vector<std::unique_ptr<Client>> cl;
  for (int k = 0; k < clients; ++k) cl.push_back(std::make_unique<Client>(*s, c, k, per, false));
  uint64_t id = 0;
  master.set_remote_pieces([&](const FrameSpec& f, const FramePiece& stretch) {
    const uint64_t n = stretch.end - stretch.begin, threads = uint64_t(clients * per);
    for (int k = 0; k < clients; ++k) {
      cl[size_t(k)]->frames[f.serial] = cl[size_t(k)]->engine->remote_frame(f);
      for (int t = k * per; t < (k + 1) * per; ++t) {
        const uint32_t b = stretch.begin + uint32_t(n * uint64_t(t) / threads);
        const uint32_t e = stretch.begin + uint32_t(n * uint64_t(t + 1) / threads);
        if (b < e) cl[size_t(k)]->hand(master, ++id, {f.serial, b, e, stretch.t_begin + stretch.dt * (b - stretch.begin), stretch.dt}, true);
      }
      cl[size_t(k)]->engine->render_feed();
      for (auto& j : cl[size_t(k)]->finished())
        master.ingest_piece(k * per, j->piece, j->out.data(), j->samples, j->dropped);
    }
  });
  DisplayConfig dc;
  dc.refresh_hz = 30;
  DisplayThread ds(single, dc), dm(master, dc);
  single.start();
  master.start();
  int frames = 0;
  for (int k = 0; k < 40; ++k) {
    if (k == 20) {
      Camera cam = s->camera;
      cam.eye.x += 0.5f;
      single.publish_camera(cam);
      master.publish_camera(cam);
    }
    ds.step();
    dm.step();
    const DisplayImage &a = ds.acquire_latest(), &b = dm.acquire_latest();
    ASSERT_EQ(a.rgb.size(), b.rgb.size());
    size_t differ = 0;
    for (size_t i = 0; i < a.rgb.size(); ++i) differ += a.rgb[i] != b.rgb[i];
    ASSERT_EQ(differ, 0u) << "display step " << k;
    ASSERT_EQ(a.epoch, b.epoch) << "display step " << k;
    ASSERT_EQ(a.sample_count, b.sample_count) << "display step " << k;
    frames = int(master.stats().frames_completed);
  }
  EXPECT_GT(frames, 3);
  EXPECT_EQ(master.stats().frames_completed, single.stats().frames_completed);
  EXPECT_EQ(dm.acquire_latest().epoch[0], 2u);
  EXPECT_FALSE(master.error());
}

TEST(ClusterConventional, WallClockPiecesOnDemandDisplayAndCameraAtOnce) {
  auto s = load();
  ASSERT_TRUE(s);
  const int clients = 2, per = 2;
  EngineConfig c = config(false);
  c.threads = clients * per;
  EngineConfig mc = c;
  mc.owned_count = 0;
  Engine master(*s, mc, s->camera);
  std::vector<std::unique_ptr<Client>> cl;
  for (int k = 0; k < clients; ++k) cl.push_back(std::make_unique<Client>(*s, c, k, per, true));
  DisplayConfig dc;
  dc.refresh_hz = 240;
  DisplayThread d(master, dc);
  master.start();
  d.start();
  std::atomic<bool> stop{false};
  uint64_t handoffs = 0;
  std::thread comm([&] {  // the master's and the clients' communication threads in one
    cluster::TileScheduler sched(uint32_t(master.job_first_slot().size() - 1), clients);
    const std::vector<size_t>& first = master.job_first_slot();
    std::map<uint64_t, std::pair<int, uint32_t>> out;  // id -> client, job
    uint64_t id = 0;
    auto begin = [&](const FrameSpec& f) {
      for (auto& k : cl) k->frames[f.serial] = k->engine->remote_frame(f);
      sched.begin_frame(f.serial);
    };
    begin(master.current_frame());
    for (int k = 0; k < clients; ++k) sched.want(k, 3);
    while (!stop.load()) {
      for (int k = 0; k < clients; ++k)
        for (auto& j : cl[size_t(k)]->finished()) {
          const auto [client, job] = out.at(j->id);
          master.ingest_piece(k * per, j->piece, j->out.data(), j->samples, j->dropped);
          if (sched.complete(client, j->piece.serial, job)) master.publish_current_frame();
          sched.want(k, 1);
        }
      std::vector<cluster::TileScheduler::Assignment> a;
      for (;;) {
        sched.dispatch(a);
        if (!sched.may_begin_next()) break;
        begin(*master.begin_next_frame());
      }
      for (const auto& x : a) {
        out[++id] = {x.client, x.job};
        handoffs += x.handoff;
        cl[size_t(x.client)]->hand(master, id, {x.serial, uint32_t(first[x.job]), uint32_t(first[x.job + 1]), 0.0, 0.0}, x.handoff);
      }
      std::this_thread::sleep_for(std::chrono::microseconds(200));
    }
  });
  for (int k = 0; k < 100; ++k) {
    Camera cam = s->camera;
    cam.eye.x = 2.0f * std::sin(0.05f * float(k));
    master.publish_camera(cam);
    std::this_thread::sleep_for(std::chrono::milliseconds(5));
  }
  std::this_thread::sleep_for(std::chrono::milliseconds(300));  // the last camera settles
  stop = true;
  comm.join();
  d.stop();
  for (auto& k : cl) k->engine->stop();
  master.stop();
  const DisplayImage& img = d.acquire_latest();
  ASSERT_EQ(img.rgb.size(), size_t(40 * 30 * 3));
  for (float v : img.rgb) ASSERT_TRUE(std::isfinite(v));
  const uint32_t newest = master.camera_epoch();
  size_t current = 0;
  for (uint32_t ep : img.epoch) current += ep == newest;
  EXPECT_EQ(current, img.epoch.size());  // a whole frame of the newest camera
  EXPECT_GT(master.stats().frames_completed, 5u);
  EXPECT_FALSE(master.error());
}

}  // namespace
}  // namespace frameless
