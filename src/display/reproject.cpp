#include "display/reproject.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace frameless {
namespace {

constexpr uint32_t kNone = ~0u;
constexpr float kFar = std::numeric_limits<float>::infinity();

}  // namespace

ReprojectStats Reprojector::run(const CameraBasis& after, const SlotImage& from,
                                const SlotImage& to, bool world_moves, int max_fill) {
  ReprojectStats stats;
  const int w = from.width, h = from.height;
  const size_t n = from.pixels();
  depth_.assign(n, kFar);
  source_.assign(n, kNone);
  marks_.assign(n, kMarkMoved);
  // Forward splat: each slot's point lands in one pixel; the nearest wins (the sky loses to any
  // surface, and between two sky points the first stays).
  const Projector project(after);
  // Pixels in raster order, points by pixel: the splat streams through its input and writes
  // near where it reads (slots come in shuffled chunks: walking them misses the cache). Points
  // lie on their pixel centre's ray (trace_sample), so each pixel moves by its centre's motion.
  for (size_t p = 0; p < n; ++p) {
    float px, py, d;
    if (!project(from.points[p], px, py, d)) continue;
    const size_t t = size_t(int(py)) * size_t(w) + size_t(int(px));
    if (source_[t] == kNone || d < depth_[t]) {
      depth_[t] = d;
      source_[t] = uint32_t(p);
    }
  }
  // Cracks first: a hole with landed neighbours of about one depth on opposite sides lies inside
  // a magnified surface, and takes the farther of such a pair.
  holes_.clear();
  for (size_t t = 0; t < n; ++t)
    if (source_[t] == kNone) holes_.push_back(uint32_t(t));
  auto landed = [&](int x, int y) -> int64_t {
    if (x < 0 || y < 0 || x >= w || y >= h) return -1;
    const size_t q = size_t(y) * size_t(w) + size_t(x);
    return source_[q] == kNone ? -1 : int64_t(q);
  };
  static constexpr int kOpposite[4][2] = {{1, 0}, {0, 1}, {1, 1}, {1, -1}};
  fills_.clear();
  next_.clear();
  for (const uint32_t t : holes_) {
    const int x = int(t % uint32_t(w)), y = int(t / uint32_t(w));
    int64_t best = -1;
    for (const auto& d : kOpposite) {
      const int64_t p = landed(x + d[0], y + d[1]), q = landed(x - d[0], y - d[1]);
      if (p < 0 || q < 0) continue;
      const float near = std::min(depth_[p], depth_[q]), far = std::max(depth_[p], depth_[q]);
      if (far > near * 1.05f) continue;  // an edge between two surfaces, not a crack
      const int64_t f = depth_[p] >= depth_[q] ? p : q;
      if (best < 0 || depth_[f] > depth_[best]) best = f;
    }
    if (best < 0) {
      next_.push_back(t);
      continue;
    }
    fills_.push_back({t, source_[best], depth_[best]});
    marks_[t] = kMarkFilled;
  }
  for (const Fill& f : fills_) {
    source_[f.pixel] = f.source;
    depth_[f.pixel] = f.depth;
  }
  // Disocclusions: what an object uncovers lies behind it, so each remaining hole takes the
  // farthest landed pixel within `max_fill` pixels; none there: it keeps its old content.
  fills_.clear();
  for (const uint32_t t : next_) {
    const int x = int(t % uint32_t(w)), y = int(t / uint32_t(w));
    int64_t best = -1;
    for (int dy = -max_fill; dy <= max_fill; ++dy)
      for (int dx = -max_fill; dx <= max_fill; ++dx) {
        const int64_t q = landed(x + dx, y + dy);
        if (q >= 0 && (best < 0 || depth_[q] > depth_[best])) best = q;
      }
    marks_[t] = kMarkDisoccluded;
    if (best >= 0) fills_.push_back({t, source_[best], depth_[best]});
  }
  for (const Fill& f : fills_) {
    source_[f.pixel] = f.source;
    depth_[f.pixel] = f.depth;
  }
  // Gather into `to` pixel by pixel (points and marks stream); each slot keeps its own seq (what
  // the engine last published there).
  for (size_t t = 0; t < n; ++t) {
    const uint32_t ts = to.slot(t);
    uint32_t source = source_[t];
    uint8_t mark = marks_[t];
    if (source == kNone) {  // nothing reached it: its old content, marked as a guess
      source = uint32_t(t);
      mark = kMarkDisoccluded | kMarkUnknown;
    }
    const ScenePoint& point = from.points[source];
    if (world_moves && point_may_move(point.object)) mark |= kMarkStale;
    const uint32_t s = from.slot(source);
    DisplayPixel p = from.px[s];
    p.seq = from.px[ts].seq;
    to.px[ts] = p;
    to.points[t] = point;
    to.levels[ts] = from.levels[s];
    to.marks[t] = mark;
    stats.moved += (mark & kMarkMoved) != 0;
    stats.filled += (mark & kMarkFilled) != 0;
    stats.disoccluded += (mark & kMarkDisoccluded) != 0;
    stats.stale += (mark & kMarkStale) != 0;
  }
  return stats;
}

}  // namespace frameless
