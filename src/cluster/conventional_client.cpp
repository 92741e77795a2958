// A client's side of conventional frames across the cluster: pieces from the master go into a
// queue its render threads take from (the engine's PieceFeed); finished pieces go back with how
// many more it wants, so a prefetch of pieces keeps every thread busy (OpenRT's task prefetch).
#include <chrono>
#include <map>
#include <stdexcept>

#include "cluster/piece_queue.h"
#include "cluster/session_impl.h"

namespace frameless::cluster {
namespace {

uint64_t now_ns() {
  return uint64_t(std::chrono::duration_cast<std::chrono::nanoseconds>(
                      std::chrono::steady_clock::now().time_since_epoch())
                      .count());
}

}  // namespace

void Session::Impl::serve_conventional(const Scene& scene, EngineConfig c, const Camera& camera) {
  const int t = threads_per_client;
  Engine engine(scene, c, camera);
  PieceQueue feed(!c.deterministic);
  engine.set_piece_feed(&feed);
  const WireFormat format = c.deterministic ? WireFormat::exact : options.wire;
  const size_t prefetch = size_t(options.prefetch > 0 ? options.prefetch : 2 * t);
  const size_t slots = engine.job_pixels().size();
  std::map<uint64_t, std::shared_ptr<const FrameState>> frames;  // the frames pieces may name
  size_t asked = 0;                  // pieces asked for and not received yet
  uint64_t asked_at = 0, request_ns = 0, requests = 0;
  bool timing = false, attached = false;
  std::vector<uint8_t> bytes;
  Backoff backoff;
  auto spin_until = std::chrono::steady_clock::now();

  auto send_results = [&](std::vector<std::unique_ptr<PieceJob>> finished, size_t want, uint64_t idle) {
    Results r;
    r.format = format;
    r.want = uint32_t(want);
    r.idle_ns = idle;
    r.request_ns = request_ns;
    r.requests = requests;
    const EngineStats st = engine.stats();
    double busy = 0;
    for (int k = c.owned_first; k < c.owned_first + t; ++k) busy += st.threads[size_t(k)].busy_seconds;
    r.busy_ns = uint64_t(busy * 1e9);
    for (std::unique_ptr<PieceJob>& j : finished)
      r.pieces.push_back(PieceResult{j->id, j->piece, j->samples, j->dropped, std::move(j->out)});
    link->send_async(0, kTagResults, encode(r));
  };

  for (bool stop = false; !stop;) {
    bool busy = false;
    while (!stop && link->poll(0, kTagControl, bytes)) {
      busy = true;
      Control m = decode_control(bytes.data(), bytes.size());
      if (!attached) {
        engine.start();  // wall clock: the threads wait for pieces
        attached = true;
      }
      if (m.advance) throw std::invalid_argument("control.advance: conventional frames come in pieces");
      apply_changes(engine, scene, m);
      if (m.frame) {
        frames[m.frame->serial] = engine.remote_frame(*m.frame);
        while (frames.size() > 4) frames.erase(frames.begin());  // at most two are in flight
      }
      if (!m.pieces.empty() && m.format != format)
        throw std::invalid_argument("control.format: not the wire format of this run");
      for (PieceOrder& o : m.pieces) {
        const auto f = frames.find(o.piece.serial);
        if (f == frames.end()) throw std::invalid_argument("control.pieces: frame " + std::to_string(o.piece.serial) + " unknown");
        if (o.piece.end > slots) throw std::invalid_argument("control.pieces: slots beyond the image");
        auto job = std::make_unique<PieceJob>();
        job->id = o.id;
        job->frame = f->second;
        job->piece = o.piece;
        job->in = std::move(o.states);
        feed.push(std::move(job));
      }
      asked -= std::min(asked, m.pieces.size());
      if (timing && !m.pieces.empty()) {
        request_ns += now_ns() - asked_at;
        ++requests;
        timing = false;
      }
      if (c.deterministic && !m.pieces.empty()) {
        engine.render_feed();
        if (auto e = engine.error()) throw std::runtime_error("render thread failed: " + *e);
        size_t held = 0;
        uint64_t idle = 0;
        send_results(feed.take_finished(held, idle), 0, 0);
      }
      stop = m.stop;
    }
    while (link->poll(0, kTagPing, bytes)) {
      link->send(0, kTagPing, bytes);
      spin_until = std::chrono::steady_clock::now() + std::chrono::milliseconds(20);
    }
    if (attached && !c.deterministic && !stop) {
      if (auto e = engine.error()) throw std::runtime_error("render thread failed: " + *e);
      size_t held = 0;
      uint64_t idle = 0;
      std::vector<std::unique_ptr<PieceJob>> finished = feed.take_finished(held, idle);
      const size_t want = prefetch > held + asked ? prefetch - held - asked : 0;
      if (!finished.empty() || want > 0) {
        send_results(std::move(finished), want, idle);
        if (want > 0 && !timing) asked_at = now_ns(), timing = true;
        asked += want;
        busy = true;
      }
    }
    busy || std::chrono::steady_clock::now() < spin_until ? backoff.reset() : backoff.nap();
  }
  feed.close();
  engine.stop();
}

}  // namespace frameless::cluster
