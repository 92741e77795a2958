// Byte encoding of conventional mode's pieces: frame specs, piece orders, whole pixel states
// and the clients' results (wire.h).
#include "cluster/wire_pieces.h"

#include <algorithm>

namespace frameless::cluster {
using namespace wire_io;

namespace {

constexpr uint32_t kMaxPieceSlots = 1u << 24;  // more than any image's pixels (16384^2 / 16)

void put_record(Writer& w, const PixelRecord& r, WireFormat f) {
  w.put(r.passes);
  w.put(r.count);
  w.put(r.epoch);
  if (f == WireFormat::rgbe) {
    uint8_t rgbe[8];
    encode_rgbe(r.sample, rgbe);
    encode_rgbe(Vec3(float(r.mean[0]), float(r.mean[1]), float(r.mean[2])), rgbe + 4);
    for (uint8_t byte : rgbe) w.put(byte);
    w.put(to_bfloat16(r.count > 1 ? float(r.m2 / double(r.count - 1)) : 0.0f));
  } else {
    for (double m : r.mean) w.put(m);
    w.put(r.m2);
    for (int k = 0; k < 3; ++k) w.put(r.sample[k]);
  }
  w.put(r.time);
  w.put(r.levels);
}

PixelRecord get_record(Reader& rd, WireFormat f) {
  PixelRecord r;
  r.passes = rd.get<uint32_t>("record.passes");
  r.count = rd.get<uint32_t>("record.count");
  r.epoch = rd.get<uint32_t>("record.epoch");
  if (r.epoch > 0 && r.count == 0) rd.fail("record.count", "a sampled pixel without samples");
  if (f == WireFormat::rgbe) {
    uint8_t rgbe[8];
    for (uint8_t& byte : rgbe) byte = rd.get<uint8_t>("record.rgbe");
    if (!canonical_rgbe(rgbe) || !canonical_rgbe(rgbe + 4)) rd.fail("record.rgbe", "not a canonical RGBE colour");
    r.sample = decode_rgbe(rgbe);
    const Vec3 mean = decode_rgbe(rgbe + 4);
    for (int k = 0; k < 3; ++k) r.mean[k] = mean[k];
    const float variance = from_bfloat16(rd.get<uint16_t>("record.variance"));
    if (!std::isfinite(variance) || variance < 0.0f) rd.fail("record.variance", "not finite and non-negative");
    if (variance != 0.0f && r.count < 2) rd.fail("record.variance", "non-zero with fewer than two samples");
    r.m2 = r.count > 1 ? double(variance) * double(r.count - 1) : 0.0;
  } else {
    for (double& m : r.mean) {
      m = rd.get<double>("record.mean");
      if (!std::isfinite(m)) rd.fail("record.mean", "not finite");
    }
    r.m2 = rd.get<double>("record.m2");
    if (!std::isfinite(r.m2) || r.m2 < 0.0) rd.fail("record.m2", "not finite and non-negative");
    for (int k = 0; k < 3; ++k) r.sample[k] = rd.finite("record.sample");
  }
  r.time = rd.finite("record.time");
  r.levels = rd.get<uint8_t>("record.levels");
  return r;
}

void put_piece(Writer& w, const FramePiece& p) {
  w.put(p.serial);
  w.put(p.begin);
  w.put(p.end);
  w.put(p.t_begin);
  w.put(p.dt);
}

FramePiece get_piece(Reader& r) {
  FramePiece p;
  p.serial = r.get<uint64_t>("piece.serial");
  p.begin = r.get<uint32_t>("piece.begin");
  p.end = r.get<uint32_t>("piece.end");
  if (p.serial < 1) r.fail("piece.serial", "must be at least 1");
  if (p.end <= p.begin || p.end - p.begin > kMaxPieceSlots) r.fail("piece.end", "empty or too large");
  p.t_begin = r.get<double>("piece.t_begin");
  p.dt = r.get<double>("piece.dt");
  if (!std::isfinite(p.t_begin) || !std::isfinite(p.dt) || p.dt < 0.0) r.fail("piece.dt", "not finite and non-negative");
  return p;
}

void put_records(Writer& w, const std::vector<PixelRecord>& records, WireFormat f) {
  w.put(uint32_t(records.size()));
  for (const PixelRecord& r : records) put_record(w, r, f);
}

// Records of a piece: exactly one per slot (or none, where `optional`).
std::vector<PixelRecord> get_records(Reader& r, const FramePiece& p, WireFormat f, bool optional) {
  const uint32_t n = r.count("records", piece_record_bytes(f));
  if (n != p.end - p.begin && !(optional && n == 0)) r.fail("records", "not one per slot of the piece");
  std::vector<PixelRecord> out(n);
  for (PixelRecord& rec : out) rec = get_record(r, f);
  return out;
}

WireFormat get_format(Reader& r) {
  const uint32_t format = r.get<uint32_t>("format");
  if (format > uint32_t(WireFormat::rgbe)) r.fail("format", "unknown wire format " + std::to_string(format));
  return WireFormat(format);
}

}  // namespace

void put_frame_and_pieces(Writer& w, const Control& m) {
  if (m.frame) {
    w.put(m.frame->serial);
    w.put(m.frame->epoch);
    put_camera(w, m.frame->camera);
    w.put(m.frame->time);
  }
  if (!m.pieces.empty()) {
    w.put(uint32_t(m.format));
    w.put(uint32_t(m.pieces.size()));
    for (const PieceOrder& o : m.pieces) {
      w.put(o.id);
      put_piece(w, o.piece);
      put_records(w, o.states, m.format);
    }
  }
}

void get_frame_and_pieces(Reader& r, Control& m, bool frame, bool pieces) {
  if (frame) {
    FrameSpec f;
    f.serial = r.get<uint64_t>("frame.serial");
    f.epoch = r.get<uint32_t>("frame.epoch");
    if (f.serial < 1 || f.epoch < 1) r.fail("frame", "serial and epoch must be at least 1");
    f.camera = get_camera(r);
    f.time = r.get<double>("frame.time");
    if (!std::isfinite(f.time)) r.fail("frame.time", "not finite");
    m.frame = f;
  }
  if (pieces) {
    m.format = get_format(r);
    const uint32_t n = r.count("pieces", 44);
    if (n == 0) r.fail("pieces", "empty");
    m.pieces.resize(n);
    for (PieceOrder& o : m.pieces) {
      o.id = r.get<uint64_t>("piece.id");
      o.piece = get_piece(r);
      o.states = get_records(r, o.piece, m.format, true);
    }
  }
}

std::vector<uint8_t> encode(const Results& m) {
  size_t records = 0;
  for (const PieceResult& p : m.pieces) records += p.records.size();
  Writer w(64 + 64 * m.pieces.size() + piece_record_bytes(m.format) * records);
  w.put(uint32_t(m.format));
  w.put(m.want);
  w.put(m.idle_ns);
  w.put(m.request_ns);
  w.put(m.requests);
  w.put(m.busy_ns);
  w.put(uint32_t(m.pieces.size()));
  for (const PieceResult& p : m.pieces) {
    w.put(p.id);
    put_piece(w, p.piece);
    w.put(p.samples);
    w.put(p.dropped);
    put_records(w, p.records, m.format);
  }
  return w.take();
}

Results decode_results(const uint8_t* data, size_t size) {
  Reader r(data, size, "results");
  Results m;
  m.format = get_format(r);
  m.want = r.get<uint32_t>("want");
  if (m.want > 4096) r.fail("want", "more than 4096 pieces");
  m.idle_ns = r.get<uint64_t>("idle_ns");
  m.request_ns = r.get<uint64_t>("request_ns");
  m.requests = r.get<uint64_t>("requests");
  m.busy_ns = r.get<uint64_t>("busy_ns");
  m.pieces.resize(r.count("pieces", 60));
  for (PieceResult& p : m.pieces) {
    p.id = r.get<uint64_t>("piece.id");
    p.piece = get_piece(r);
    p.samples = r.get<uint64_t>("piece.samples");
    p.dropped = r.get<uint64_t>("piece.dropped");
    if (p.samples > 2ull * (p.piece.end - p.piece.begin) || p.dropped > p.samples)
      r.fail("piece.samples", "more than two per slot");
    p.records = get_records(r, p.piece, m.format, false);
  }
  r.end();
  return m;
}

}  // namespace frameless::cluster
