// Reprojection (the render cache, Walter, Drettakis and Parker 1999), display thread only: when
// the camera changes, every displayed pixel moves to where its primary hit now projects (forward
// splat, the nearest point wins); cracks are closed from the surface around them and
// disocclusions filled from the farthest content nearby (what a foreground object uncovers is
// background), both marked, so render threads can fill them first and the blend replaces them
// whole. Works in the display's slot order.
#pragma once
#include <algorithm>
#include <chrono>
#include <cstdint>
#include <limits>
#include <vector>

#include "core/base/fused_float.h"
#include "core/scene/camera.h"
#include "display/display_pixel.h"
#include "display/view_point.h"
#include "frameless/cpu_clock.h"
#include "frameless/pixel_points.h"

namespace frameless {

// The display's CPU budget for reprojection, a leaky bucket: credit fills at `budget` seconds of
// CPU per second of wall time, at most one reprojection's cost ahead; a reprojection spends its
// CPU time; none starts while the credit is negative (its camera change merges into a later one).
// Without a budget nothing is spent, so turning one on later starts from no debt.
class ReprojectBudget {
 public:
  // Whether a reprojection may start at wall time `now` (seconds); budget <= 0: always.
  bool allow(double now, float budget) {
    if (!(budget > 0.0f)) return true;
    if (last_ >= 0.0) credit_ = std::min(cost_, credit_ + double(budget) * (now - last_));
    last_ = now;
    return credit_ >= 0.0;
  }
  void spend(double cpu_seconds, float budget) {
    cost_ = cpu_seconds;
    if (budget > 0.0f) credit_ -= cpu_seconds;
  }

 private:
  double credit_ = 0.0;  // CPU seconds still allowed
  double last_ = -1.0;   // wall time of the last fill
  double cost_ = 0.0;    // the last reprojection's CPU seconds (the most credit kept)
};

struct ReprojectStats {
  size_t moved = 0;        // pixels that received a moved pixel
  size_t filled = 0;       // cracks closed from a neighbour
  size_t disoccluded = 0;  // uncovered pixels (guessed from the background around them)
  size_t stale = 0;        // pixels showing something that may move (dynamic objects, instances)
};

// The display image: pixels by slot (slot s holds pixel pixel_of[s], identity when null), points
// and marks by pixel. A pixel whose mark is kMarkNone shows the engine's newest update there, so
// its point is the engine's (world space, read whole from `engine_points` when set); a marked
// pixel shows moved content, whose point is in `points`, relative to the image's camera.
struct SlotImage {
  int width = 0;
  int height = 0;
  const uint32_t* pixel_of = nullptr;
  const uint32_t* slot_of = nullptr;
  DisplayPixel* px = nullptr;
  ViewPoint* points = nullptr;
  uint8_t* marks = nullptr;
  const PixelPoint* engine_points = nullptr;
  size_t pixels() const { return size_t(width) * size_t(height); }
  uint32_t slot(size_t pixel) const { return slot_of ? slot_of[pixel] : uint32_t(pixel); }
  uint32_t pixel(size_t slot) const { return pixel_of ? pixel_of[slot] : uint32_t(slot); }
};

// Milliseconds of a reprojection's phases, by Phase: the splat, the crack and disocclusion
// searches, the gather's pass by pixel (points and marks; with an identity layout, the whole
// gather) and its pass by slot (the pixels; 0 with an identity layout). Wall time, and the
// calling thread's CPU time: beside busy render threads the display thread may wait for a core
// inside a phase, and only the CPU time says what the phase itself costs.
struct ReprojectTimes {
  enum Phase { splat, cracks, disocclusions, pixel_pass, slot_pass, kPhases };
  static constexpr const char* kNames[kPhases] = {"splat", "cracks", "disocclusions", "pixel_pass", "slot_pass"};
  double ms[kPhases] = {};
  double cpu_ms[kPhases] = {};
  ReprojectTimes& operator+=(const ReprojectTimes& o) {
    for (int i = 0; i < kPhases; ++i) ms[i] += o.ms[i], cpu_ms[i] += o.cpu_ms[i];
    return *this;
  }
};

// The clocks between a reprojection's phases (wall and the thread's CPU): lap() books the time
// since the last lap to a phase.
class PhaseClock {
 public:
  explicit PhaseClock(ReprojectTimes& times) : times_(times) {}
  void lap(ReprojectTimes::Phase phase);

 private:
  ReprojectTimes& times_;
  std::chrono::steady_clock::time_point wall_ = std::chrono::steady_clock::now();
  uint64_t cpu_ns_ = thread_cpu_ns();
};

class Reprojector {
 public:
  // `to` <- `from` (whose points are relative to camera `before`) moved to camera `after` (same
  // size and slot order; `to`'s points are then relative to `after`): each pixel goes where its
  // point projects. Slots without a point (never rendered) move nowhere; a disoccluded pixel with
  // nothing landed within `max_fill` pixels keeps `from`'s own content, marked, without a point.
  // `world_moves`: something may have moved, so pixels showing dynamic objects or instances are
  // marked stale (else nothing is).
  // `census` (optional, cleared by the caller): counts the epochs of the pixels `to` shows.
  ReprojectStats run(const CameraBasis& before, const CameraBasis& after, const SlotImage& from,
                     const SlotImage& to, bool world_moves = true, int max_fill = 3,
                     EpochCensus* census = nullptr);

