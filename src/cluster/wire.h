// The cluster's messages and their byte encoding (no MPI here: pure functions, fuzzed). Every
// message starts with a magic number and the wire version; decoding checks every size, count
// and value before use and names the field that is wrong in one line.
#pragma once
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "core/geometry/geometry.h"
#include "core/scene/camera.h"
#include "frameless/engine.h"
#include "frameless/remote_frames.h"

namespace frameless::cluster {

inline constexpr uint32_t kWireMagic = 0x31434c46u;  // "FLC1" read as little-endian bytes
inline constexpr uint32_t kWireVersion = 1;

// MPI tags: one kind of message per tag, so a receiver probes for exactly what it expects.
// (The handshake itself is a collective: MPI_Gather of Hellos, MPI_Bcast of the verdict.)
enum Tag : int { kTagControl = 3, kTagUpdates = 4, kTagBye = 5, kTagPing = 6, kTagResults = 7 };

// Every rank, once, after loading the scene: who it is and whether it can render.
struct Hello {
  std::string build;             // build identity (version, wire version, compiler): must match
  uint64_t scene_fingerprint = 0;  // what the rank loaded: must match the master's
  uint32_t threads = 0;          // render threads it will run
  std::string error;             // non-empty: it cannot take part (scene failed to load, ...)
};

// How pixel records travel. exact: what the master's display needs to reproduce a local run
// bit for bit (45 bytes; 61 for a conventional piece's whole state). rgbe: OpenRT's idea of
// quantised colours, kept high-dynamic-range: sample and mean as RGBE (8-bit mantissas, shared
// exponent: 0.4 % relative error), variance as bfloat16 (27 bytes); wall-clock runs only.
enum class WireFormat : uint32_t { exact = 0, rgbe = 1 };

// Conventional mode: a piece of a frame handed to one client, with the states it starts from
// when another rank rendered those pixels last.
struct PieceOrder {
  uint64_t id = 0;
  FramePiece piece;
  std::vector<PixelRecord> states;  // one per slot, or empty: the client has them
};

// Master -> clients: only what changed since the last control message (differential), then
// optionally a deterministic tick to render or the order to stop; in conventional mode a new
// frame's spec and pieces for this client (one tag: they arrive in the order they were sent).
struct Control {
  std::optional<std::pair<uint32_t, Camera>> camera;  // epoch, camera
  std::vector<float> world;                           // packed WorldState; empty: unchanged
  std::vector<InstanceMove> moves;                    // moved instances; empty: none
  std::optional<std::pair<uint64_t, double>> advance; // deterministic: tick index, seconds
  std::optional<FrameSpec> frame;                     // conventional: a frame begun
  WireFormat format = WireFormat::exact;              // of the pieces' states
  std::vector<PieceOrder> pieces;                     // conventional: work for this client
  bool stop = false;
};

// Client -> master (conventional): finished pieces, and how many more it wants now (its
// prefetch depth less what it holds).
struct PieceResult {
  uint64_t id = 0;
  FramePiece piece;
  uint64_t samples = 0, dropped = 0;
  std::vector<PixelRecord> records;  // one per slot
};
struct Results {
  WireFormat format = WireFormat::exact;
  uint32_t want = 0;
  uint64_t idle_ns = 0;       // its render threads' time waiting for a piece, cumulative
  uint64_t request_ns = 0;    // time from asking for pieces to receiving them, summed
  uint64_t requests = 0;      // requests answered
  uint64_t busy_ns = 0;       // its render threads' CPU time, cumulative
  std::vector<PieceResult> pieces;
};

// Client -> master: the news of its render threads. `tick` is the deterministic tick these
// updates complete (~0 on the wall clock).
struct Updates {
  uint64_t tick = ~uint64_t(0);
  WireFormat format = WireFormat::exact;
  std::vector<RemoteBatch> threads;
};

// Bytes of one pixel record on the wire (slot, count, epoch, sample, mean, variance, time, levels).
inline constexpr size_t kSlotRecordBytes = 45;
inline constexpr size_t kCompactRecordBytes = 27;
inline size_t record_bytes(WireFormat f) { return f == WireFormat::rgbe ? kCompactRecordBytes : kSlotRecordBytes; }
// Bytes of one whole pixel state (PixelRecord) in a piece: exact, or with RGBE colours.
inline constexpr size_t kPieceRecordBytes = 61;
inline constexpr size_t kCompactPieceRecordBytes = 27;
inline size_t piece_record_bytes(WireFormat f) {
  return f == WireFormat::rgbe ? kCompactPieceRecordBytes : kPieceRecordBytes;
}

// RGBE (Ward's shared-exponent colour) of a non-negative colour (negative parts become 0), and back.
void encode_rgbe(const Vec3& c, uint8_t out[4]);
Vec3 decode_rgbe(const uint8_t in[4]);

std::vector<uint8_t> encode(const Hello& m);
std::vector<uint8_t> encode(const Control& m);
std::vector<uint8_t> encode(const Updates& m);
std::vector<uint8_t> encode(const Results& m);

// Decoders: the message, or std::invalid_argument with "FIELD: problem" on anything malformed
// (wrong magic or version, truncated, trailing bytes, counts beyond the message, non-finite).
Hello decode_hello(const uint8_t* data, size_t size);
Control decode_control(const uint8_t* data, size_t size);
Updates decode_updates(const uint8_t* data, size_t size);
Results decode_results(const uint8_t* data, size_t size);

// Build identity compared between ranks (FRAMELESS_TEST_BUILD_ID overrides it: tests stage a
// mismatched build with it).
std::string build_identity();

}  // namespace frameless::cluster
