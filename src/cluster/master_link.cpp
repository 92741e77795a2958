// The master's side of the cluster: differential control messages out, pixel updates in.
#include <cstdio>
#include <stdexcept>

#include "cluster/session_impl.h"
#include "core/scene/dynamic.h"
#include "frameless/cpu_clock.h"
#include "frameless/output_commit.h"

namespace frameless::cluster {

void Session::Impl::fail(const std::string& line) {
  std::fprintf(stderr, "frameless: cluster: %s\n", line.c_str());
  std::fflush(stderr);
  // A capture frame being written is finished and listed first; held until the process is gone.
  const std::unique_lock<std::mutex> frozen = freeze_output_commits();
  link->abort(3);  // every rank ends now: a fault must not hang the job
}

Control Session::Impl::changes() {
  Control c;
  uint32_t epoch = 0;
  const Camera cam = engine->camera(&epoch);
  if (epoch != sent_camera_epoch) {
    c.camera.emplace(epoch, cam);
    sent_camera_epoch = epoch;
  }
  if (const uint32_t w = engine->world_epoch(); w != sent_world_epoch) {
    pack_world(engine->world(), c.world);
    sent_world_epoch = w;
  }
  if (const uint32_t i = engine->instances_epoch(); i != sent_instances_epoch)
    add_moves(c, i, engine->instance_top());  // one snapshot
  return c;
}

Control Session::Impl::frame_changes(uint64_t serial) {
  // A conventional frame sees the world and instances of the instant it began, which may be
  // older than the newest: the clients get exactly those.
  const FrameWorld f = engine->frame_world(serial);
  Control c;
  if (f.world_epoch != sent_world_epoch) {
    pack_world(f.world, c.world);
    sent_world_epoch = f.world_epoch;
  }
  if (f.instances_epoch != sent_instances_epoch)
    add_moves(c, f.instances_epoch, f.instances ? f.instances : scene->accel.instance_top());
  return c;
}

void Session::Impl::add_moves(Control& c, uint32_t epoch, const std::shared_ptr<const InstanceTop>& top) {
  // Only the instances whose transform differs from what the clients have (attach() filled
  // sent_transforms with the declared ones: what every client built).
  for (uint32_t k = 0; top && k < sent_transforms.size() && k < top->position.size(); ++k) {
    const Affine& a = top->instances[top->position[k]].to_world;
    const Affine& old = sent_transforms[k];
    if (a.m != old.m || a.t != old.t) {
      c.moves.push_back({k, a});
      sent_transforms[k] = a;
    }
  }
  sent_instances_epoch = epoch;
}

void Session::Impl::send_all(const Control& c) {
  const std::vector<uint8_t> bytes = encode(c);
  for (int r = 1; r < link->size(); ++r) link->send(r, kTagControl, bytes);
  std::lock_guard<std::mutex> lock(stats_mutex);
  ++stats.controls;
}

std::optional<uint64_t> Session::Impl::receive_updates(int source) {
  std::vector<uint8_t> bytes;
  int from = 0;
  if (!link->poll(source, kTagUpdates, bytes, &from)) return std::nullopt;
  uint64_t records = 0;
  Updates u;
  try {
    u = decode_updates(bytes.data(), bytes.size());
    const int first = (from - 1) * threads_per_client;
    for (const RemoteBatch& b : u.threads) {
      if (b.thread < first || b.thread >= first + threads_per_client)
        throw std::invalid_argument("updates.thread: " + std::to_string(b.thread) + " is not one of its threads");
      engine->ingest(b);
      records += b.slots.size();
    }
  } catch (const std::exception& ex) {
    fail("message from rank " + std::to_string(from) + " rejected: " + ex.what());
  }
  std::lock_guard<std::mutex> lock(stats_mutex);
  ++stats.messages;
  stats.bytes += bytes.size();
  stats.pixel_records += records;
  return u.tick;
}

void Session::Impl::comm_main() {
  const double cpu0 = thread_cpu_seconds();
  Backoff backoff;
  while (!comm_stop.load(std::memory_order_acquire)) {
    bool busy = false;
    if (Control c = changes(); has_changes(c)) {
      send_all(c);
      busy = true;
    }
    while (receive_updates(-1)) busy = true;
    busy ? backoff.reset() : backoff.nap();
    std::lock_guard<std::mutex> lock(stats_mutex);
    stats.comm_cpu_seconds = thread_cpu_seconds() - cpu0;
  }
}

void Session::Impl::advance_round(uint64_t tick, double seconds) {
  Control c = changes();
  c.advance.emplace(tick, seconds);
  send_all(c);
  // Each client answers with exactly one update message for this tick.
  for (int r = 1; r < link->size(); ++r) {
    Backoff backoff;
    std::optional<uint64_t> got;
    while (!(got = receive_updates(r))) backoff.nap();
    if (*got != tick)
      fail("rank " + std::to_string(r) + " answered tick " + std::to_string(*got) + " for tick " +
           std::to_string(tick));
  }
}

}  // namespace frameless::cluster
