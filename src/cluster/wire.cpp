// Byte encoding of the cluster's messages: little-endian fixed-width fields, counts before
// arrays, every read bounds-checked.
#include "cluster/wire.h"
#include "cluster/wire_io.h"
#include "cluster/wire_pieces.h"

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <stdexcept>

namespace frameless::cluster {
using namespace wire_io;

namespace {

constexpr uint32_t kCamera = 1, kWorld = 2, kMoves = 4, kAdvance = 8, kStop = 16, kFrame = 32,
                   kPieces = 64;  // Control kind bits

}  // namespace

std::vector<uint8_t> encode(const Hello& m) {
  Writer w;
  w.str(m.build);
  w.put(m.scene_fingerprint);
  w.put(m.threads);
  w.str(m.error);
  return w.take();
}

Hello decode_hello(const uint8_t* data, size_t size) {
  Reader r(data, size, "hello");
  Hello m;
  m.build = r.str("build", 256);
  m.scene_fingerprint = r.get<uint64_t>("scene");
  m.threads = r.get<uint32_t>("threads");
  if (m.threads > 1024) r.fail("threads", "more than 1024");
  m.error = r.str("error", 4096);
  r.end();
  return m;
}

std::vector<uint8_t> encode(const Control& m) {
  Writer w(128 + 4 * m.world.size() + 52 * m.moves.size());
  const uint32_t bits = (m.camera ? kCamera : 0) | (m.world.empty() ? 0 : kWorld) |
                        (m.moves.empty() ? 0 : kMoves) | (m.advance ? kAdvance : 0) | (m.stop ? kStop : 0) |
                        (m.frame ? kFrame : 0) | (m.pieces.empty() ? 0 : kPieces);
  w.put(bits);
  if (m.camera) {
    w.put(m.camera->first);
    put_camera(w, m.camera->second);
  }
  if (!m.world.empty()) {
    w.put(uint32_t(m.world.size()));
    for (float f : m.world) w.put(f);
  }
  if (!m.moves.empty()) {
    w.put(uint32_t(m.moves.size()));
    for (const InstanceMove& mv : m.moves) {
      w.put(mv.index);
      for (int c = 0; c < 3; ++c)
        for (int k = 0; k < 3; ++k) w.put(mv.to_world.m[c][k]);
      for (int k = 0; k < 3; ++k) w.put(mv.to_world.t[k]);
    }
  }
  if (m.advance) {
    w.put(m.advance->first);
    w.put(m.advance->second);
  }
  put_frame_and_pieces(w, m);
  return w.take();
}

Control decode_control(const uint8_t* data, size_t size) {
  Reader r(data, size, "control");
  Control m;
  const uint32_t bits = r.get<uint32_t>("kind");
  if (bits & ~uint32_t(kCamera | kWorld | kMoves | kAdvance | kStop | kFrame | kPieces)) r.fail("kind", "unknown bits");
  if (bits & kCamera) {
    const uint32_t epoch = r.get<uint32_t>("camera.epoch");
    if (epoch < 1) r.fail("camera.epoch", "must be at least 1");
    m.camera.emplace(epoch, get_camera(r));
  }
  if (bits & kWorld) {
    const uint32_t n = r.count("world", 4);
    if (n == 0) r.fail("world", "empty");
    m.world.resize(n);
    for (float& f : m.world) f = r.finite("world");
  }
  if (bits & kMoves) {
    const uint32_t n = r.count("moves", 52);
    if (n == 0) r.fail("moves", "empty");
    m.moves.resize(n);
    for (InstanceMove& mv : m.moves) {
      mv.index = r.get<uint32_t>("moves.index");
      for (int c = 0; c < 3; ++c)
        for (int k = 0; k < 3; ++k) mv.to_world.m[c][k] = r.finite("moves.matrix");
      for (int k = 0; k < 3; ++k) mv.to_world.t[k] = r.finite("moves.offset");
    }
  }
  if (bits & kAdvance) {
    const uint64_t tick = r.get<uint64_t>("advance.tick");
    const double seconds = r.get<double>("advance.seconds");
    if (!(seconds > 0.0 && seconds <= 1.0)) r.fail("advance.seconds", "must be in (0, 1]");
    m.advance.emplace(tick, seconds);
  }
  get_frame_and_pieces(r, m, bits & kFrame, bits & kPieces);
  m.stop = bits & kStop;
  r.end();
  return m;
}

void encode_rgbe(const Vec3& c, uint8_t out[4]) {
  const float r = std::max(c.x, 0.0f), g = std::max(c.y, 0.0f), b = std::max(c.z, 0.0f);
  const float v = std::max({r, g, b});
  if (!(v >= 1e-32f)) {
    out[0] = out[1] = out[2] = out[3] = 0;
    return;
  }
  int e = 0;
  const float scale = std::frexp(v, &e) * 256.0f / v;  // v = m 2^e, m in [0.5, 1)
  if (e > 127) e = 127, out[0] = out[1] = out[2] = 255;  // beyond any radiance: saturate
  else
    for (int k = 0; k < 3; ++k) out[k] = uint8_t(std::min(255.0f, c[k] > 0 ? c[k] * scale : 0.0f));
  out[3] = uint8_t(e + 128);
}

// Canonical: what encode_rgbe makes of the colour it decodes to, so every colour has one
// encoding (the encoder also sends colours below 1e-32 as black, which a mantissa test missed).
bool canonical_rgbe(const uint8_t in[4]) {
  uint8_t again[4];
  encode_rgbe(decode_rgbe(in), again);
  return std::memcmp(again, in, 4) == 0;
}

Vec3 decode_rgbe(const uint8_t in[4]) {
  if (in[3] == 0) return Vec3(0.0f);
  const float f = std::ldexp(1.0f, int(in[3]) - (128 + 8));
  return Vec3((float(in[0]) + 0.5f) * f, (float(in[1]) + 0.5f) * f, (float(in[2]) + 0.5f) * f);
}

std::vector<uint8_t> encode(const Updates& m) {
  size_t slots = 0;
  for (const RemoteBatch& b : m.threads) slots += b.slots.size();
  Writer w(32 + 40 * m.threads.size() + record_bytes(m.format) * slots);
  w.put(m.tick);
  w.put(uint32_t(m.format));
  w.put(uint32_t(m.threads.size()));
  for (const RemoteBatch& b : m.threads) {
    w.put(uint32_t(b.thread));
    w.put(b.updates);
    w.put(b.samples);
    w.put(b.dropped);
    w.put(b.busy_ns);
    w.put(uint32_t(b.slots.size()));
    for (const RemoteSlot& s : b.slots) {
      w.put(s.slot);
      w.put(s.state.count);
      w.put(s.state.epoch);
      if (m.format == WireFormat::rgbe) {
        uint8_t rgbe[8];
        encode_rgbe(s.state.sample, rgbe);
        encode_rgbe(s.state.mean, rgbe + 4);
        for (uint8_t byte : rgbe) w.put(byte);
        w.put(to_bfloat16(s.state.variance));
      } else {
        for (int k = 0; k < 3; ++k) w.put(s.state.sample[k]);
        for (int k = 0; k < 3; ++k) w.put(s.state.mean[k]);
        w.put(s.state.variance);
      }
      w.put(s.state.time);
      w.put(s.state.levels);
    }
  }
  return w.take();
}

Updates decode_updates(const uint8_t* data, size_t size) {
  Reader r(data, size, "updates");
  Updates m;
  m.tick = r.get<uint64_t>("tick");
  const uint32_t format = r.get<uint32_t>("format");
  if (format > uint32_t(WireFormat::rgbe)) r.fail("format", "unknown wire format " + std::to_string(format));
  m.format = WireFormat(format);
  const size_t record = record_bytes(m.format);
  const uint32_t threads = r.count("threads", 40);
  if (threads > 1024) r.fail("threads", "more than 1024");
  m.threads.resize(threads);
  for (RemoteBatch& b : m.threads) {
    const uint32_t t = r.get<uint32_t>("thread");
    if (t >= 1u << 20) r.fail("thread", "index out of range");
    b.thread = int(t);
    b.updates = r.get<uint64_t>("updates");
    b.samples = r.get<uint64_t>("samples");
    b.dropped = r.get<uint64_t>("dropped");
    b.busy_ns = r.get<uint64_t>("busy_ns");
    b.slots.resize(r.count("slots", record));
    for (RemoteSlot& s : b.slots) {
      s.slot = r.get<uint32_t>("slot");
      s.state.count = r.get<uint32_t>("count");
      s.state.epoch = r.get<uint32_t>("epoch");
      if (m.format == WireFormat::rgbe) {
        uint8_t rgbe[8];
        for (uint8_t& byte : rgbe) byte = r.get<uint8_t>("rgbe");
        if (!canonical_rgbe(rgbe) || !canonical_rgbe(rgbe + 4))  // one encoding per colour
          r.fail("rgbe", "not a canonical RGBE colour");
        s.state.sample = decode_rgbe(rgbe);
        s.state.mean = decode_rgbe(rgbe + 4);
        s.state.variance = from_bfloat16(r.get<uint16_t>("variance"));
        if (!std::isfinite(s.state.variance)) r.fail("variance", "not finite");
      } else {
        for (int k = 0; k < 3; ++k) s.state.sample[k] = r.finite("sample");
        for (int k = 0; k < 3; ++k) s.state.mean[k] = r.finite("mean");
        s.state.variance = r.finite("variance");
      }
      if (s.state.variance < 0.0f) r.fail("variance", "negative");
      s.state.time = r.finite("time");
      s.state.levels = r.get<uint8_t>("levels");
    }
  }
  r.end();
  return m;
}

std::string build_identity() {
  if (const char* o = std::getenv("FRAMELESS_TEST_BUILD_ID"); o && *o) return o;
  return std::string("frameless ") + FRAMELESS_VERSION + " wire " + std::to_string(kWireVersion) +
         " " + __VERSION__ + " pixel " + std::to_string(sizeof(PixelState));
}

}  // namespace frameless::cluster
