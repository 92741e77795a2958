// Cluster session: MPI start and stop, the handshake, the client's loop, the master's attach.
#include <chrono>
#include <cstdio>
#include <cstring>
#include <stdexcept>

#include "cluster/change_collector.h"
#include "cluster/session_impl.h"
#include "core/scene/dynamic.h"

namespace frameless::cluster {

bool launched() { return launched_size() >= 2; }

uint64_t scene_fingerprint(const Scene& s) {
  uint64_t h = 1469598103934665603ull;  // FNV-1a over what must agree between ranks
  auto mix = [&](const void* p, size_t n) {
    const auto* b = static_cast<const uint8_t*>(p);
    for (size_t i = 0; i < n; ++i) h = (h ^ b[i]) * 1099511628211ull;
  };
  auto count = [&](size_t n) { mix(&n, sizeof n); };
  mix(s.name.data(), s.name.size());
  const Geometry& g = s.geometry;
  count(g.positions.size());
  count(g.triangles.size());
  count(g.spheres.size());
  count(g.patches.size());
  count(g.instances.size());
  count(s.materials.size());
  count(s.textures.size());
  count(s.lights.size());
  count(s.dynamic.size());
  if (!g.positions.empty()) mix(g.positions.data(), sizeof(Vec3) * std::min<size_t>(g.positions.size(), 4096));
  if (!g.spheres.empty()) mix(g.spheres.data(), sizeof(Sphere) * std::min<size_t>(g.spheres.size(), 4096));
  const float cam[10] = {s.camera.eye.x, s.camera.eye.y, s.camera.eye.z, s.camera.look.x, s.camera.look.y,
                         s.camera.look.z, s.camera.up.x, s.camera.up.y, s.camera.up.z, s.camera.fov_deg};
  mix(cam, sizeof cam);
  return h;
}

void apply_changes(Engine& engine, const Scene& scene, const Control& m) {
  if (m.camera) engine.publish_camera_as(m.camera->second, m.camera->first);
  if (!m.world.empty()) {
    WorldState w = initial_world(scene);
    if (!unpack_world(m.world.data(), m.world.size(), w))
      throw std::invalid_argument("control.world: does not match the scene");
    engine.publish_world(w);
  }
  if (!m.moves.empty()) {
    const auto top = engine.instance_top();
    const size_t instances = top ? top->position.size() : 0;
    for (const InstanceMove& mv : m.moves)
      if (mv.index >= instances) throw std::invalid_argument("control.moves: instance out of range");
    engine.move_instances(m.moves);
  }
}

Session::Session() : impl_(std::make_unique<Impl>()) {
  if (launched()) impl_->link = std::make_unique<MpiLink>();
}

Session::~Session() {
  detach();
  if (master()) impl_->release_clients();  // a master that ends early still lets its clients go
}

int Session::rank() const { return impl_->link ? impl_->link->rank() : 0; }
int Session::size() const { return impl_->link ? impl_->link->size() : 1; }

std::string Session::handshake(const std::string& error, uint64_t fingerprint, int threads) {
  Impl& d = *impl_;
  if (!d.link) throw std::logic_error("cluster: not launched by mpirun");
  Hello me;
  me.build = build_identity();
  me.scene_fingerprint = fingerprint;
  me.threads = uint32_t(std::max(0, threads));
  me.error = error;
  const std::vector<std::vector<uint8_t>> all = d.link->gather(encode(me));
  std::vector<uint8_t> verdict;
  if (master()) {
    std::string problem;
    std::vector<Hello> hellos;
    auto one_line = [](std::string& s) {  // it is printed as part of one line
      for (char& ch : s)
        if (uint8_t(ch) < 0x20) ch = ' ';
    };
    for (size_t r = 0; r < all.size() && problem.empty(); ++r) {
      try {
        hellos.push_back(decode_hello(all[r].data(), all[r].size()));
        one_line(hellos.back().error);
        one_line(hellos.back().build);
      } catch (const std::exception& ex) {
        problem = "rank " + std::to_string(r) + ": " + ex.what();
      }
    }
    for (size_t r = 0; r < hellos.size() && problem.empty(); ++r) {
      const Hello& h = hellos[r];
      const std::string who = "rank " + std::to_string(r);
      if (!h.error.empty())
        problem = who + ": " + h.error;
      else if (h.build != hellos[0].build)
        problem = who + " runs another build (" + h.build + ") than rank 0 (" + hellos[0].build + ")";
      else if (h.scene_fingerprint != hellos[0].scene_fingerprint)
        problem = who + " loaded another scene than rank 0 (same file everywhere?)";
      else if (r >= 2 && h.threads != hellos[1].threads)
        problem = who + " runs " + std::to_string(h.threads) + " render threads, rank 1 " +
                  std::to_string(hellos[1].threads) + ": give --threads";
    }
    if (problem.empty() && !hellos.empty()) d.threads_per_client = int(hellos.size() > 1 ? hellos[1].threads : 0);
    const std::string msg = problem + '\n' + std::to_string(d.threads_per_client);
    verdict.assign(msg.begin(), msg.end());
  }
  d.link->broadcast(verdict);
  const std::string text(verdict.begin(), verdict.end());
  const size_t nl = text.rfind('\n');
  d.threads_per_client = std::atoi(text.c_str() + nl + 1);
  d.serving = nl == 0 && clients() > 0;  // the clients now serve until the master releases them
  return text.substr(0, nl);
}

EngineConfig Session::master_config(EngineConfig c) const {
  c.threads = clients() * impl_->threads_per_client;
  c.owned_first = 0;
  c.owned_count = 0;
  return c;
}

int Session::serve(const Scene& scene, EngineConfig c, const Camera& camera, const ClusterOptions& o) {
  Impl& d = *impl_;
  const int t = d.threads_per_client;
  c.threads = clients() * t;
  c.owned_first = (rank() - 1) * t;
  c.owned_count = t;
  auto fail = [&](const std::string& what) -> int {
    std::fprintf(stderr, "frameless: cluster rank %d: %s\n", rank(), what.c_str());
    std::fflush(stderr);
    d.link->abort(3);
  };
  try {
    d.options = o;
    if (c.mode == RenderMode::conventional) {
      d.serve_conventional(scene, c, camera);
      d.link->flush();
      d.link->send(0, kTagBye, {});
      return 0;
    }
    Engine engine(scene, c, camera);
    ChangeCollector collector(engine, c.owned_first, t);
    auto send = [&](uint64_t tick) {
      Updates u;
      u.tick = tick;
      u.format = c.deterministic ? WireFormat::exact : o.wire;
      u.threads = collector.take(engine);
      d.link->send(0, kTagUpdates, encode(u));
    };
    // The engine starts with the master's first control message (attach() always sends one):
    // before that the master may not be receiving, and a large send would block this loop.
    bool attached = false;
    std::vector<uint8_t> bytes;
    auto last = std::chrono::steady_clock::now();
    Backoff backoff;
    auto spin_until = std::chrono::steady_clock::now();
    for (;;) {
      bool busy = false, stop = false;
      while (d.link->poll(0, kTagControl, bytes)) {
        busy = true;
        Control m = decode_control(bytes.data(), bytes.size());
        if (!attached) {
          engine.start();
          attached = true;
          last = std::chrono::steady_clock::now();
        }
        apply_changes(engine, scene, m);
        if (m.frame || !m.pieces.empty()) throw std::invalid_argument("control.pieces: this rank renders frameless");
        if (m.advance) {
          if (!c.deterministic) throw std::invalid_argument("control.advance: this rank runs on the wall clock");
          if (m.advance->first != engine.ticks())
            throw std::invalid_argument("control.advance: tick " + std::to_string(m.advance->first) +
                                        " out of order");
          engine.advance(m.advance->second);
          if (auto e = engine.error()) throw std::runtime_error("render thread failed: " + *e);
          send(m.advance->first);
        }
        if (m.stop) stop = true;
      }
      while (d.link->poll(0, kTagPing, bytes)) {
        d.link->send(0, kTagPing, bytes);
        // Answer the next pings at once (bench cluster times MPI's round trip, not our naps).
        spin_until = std::chrono::steady_clock::now() + std::chrono::milliseconds(20);
      }
      if (stop) break;
      if (attached && !c.deterministic) {
        if (auto e = engine.error()) throw std::runtime_error("render thread failed: " + *e);
        const auto now = std::chrono::steady_clock::now();
        if (now - last >= std::chrono::duration<double, std::milli>(o.batch_ms)) {
          send(~uint64_t(0));
          last = now;
          busy = true;
        }
      }
      busy || std::chrono::steady_clock::now() < spin_until ? backoff.reset() : backoff.nap();
    }
    engine.stop();
    d.link->send(0, kTagBye, {});
  } catch (const std::exception& ex) {
    return fail(ex.what());
  }
  return 0;
}

void Session::attach(Engine& engine, const Scene& scene, const ClusterOptions& o) {
  Impl& d = *impl_;
  d.engine = &engine;
  d.scene = &scene;
  d.options = o;
  d.sent_camera_epoch = 1;
  d.sent_world_epoch = 1;
  d.sent_instances_epoch = 1;
  d.sent_transforms.clear();
  if (const auto top = scene.accel.instance_top())
    for (uint32_t p : top->position) d.sent_transforms.push_back(top->instances[p].to_world);
  const bool deterministic = engine.config().deterministic;
  if (engine.config().mode == RenderMode::conventional) {
    // OpenRT's way: frame 1 (begun when the engine started) goes out, then pieces on demand.
    const size_t clients = size_t(d.link->size() - 1);
    d.client_idle_ns.assign(clients, 0);
    d.client_request_ns.assign(clients, 0);
    d.client_requests.assign(clients, 0);
    d.out_pieces.clear();
    d.sent_frame_serial = 0;
    if (deterministic) {
      engine.set_remote_pieces([&d](const FrameSpec& f, const FramePiece& p) { d.conventional_round(f, p); });
      d.send_all(Control{});  // the clients start their engines now
      return;
    }
    d.scheduler = std::make_unique<TileScheduler>(uint32_t(engine.job_first_slot().size() - 1), int(clients));
    Control first = d.frame_changes(engine.current_frame().serial);
    first.frame = engine.current_frame();
    d.send_all(first);
    d.sent_frame_serial = first.frame->serial;
    d.scheduler->begin_frame(first.frame->serial);
    d.comm_stop.store(false);
    d.comm = std::thread([&d] { d.conventional_comm_main(); });
    return;
  }
  if (deterministic) {
    engine.set_remote_advance([&d](uint64_t tick, double seconds) { d.advance_round(tick, seconds); });
  }
  d.send_all(d.changes());  // always one message: the clients start rendering now
  if (!deterministic) {
    d.comm_stop.store(false);
    d.comm = std::thread([&d] { d.comm_main(); });
  }
}

void Session::detach() {
  Impl& d = *impl_;
  if (!d.engine) return;
  if (d.comm.joinable()) {
    d.comm_stop.store(true, std::memory_order_release);
    d.comm.join();
  }
  d.engine->set_remote_advance(nullptr);
  d.engine->set_remote_pieces(nullptr);
  d.scheduler.reset();
  d.engine = nullptr;
  d.release_clients();
}

void Session::Impl::release_clients() {
  if (!serving) return;
  serving = false;
  Control stop;
  stop.stop = true;
  send_all(stop);
  // Updates still in flight are taken (and dropped: the engine may be stopping) until every
  // client said goodbye, so no client is left blocked in a send.
  std::vector<uint8_t> bytes;
  for (int r = 1; r < link->size(); ++r) {
    Backoff backoff;
    while (!link->poll(r, kTagBye, bytes))
      if (!link->poll(r, kTagUpdates, bytes) && !link->poll(r, kTagResults, bytes)) backoff.nap();
  }
}

ClusterStats Session::stats() const {
  std::lock_guard<std::mutex> lock(impl_->stats_mutex);
  return impl_->stats;
}

double Session::ping(int client) {
  Impl& d = *impl_;
  std::vector<uint8_t> bytes(16, 0), back;
  const auto t0 = std::chrono::steady_clock::now();
  d.link->send(client, kTagPing, bytes);
  while (!d.link->poll(client, kTagPing, back)) {
  }
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

}  // namespace frameless::cluster