  // How disocclusions find the farthest content near them: one window per hole, or by rows
  // (cheaper than the scalar window for many holes); automatic takes the vector window where
  // there is one, else picks by the number of holes. All give the same image.
  enum class Search { automatic, window, rows };
  void set_search(Search s) { search_ = s; }
  // AVX-512 paths (splat, crack search, disocclusion window, the gather's pass by pixel) where the
  // build has them, else AVX2 ones (the same four); off: the scalar code, which they must match
  // exactly (tested).
  void set_vectorized(bool on) { vectorized_ = on; }
  // The phases of the last run().
  const ReprojectTimes& last_times() const { return times_; }
  // Which vector paths this build has ("AVX-512", "AVX2" or "scalar"): reprojection's cost
  // differs by about 1.5x between them, so benchmarks say which ran.
  static const char* vector_paths() {
#if defined(__AVX512F__)
    return "AVX-512";
#elif defined(__AVX2__)
    return "AVX2";
#else
    return "scalar";
#endif
  }

 private:
  uint32_t farther(uint32_t a, uint32_t b) const;
  bool vector_window(int r) const;
  size_t splat16(const ViewMove& move, const SlotImage& from, int w);
  // Up to sixteen (AVX2: eight) of the engine's world points (unmarked pixels) waiting to be
  // landed together (land_engine16, land_engine8).
  struct alignas(64) EngineBatch {
    float x[16], y[16], z[16];
    uint32_t object[16], source[16];
    int count = 0;
    // Source pixel `source`'s point queued; returns the points now waiting.
    int add(const ScenePoint& point, uint32_t source_pixel) {
      x[count] = point.p.x, y[count] = point.p.y, z[count] = point.p.z;
      object[count] = point.object, source[count] = source_pixel;
      return ++count;
    }
  };
  void land_engine16(const Projector& to, const EngineBatch& batch, int w);
  void land_engine8(const Projector& to, const EngineBatch& batch, int w);
  // The batch's lanes `lanes` landed (both vector forms): at pixel target[i], depth bits depth[i],
  // view bits word[i], as land() lands one point.
  void land_lanes(uint32_t lanes, const EngineBatch& batch, const uint32_t* target, const uint32_t* depth,
                  const uint32_t* word) {
    for (uint32_t m = lanes; m; m &= m - 1u) {
      const int i = __builtin_ctz(m);
      uint64_t& k = key_[target[i]];
      k = std::min(k, uint64_t(depth[i]) << 32 | batch.source[i]);
      moved_[batch.source[i]] = word[i];
    }
  }
  void crack(uint32_t t, int w, int h);
  void cracks16(int w, int h);
  // The AVX2 forms of splat16, cracks16 and the vector window (reproject_avx2.cpp), for cores
  // without AVX-512.
  size_t splat8(const ViewMove& move, const SlotImage& from, int w);
  // Lands source pixel p (its point already known) and records where (moved_).
  void land(size_t p, bool in, float px, float py, float depth, uint32_t kind, int w);
  // The scalar splat of pixel p: marked, its ViewPoint moved; unmarked, the engine's point.
  void splat_one(const ViewMove& move, const SlotImage& from, size_t p, int w);
  void cracks4(int w, int h);
  // The gather (reproject_gather.cpp): `to`'s points, marks and pixels from the keys; its pass
  // by pixel in AVX-512 (16 pixels a step) and AVX2 (8), adding the marks' counts.
  ReprojectStats gather(const SlotImage& from, const SlotImage& to, bool world_moves, EpochCensus* census,
                        PhaseClock& clock);
  size_t places16(const SlotImage& from, const SlotImage& to, bool world_moves, size_t count[4]);
  size_t places8(const SlotImage& from, const SlotImage& to, bool world_moves, size_t count[4]);
  uint32_t farthest_in_window4(int x, int y, int w, int h, int r) const;
  uint32_t farthest_in_window(int x, int y, int w, int h, int r) const;
  uint32_t farthest_in_rows(int x, int y, int w, int h, int r);
  Search search_ = Search::automatic;
  bool vectorized_ = true;
  ReprojectTimes times_;
  std::vector<uint32_t> row_best_, prefix_, suffix_;  // farthest_in_rows' scratch
  std::vector<uint8_t> row_done_;
  // By pixel: the nearest point landed so far as (depth bits << 32 | the pixel of `from` it
  // shows), so the nearest is the smallest key and ties go to the lower pixel; kHole: none.
  std::vector<uint64_t> key_;
  // Whether the gather left key_ all holes and marks_ all kMarkMoved (it clears each pixel's
  // after their last read, so run() need not fill them again).
  bool keys_clear_ = false;
  struct Fill {
    uint32_t pixel;
    uint64_t key;
  };
  std::vector<uint8_t> marks_;   // by pixel: kMarkMoved, or how a hole was filled
  std::vector<uint32_t> next_;   // holes (nothing landed) that are no crack: the first next_count_
  size_t next_count_ = 0;
  std::vector<uint64_t> row_fill_[2];  // cracks16 (cracks4): a row's fill keys, 16 (4) per group
  std::vector<uint8_t> row_found_[2];  // cracks16 (cracks4): which of a group's pixels were filled (a byte per 8)
  std::vector<Fill> fills_;      // a pass's fills, applied together after it
  std::vector<uint32_t> source_slot_;  // by pixel: the slot of `from` the gather copies
  // By source pixel of `from`, where its point landed in `after`: view_bits (fractions and kind);
  // the gather builds the moved points from these and the keys' depths.
  std::vector<uint32_t> moved_;
};

}  // namespace frameless
