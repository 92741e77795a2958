// The cluster's wire format: every message survives a round trip exactly, and every malformed
// message (truncated anywhere, wrong magic or version, counts beyond the message, non-finite
// values, trailing bytes) is refused with a one-line std::invalid_argument, never read past.
#include <gtest/gtest.h>

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstring>
#include <limits>

#include "cluster/wire.h"

namespace frameless::cluster {
namespace {

Updates sample_updates() {
  Updates u;
  u.tick = 42;
  for (int t = 3; t < 5; ++t) {
    RemoteBatch b;
    b.thread = t;
    b.updates = 1000 + t;
    b.samples = 2000 + t;
    b.dropped = t;
    b.busy_ns = 123456789;
    for (uint32_t s = 0; s < 3; ++s) {
      RemoteSlot r;
      r.slot = 100 * uint32_t(t) + s;
      r.state.count = 5 + s;
      r.state.epoch = 2;
      r.state.sample = Vec3(0.1f * float(s), 1e-30f, 65504.0f);
      r.state.mean = Vec3(0.25f, 0.5f, 0.75f);
      r.state.variance = 0.01f * float(s);
      r.state.time = 1.5f;
      r.state.levels = uint8_t(s * 7);
      b.slots.push_back(r);
    }
    u.threads.push_back(b);
  }
  return u;
}

Control sample_control() {
  Control c;
  Camera cam;
  cam.eye = {1, 2, 3};
  cam.look = {0, 0, 0};
  cam.up = {0, 1, 0};
  cam.fov_deg = 50;
  c.camera.emplace(7u, cam);
  c.world = {1.0f, -2.0f, 3.5f};
  Affine a;
  a.t = {4, 5, 6};
  a.m[1][2] = 0.5f;
  c.moves.push_back({9, a});
  c.advance.emplace(12u, 1.0 / 30.0);
  return c;
}

TEST(Wire, UpdatesRoundTripExactly) {
  const Updates u = sample_updates();
  const std::vector<uint8_t> bytes = encode(u);
  EXPECT_EQ(bytes.size(), 8 + 8 + 4 + 4 + 2 * (4 + 32 + 4 + 3 * kSlotRecordBytes));
  const Updates d = decode_updates(bytes.data(), bytes.size());
  EXPECT_EQ(d.tick, 42u);
  ASSERT_EQ(d.threads.size(), 2u);
  for (size_t t = 0; t < 2; ++t) {
    const RemoteBatch &a = u.threads[t], &b = d.threads[t];
    EXPECT_EQ(a.thread, b.thread);
    EXPECT_EQ(a.updates, b.updates);
    EXPECT_EQ(a.samples, b.samples);
    EXPECT_EQ(a.dropped, b.dropped);
    EXPECT_EQ(a.busy_ns, b.busy_ns);
    ASSERT_EQ(a.slots.size(), b.slots.size());
    for (size_t s = 0; s < a.slots.size(); ++s) {
      const PixelSnapshot &x = a.slots[s].state, &y = b.slots[s].state;
      EXPECT_EQ(a.slots[s].slot, b.slots[s].slot);
      EXPECT_EQ(x.count, y.count);
      EXPECT_EQ(x.epoch, y.epoch);
      EXPECT_EQ(x.sample, y.sample);
      EXPECT_EQ(x.mean, y.mean);
      EXPECT_EQ(x.variance, y.variance);
      EXPECT_EQ(x.time, y.time);
      EXPECT_EQ(x.levels, y.levels);
    }
  }
}

TEST(Wire, ControlAndHelloRoundTrip) {
  const Control c = sample_control();
  const std::vector<uint8_t> bytes = encode(c);
  const Control d = decode_control(bytes.data(), bytes.size());
  ASSERT_TRUE(d.camera);
  EXPECT_EQ(d.camera->first, 7u);
  EXPECT_EQ(d.camera->second.eye, c.camera->second.eye);
  EXPECT_EQ(d.world, c.world);
  ASSERT_EQ(d.moves.size(), 1u);
  EXPECT_EQ(d.moves[0].index, 9u);
  EXPECT_EQ(d.moves[0].to_world.m, c.moves[0].to_world.m);
  EXPECT_EQ(d.moves[0].to_world.t, c.moves[0].to_world.t);
  ASSERT_TRUE(d.advance);
  EXPECT_EQ(d.advance->first, 12u);
  EXPECT_EQ(d.advance->second, 1.0 / 30.0);
  EXPECT_FALSE(d.stop);
  Control stop;
  stop.stop = true;
  const std::vector<uint8_t> sb = encode(stop);
  const Control ds = decode_control(sb.data(), sb.size());
  EXPECT_TRUE(ds.stop);
  EXPECT_FALSE(ds.camera || ds.advance || !ds.world.empty() || !ds.moves.empty());

  Hello h;
  h.build = "b";
  h.scene_fingerprint = 99;
  h.threads = 4;
  h.error = "x.json: no such file";
  const std::vector<uint8_t> hb = encode(h);
  const Hello dh = decode_hello(hb.data(), hb.size());
  EXPECT_EQ(dh.build, "b");
  EXPECT_EQ(dh.scene_fingerprint, 99u);
  EXPECT_EQ(dh.threads, 4u);
  EXPECT_EQ(dh.error, h.error);
}

template <class F>
std::string refusal(F decode, const std::vector<uint8_t>& bytes) {
  try {
    decode(bytes.data(), bytes.size());
  } catch (const std::invalid_argument& e) {
    return e.what();
  }
  return "";
}

TEST(Wire, EveryTruncationIsRefusedWithOneLine) {
  const auto updates = [](const uint8_t* p, size_t n) { return decode_updates(p, n); };
  const auto control = [](const uint8_t* p, size_t n) { return decode_control(p, n); };
  for (const auto& [bytes, is_updates] :
       {std::pair{encode(sample_updates()), true}, std::pair{encode(sample_control()), false}}) {
    for (size_t n = 0; n < bytes.size(); ++n) {
      const std::vector<uint8_t> cut(bytes.begin(), bytes.begin() + std::ptrdiff_t(n));
      const std::string why = is_updates ? refusal(updates, cut) : refusal(control, cut);
      ASSERT_FALSE(why.empty()) << n << " of " << bytes.size() << " bytes accepted";
      EXPECT_EQ(why.find('\n'), std::string::npos) << why;
    }
    std::vector<uint8_t> longer = bytes;
    longer.push_back(0);
    const std::string why = is_updates ? refusal(updates, longer) : refusal(control, longer);
    EXPECT_NE(why.find("trailing"), std::string::npos) << why;
  }
}

TEST(Wire, BadFieldsAreNamed) {
  const auto updates = [](const uint8_t* p, size_t n) { return decode_updates(p, n); };
  std::vector<uint8_t> b = encode(sample_updates());
  b[0] ^= 1;
  EXPECT_NE(refusal(updates, b).find("updates.magic"), std::string::npos);
  b = encode(sample_updates());
  b[4] = 9;
  EXPECT_NE(refusal(updates, b).find("updates.version"), std::string::npos);
  // A slot count of 2^32-1 in a short message: refused before anything is allocated.
  b = encode(sample_updates());
  const size_t slots_at = 8 + 8 + 4 + 4 + 4 + 32;
  const uint32_t huge = 0xffffffffu;
  std::memcpy(b.data() + slots_at, &huge, 4);
  EXPECT_NE(refusal(updates, b).find("updates.slots: count beyond the message"), std::string::npos);
  // A NaN sample.
  b = encode(sample_updates());
  const float nan = std::numeric_limits<float>::quiet_NaN();
  std::memcpy(b.data() + slots_at + 4 + 12, &nan, 4);
  EXPECT_NE(refusal(updates, b).find("updates.sample: not finite"), std::string::npos);
  // A control message with an unknown kind bit, and an advance of zero seconds.
  const auto control = [](const uint8_t* p, size_t n) { return decode_control(p, n); };
  Control c;
  c.advance.emplace(1u, 0.5);
  b = encode(c);
  b[8] |= 0x80;
  EXPECT_NE(refusal(control, b).find("control.kind"), std::string::npos);
  b = encode(c);
  const double zero = 0.0;
  std::memcpy(b.data() + b.size() - 8, &zero, 8);
  EXPECT_NE(refusal(control, b).find("control.advance.seconds"), std::string::npos);
}

TEST(Wire, RgbeRecordsAreSmallerAndWithinTheirPrecision) {
  Updates u = sample_updates();
  u.format = WireFormat::rgbe;
  const std::vector<uint8_t> bytes = encode(u);
  EXPECT_EQ(bytes.size(), 8 + 8 + 4 + 4 + 2 * (4 + 32 + 4 + 3 * kCompactRecordBytes));
  EXPECT_LT(double(kCompactRecordBytes) / double(kSlotRecordBytes), 0.61);
  const Updates d = decode_updates(bytes.data(), bytes.size());
  ASSERT_EQ(d.format, WireFormat::rgbe);
  for (size_t t = 0; t < 2; ++t)
    for (size_t s = 0; s < 3; ++s) {
      const PixelSnapshot &x = u.threads[t].slots[s].state, &y = d.threads[t].slots[s].state;
      EXPECT_EQ(x.count, y.count);
      EXPECT_EQ(x.epoch, y.epoch);
      EXPECT_EQ(x.time, y.time);
      EXPECT_EQ(x.levels, y.levels);
      for (int k = 0; k < 3; ++k) {
        // Each channel within half a mantissa step of the colour's largest channel (1/256 of it).
        const float big = std::max({x.sample.x, x.sample.y, x.sample.z});
        EXPECT_NEAR(y.sample[k], x.sample[k], big / 256.0f) << t << " " << s << " " << k;
        EXPECT_NEAR(y.mean[k], x.mean[k], 0.75f / 256.0f);
      }
      EXPECT_NEAR(y.variance, x.variance, x.variance / 128.0f + 1e-12f);
    }
}

TEST(Wire, RgbeEncodesZeroBlackAndHugeAndIsCanonical) {
  uint8_t b[4];
  encode_rgbe(Vec3(0.0f), b);
  EXPECT_EQ(decode_rgbe(b), Vec3(0.0f));
  encode_rgbe(Vec3(-1.0f, 0.0f, 0.0f), b);  // negative parts become 0
  EXPECT_EQ(decode_rgbe(b), Vec3(0.0f));
  encode_rgbe(Vec3(1e30f, 1.0f, 0.0f), b);
  EXPECT_NEAR(decode_rgbe(b).x / 1e30f, 1.0f, 1.0f / 128.0f);
  for (float v : {1e-20f, 0.001f, 0.5f, 1.0f, 3.7f, 65504.0f}) {
    encode_rgbe(Vec3(v, v / 3, 0), b);
    EXPECT_GE(std::max({b[0], b[1], b[2]}), 128) << v;
    uint8_t again[4];
    encode_rgbe(decode_rgbe(b), again);  // one encoding per colour: decode, encode gives it back
    EXPECT_EQ(std::memcmp(b, again, 4), 0) << v;
  }
  // A non-canonical colour (largest mantissa below 128) and an unknown format are refused.
  Updates u = sample_updates();
  u.format = WireFormat::rgbe;
  std::vector<uint8_t> bytes = encode(u);
  const size_t first_rgbe = 8 + 8 + 4 + 4 + 4 + 32 + 4 + 12;
  bytes[first_rgbe] = bytes[first_rgbe + 1] = bytes[first_rgbe + 2] = 5;
  bytes[first_rgbe + 3] = 130;
  const auto updates = [](const uint8_t* p, size_t n) { return decode_updates(p, n); };
  EXPECT_NE(refusal(updates, bytes).find("updates.rgbe: not a canonical"), std::string::npos);
  // A colour below 1e-32, which the encoder sends as black (found by the fuzzer): refused too.
  bytes = encode(u);
  bytes[first_rgbe] = 0x65, bytes[first_rgbe + 1] = 0xe0, bytes[first_rgbe + 2] = 0, bytes[first_rgbe + 3] = 0x0b;
  EXPECT_NE(refusal(updates, bytes).find("updates.rgbe: not a canonical"), std::string::npos);
  bytes = encode(u);
  bytes[16] = 7;
  EXPECT_NE(refusal(updates, bytes).find("updates.format: unknown wire format 7"), std::string::npos);
}

// Conventional mode's messages: a control with a frame spec and pieces (handed-over states on
// one of them), and a client's results, exact and with RGBE colours.
PixelRecord sample_record(uint32_t k) {
  PixelRecord r;
  r.passes = 10 + k;
  r.count = 3 + k;
  r.epoch = 2;
  r.mean[0] = 0.1 + 1e-12 * k, r.mean[1] = 0.5, r.mean[2] = 3.75;
  r.m2 = 0.02 * k;
  r.sample = Vec3(0.2f, 0.4f, 1e-30f);
  r.time = 1.25f;
  r.levels = uint8_t(k);
  return r;
}

Control sample_pieces() {
  Control c;
  FrameSpec f;
  f.serial = 5;
  f.epoch = 2;
  f.camera = sample_control().camera->second;
  f.time = 0.75;
  c.frame = f;
  for (uint64_t id : {11u, 12u}) {
    PieceOrder o;
    o.id = id;
    o.piece = FramePiece{5, uint32_t(id * 10), uint32_t(id * 10 + 3), 0.5, 1e-3};
    if (id == 12)
      for (uint32_t k = 0; k < 3; ++k) o.states.push_back(sample_record(k));
    c.pieces.push_back(o);
  }
  return c;
}

Results sample_results(WireFormat f) {
  Results r;
  r.format = f;
  r.want = 6;
  r.idle_ns = 123;
  r.request_ns = 456;
  r.requests = 2;
  r.busy_ns = 789;
  PieceResult p;
  p.id = 11;
  p.piece = FramePiece{5, 110, 113, 0.5, 1e-3};
  p.samples = 6;
  p.dropped = 1;
  for (uint32_t k = 0; k < 3; ++k) p.records.push_back(sample_record(k));
  r.pieces.push_back(p);
  return r;
}

void expect_same_piece(const FramePiece& a, const FramePiece& b) {
  EXPECT_EQ(a.serial, b.serial);
  EXPECT_EQ(a.begin, b.begin);
  EXPECT_EQ(a.end, b.end);
  EXPECT_EQ(a.t_begin, b.t_begin);
  EXPECT_EQ(a.dt, b.dt);
}

void expect_same_record(const PixelRecord& a, const PixelRecord& b) {
  EXPECT_EQ(a.passes, b.passes);
  EXPECT_EQ(a.count, b.count);
  EXPECT_EQ(a.epoch, b.epoch);
  for (int k = 0; k < 3; ++k) EXPECT_EQ(a.mean[k], b.mean[k]);
  EXPECT_EQ(a.m2, b.m2);
  EXPECT_EQ(a.sample, b.sample);
  EXPECT_EQ(a.time, b.time);
  EXPECT_EQ(a.levels, b.levels);
}

TEST(Wire, PiecesAndResultsRoundTripExactly) {
  const Control c = sample_pieces();
  const std::vector<uint8_t> cb = encode(c);
  const Control d = decode_control(cb.data(), cb.size());
  ASSERT_TRUE(d.frame);
  EXPECT_EQ(d.frame->serial, 5u);
  EXPECT_EQ(d.frame->epoch, 2u);
  EXPECT_EQ(d.frame->camera.eye, c.frame->camera.eye);
  EXPECT_EQ(d.frame->time, 0.75);
  ASSERT_EQ(d.pieces.size(), 2u);
  for (size_t i = 0; i < 2; ++i) {
    EXPECT_EQ(d.pieces[i].id, c.pieces[i].id);
    expect_same_piece(d.pieces[i].piece, c.pieces[i].piece);
    ASSERT_EQ(d.pieces[i].states.size(), c.pieces[i].states.size());
    for (size_t k = 0; k < c.pieces[i].states.size(); ++k) expect_same_record(d.pieces[i].states[k], c.pieces[i].states[k]);
  }
  const Results r = sample_results(WireFormat::exact);
  const std::vector<uint8_t> rb = encode(r);
  EXPECT_EQ(rb.size(), 8 + 4 + 4 + 32 + 4 + (8 + 32 + 16 + 4 + 3 * kPieceRecordBytes));
  const Results e = decode_results(rb.data(), rb.size());
  EXPECT_EQ(e.want, 6u);
  EXPECT_EQ(e.idle_ns, 123u);
  EXPECT_EQ(e.request_ns, 456u);
  EXPECT_EQ(e.requests, 2u);
  EXPECT_EQ(e.busy_ns, 789u);
  ASSERT_EQ(e.pieces.size(), 1u);
  EXPECT_EQ(e.pieces[0].samples, 6u);
  EXPECT_EQ(e.pieces[0].dropped, 1u);
  expect_same_piece(e.pieces[0].piece, r.pieces[0].piece);
  for (size_t k = 0; k < 3; ++k) expect_same_record(e.pieces[0].records[k], r.pieces[0].records[k]);
}

TEST(Wire, RgbeResultsAreSmallerAndKeepCountsExact) {
  const Results r = sample_results(WireFormat::rgbe);
  const std::vector<uint8_t> rb = encode(r);
  EXPECT_EQ(rb.size(), 8 + 4 + 4 + 32 + 4 + (8 + 32 + 16 + 4 + 3 * kCompactPieceRecordBytes));
  const Results e = decode_results(rb.data(), rb.size());
  for (size_t k = 0; k < 3; ++k) {
    const PixelRecord &a = r.pieces[0].records[k], &b = e.pieces[0].records[k];
    EXPECT_EQ(a.passes, b.passes);
    EXPECT_EQ(a.count, b.count);
    EXPECT_EQ(a.epoch, b.epoch);
    EXPECT_EQ(a.time, b.time);
    for (int c = 0; c < 3; ++c) EXPECT_NEAR(b.mean[c], a.mean[c], 3.75 / 256.0);
    EXPECT_NEAR(b.m2, a.m2, a.m2 / 128.0 + 1e-12);
  }
}

TEST(Wire, MalformedPiecesAndResultsAreRefusedWithOneLine) {
  const auto control = [](const uint8_t* p, size_t n) { return decode_control(p, n); };
  const auto results = [](const uint8_t* p, size_t n) { return decode_results(p, n); };
  for (const auto& [bytes, is_results] :
       {std::pair{encode(sample_pieces()), false}, std::pair{encode(sample_results(WireFormat::exact)), true},
        std::pair{encode(sample_results(WireFormat::rgbe)), true}}) {
    for (size_t n = 0; n < bytes.size(); ++n) {
      const std::vector<uint8_t> cut(bytes.begin(), bytes.begin() + std::ptrdiff_t(n));
      const std::string why = is_results ? refusal(results, cut) : refusal(control, cut);
      ASSERT_FALSE(why.empty()) << n << " of " << bytes.size() << " bytes accepted";
      EXPECT_EQ(why.find('\n'), std::string::npos) << why;
    }
  }
  // A result with fewer records than its piece has slots; an empty piece; a negative m2; a
  // piece of frame 0; more samples than two per slot; a variance with one sample (RGBE).
  Results r = sample_results(WireFormat::exact);
  r.pieces[0].records.pop_back();
  std::vector<uint8_t> b = encode(r);
  EXPECT_NE(refusal(results, b).find("results.records: not one per slot"), std::string::npos);
  r = sample_results(WireFormat::exact);
  r.pieces[0].piece.end = r.pieces[0].piece.begin;
  r.pieces[0].records.clear();
  b = encode(r);
  EXPECT_NE(refusal(results, b).find("results.piece.end: empty"), std::string::npos);
  r = sample_results(WireFormat::exact);
  r.pieces[0].records[1].m2 = -1.0;
  b = encode(r);
  EXPECT_NE(refusal(results, b).find("results.record.m2"), std::string::npos);
  r = sample_results(WireFormat::exact);
  r.pieces[0].piece.serial = 0;
  b = encode(r);
  EXPECT_NE(refusal(results, b).find("results.piece.serial"), std::string::npos);
  r = sample_results(WireFormat::exact);
  r.pieces[0].samples = 7;
  b = encode(r);
  EXPECT_NE(refusal(results, b).find("results.piece.samples"), std::string::npos);
  r = sample_results(WireFormat::rgbe);
  r.pieces[0].records[0].count = 1;
  r.pieces[0].records[0].m2 = 0.0;
  b = encode(r);
  const float one = 1.0f;  // bfloat16 1.0 into the first record's variance
  const uint16_t bf = uint16_t(std::bit_cast<uint32_t>(one) >> 16);
  const size_t var_at = 8 + 4 + 4 + 32 + 4 + 8 + 32 + 16 + 4 + 12 + 8;
  std::memcpy(b.data() + var_at, &bf, 2);
  EXPECT_NE(refusal(results, b).find("results.record.variance: non-zero with fewer than two"), std::string::npos);
}

}  // namespace
}  // namespace frameless::cluster
