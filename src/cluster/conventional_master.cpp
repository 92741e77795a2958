// The master's side of conventional frames across the cluster (OpenRT's distribution, seed
// 002): frame specs out, pieces handed out on demand with affinity and stealing (TileScheduler),
// finished pieces in and assembled into the master's frames; a deterministic round splits a
// stretch of a frame over the clients exactly as one process splits it over its threads.
#include <chrono>
#include <stdexcept>

#include "cluster/session_impl.h"
#include "frameless/cpu_clock.h"

namespace frameless::cluster {

void Session::Impl::take_results(int from, const std::vector<uint8_t>& bytes) {
  uint64_t records = 0;
  try {
    const Results m = decode_results(bytes.data(), bytes.size());
    if (m.format != (engine->config().deterministic ? WireFormat::exact : options.wire))
      throw std::invalid_argument("results.format: not the wire format of this run");
    const int client = from - 1;
    for (const PieceResult& p : m.pieces) {
      const auto it = out_pieces.find(p.id);
      if (it == out_pieces.end() || it->second.client != client)
        throw std::invalid_argument("piece " + std::to_string(p.id) + " was not handed to it");
      const FramePiece sent = it->second.piece;  // a copy: the entry goes below
      if (p.piece.serial != sent.serial || p.piece.begin != sent.begin || p.piece.end != sent.end)
        throw std::invalid_argument("piece " + std::to_string(p.id) + " does not cover what was handed out");
      const uint32_t job = it->second.job;
      out_pieces.erase(it);
      engine->ingest_piece(client * threads_per_client, sent, p.records.data(), p.samples, p.dropped, m.busy_ns);
      records += p.records.size();
      if (scheduler && scheduler->complete(client, sent.serial, job)) engine->publish_current_frame();
    }
    if (scheduler) scheduler->want(client, m.want);
    client_idle_ns[size_t(client)] = m.idle_ns;
    client_request_ns[size_t(client)] = m.request_ns;
    client_requests[size_t(client)] = m.requests;
  } catch (const std::exception& ex) {
    fail("message from rank " + std::to_string(from) + " rejected: " + ex.what());
  }
  std::lock_guard<std::mutex> lock(stats_mutex);
  ++stats.messages;
  stats.bytes += bytes.size();
  stats.pixel_records += records;
  stats.client_idle_seconds = stats.request_seconds = 0;
  stats.requests = 0;
  for (size_t c = 0; c < client_idle_ns.size(); ++c) {
    stats.client_idle_seconds += double(client_idle_ns[c]) * 1e-9;
    stats.request_seconds += double(client_request_ns[c]) * 1e-9;
    stats.requests += client_requests[c];
  }
  if (scheduler) {
    stats.pieces = scheduler->handed_out();
    stats.steals = scheduler->steals();
    stats.handoffs = scheduler->handoffs();
  }
}

void Session::Impl::send_pieces(std::vector<TileScheduler::Assignment>& assigned) {
  const std::vector<size_t>& first = engine->job_first_slot();
  std::vector<Control> per_client(size_t(link->size() - 1));
  for (const TileScheduler::Assignment& a : assigned) {
    Control& c = per_client[size_t(a.client)];
    c.format = options.wire;
    PieceOrder o;
    o.id = next_piece_id++;
    o.piece.serial = a.serial;
    o.piece.begin = uint32_t(first[a.job]);
    o.piece.end = uint32_t(first[a.job + 1]);
    if (a.handoff) {  // the client that rendered it last has the states: they go along
      o.states.resize(o.piece.end - o.piece.begin);
      engine->read_records(o.piece.begin, o.piece.end, o.states.data());
    }
    out_pieces[o.id] = OutPiece{a.client, a.job, o.piece};
    c.pieces.push_back(std::move(o));
  }
  assigned.clear();
  for (size_t k = 0; k < per_client.size(); ++k)
    if (!per_client[k].pieces.empty()) link->send_async(int(k) + 1, kTagControl, encode(per_client[k]));
}

void Session::Impl::begin_frames_and_dispatch() {
  std::vector<TileScheduler::Assignment> assigned;
  for (;;) {
    scheduler->dispatch(assigned);
    if (!scheduler->may_begin_next()) break;
    // Every piece of the newest frame is out: the next frame begins now (asynchronous
    // rendering), with what changed since the last one (differential) ahead of its spec.
    send_pieces(assigned);
    const std::optional<FrameSpec> spec = engine->begin_next_frame();
    if (!spec) throw std::logic_error("cluster: next frame already begun");
    Control c = frame_changes(spec->serial);
    c.frame = *spec;
    const std::vector<uint8_t> bytes = encode(c);
    for (int r = 1; r < link->size(); ++r) link->send_async(r, kTagControl, bytes);
    scheduler->begin_frame(spec->serial);
  }
  send_pieces(assigned);
}

void Session::Impl::conventional_comm_main() {
  const double cpu0 = thread_cpu_seconds();
  Backoff backoff;
  std::vector<uint8_t> bytes;
  int from = 0;
  try {
    while (!comm_stop.load(std::memory_order_acquire)) {
      bool busy = false;
      while (link->poll(-1, kTagResults, bytes, &from)) {
        take_results(from, bytes);
        busy = true;
      }
      if (busy) begin_frames_and_dispatch();
      busy ? backoff.reset() : backoff.nap();
      std::lock_guard<std::mutex> lock(stats_mutex);
      stats.comm_cpu_seconds = thread_cpu_seconds() - cpu0;
    }
  } catch (const std::exception& ex) {
    fail(ex.what());
  }
}

void Session::Impl::conventional_round(const FrameSpec& spec, const FramePiece& stretch) {
  // The stretch's slots split over all render threads of the cluster as Engine::advance()
  // splits them over one process's threads; client c renders threads [c T, (c + 1) T).
  const int clients = link->size() - 1;
  const uint64_t threads = uint64_t(clients) * uint64_t(threads_per_client);
  const uint64_t take = stretch.end - stretch.begin;
  std::vector<bool> expect(size_t(clients), false);
  Control news;  // a new frame: what changed (differential), then its spec, to every client
  if (spec.serial != sent_frame_serial) {
    news = frame_changes(spec.serial);
    news.frame = spec;
  }
  for (int c = 0; c < clients; ++c) {
    Control m = news;
    for (int t = c * threads_per_client; t < (c + 1) * threads_per_client; ++t) {
      const uint32_t b = stretch.begin + uint32_t(take * uint64_t(t) / threads);
      const uint32_t e = stretch.begin + uint32_t(take * uint64_t(t + 1) / threads);
      if (b == e) continue;
      PieceOrder o;
      o.id = next_piece_id++;
      o.piece = FramePiece{spec.serial, b, e, stretch.t_begin + stretch.dt * double(b - stretch.begin), stretch.dt};
      o.states.resize(e - b);  // a pixel moves between threads from tick to tick: states go along
      engine->read_records(b, e, o.states.data());
      out_pieces[o.id] = OutPiece{c, ~uint32_t(0), o.piece};
      m.pieces.push_back(std::move(o));
    }
    expect[size_t(c)] = !m.pieces.empty();
    if (expect[size_t(c)] || m.frame) link->send_async(c + 1, kTagControl, encode(m));
  }
  sent_frame_serial = spec.serial;
  std::vector<uint8_t> bytes;
  for (int c = 0; c < clients; ++c) {
    if (!expect[size_t(c)]) continue;
    Backoff backoff;
    while (!link->poll(c + 1, kTagResults, bytes)) backoff.nap();
    take_results(c + 1, bytes);
  }
  if (!out_pieces.empty()) fail("a client did not return every piece of a deterministic round");
}

}  // namespace frameless::cluster
