// One display tick's blend: each collected update of the render threads blended into the back
// buffer (exponential decay or convergence), redirected by reprojection, or asked for again by
// closed-loop sampling. Display thread.
#include "display/display_thread_impl.h"

namespace frameless {

void TickSink::begin(const CollectResult& r) {
  conventional = r.mode == RenderMode::conventional;
  full = d.catch_up(r);
  image = &d.buf[d.back];
  levels = r.levels;
  dirty = &d.history.runs[d.tick_index % kHistory];
  dirty->clear();
  reproject = reproject && !conventional && r.points;
  wanted = conventional ? nullptr : r.wanted;
  points = reproject ? r.points : nullptr;
  const bool reprojected = d.reproject(*image, reproject, rule.config.reproject_budget, r.world_moves, r.points);
  d.finish_catch_up(*image);
  if (reprojected) {
    moved = true;
    if (wanted) {  // closed loop: what reprojection could not guess (nothing near it, may have moved) first
      const uint8_t* marks = d.marks.data();
      for (size_t pixel = 0; pixel < d.marks.size(); ++pixel)
        if (marks[pixel] & (kMarkUnknown | kMarkStale)) wanted->want(image->engine_slot_of(pixel));
      wanted->publish();
    }
  }
}

// Closed loop: a sample of the same camera far from what its pixel shows (beyond its noise, as
// temporal_alpha judges) means something moves there: ask for its run again soon. (After a camera
// change every pixel jumps; reprojection's marks ask for what matters then.)
inline bool jumps(const DisplayPixel& m, const PixelSnapshot& u) {
  // Four samples at least: before that the pixel's noise is not known.
  if (m.epoch == 0 || m.epoch != u.epoch || u.count < 4) return false;
  return temporal_alpha(1.0f, Vec3(m.rgb[0], m.rgb[1], m.rgb[2]), u) >= 1.0f;
}

// `guess`: what the pixel shows was guessed by reprojection (a crack, a disocclusion, something
// that may have moved): the first real sample replaces it whole.
inline void TickSink::show(DisplayPixel& m, PlaceRecord& rec, const PixelSnapshot& u, bool guess) {
  bool bad = false;
  const Vec3 c = blend_pixel(rule, conventional, Vec3(m.rgb[0], m.rgb[1], m.rgb[2]),
                             guess ? 0u : m.epoch, rec.last_update, u, &bad);
  rejected += bad;
  d.census.move(m.epoch, u.epoch);
  m.rgb[0] = c.x;
  m.rgb[1] = c.y;
  m.rgb[2] = c.z;
  rec.last_update = u.time;
  rec.count = u.count;
  rec.variance = std::isfinite(u.variance) ? u.variance : 0.0f;
  m.epoch = u.epoch;
  ++changed;
}

// An update rendered with a camera older than the one the image was moved to belongs where its
// point now projects (the render cache): blended there if nothing nearer is shown, never at its
// own pixel, which shows moved content by now.
void TickSink::redirect(const PixelSnapshot& u, const ScenePoint& point) {
  const CameraBasis& b = d.reproject_basis;
  size_t pixel = 0;
  const ViewPoint moved = to_view(b, point, pixel);  // where it lands now, as the display holds it
  if (view_kind(moved.bits) == kViewNone) return;
  const float depth = moved.depth;
  const size_t slot = image->slot_of(pixel);
  uint8_t& mark = d.marks[pixel];
  // A marked pixel shows moved content with its moved point (its depth in this camera); an
  // unmarked one its own newest update (a point its owner keeps rewriting: leave the pixel as it is).
  float shown_depth = 0.0f;
  bool shows_point = false;
  if (mark) {
    shows_point = view_kind(d.points[pixel].bits) != kViewNone;
    shown_depth = d.points[pixel].depth;
  } else {
    ScenePoint shown;
    if (!read_point(points[pixel], shown)) return;
    float sx, sy;
    shows_point = project_point(b, shown, sx, sy, shown_depth);
  }
  const bool nearer = !shows_point || depth <= shown_depth * 1.01f;
  if (!(mark & kMarkGuess) && !nearer) return;  // hidden behind what the pixel shows
  DisplayPixel& m = image->px[slot];
  const Vec3 c = (mark & kMarkGuess) ? u.sample : blend(Vec3(m.rgb[0], m.rgb[1], m.rgb[2]), u.sample, rule.config.alpha);
  if (!is_finite(c)) return;
  m.rgb[0] = c.x;
  m.rgb[1] = c.y;
  m.rgb[2] = c.z;
  d.points[pixel] = moved;
  mark = kMarkMoved;
  ++d.reproject_totals.redirected;
  mark_dirty(slot, 1);
}

void TickSink::slots(size_t first, const PixelState* states, size_t count) {
  // Engine slots [first, first + count): consecutive places within each 64-pixel chunk.
  DisplayPixel* px = image->px.data();
  PlaceRecord* records = image->rec.data();
  const uint32_t* place = image->layout ? image->layout->place_of_engine_slot.data() + first : nullptr;
  const uint32_t* pixel_of = image->layout ? image->layout->engine_order->data() + first : nullptr;
  uint32_t* seq = d.shown_seq.data() + first;
  PixelSnapshot u;
  for (size_t i = 0; i < count; ++i) {
    // Each chunk is a run of places somewhere else, and a square of pixels whose levels and marks
    // (by pixel) lie on as many rows: ask for their lines ahead of the blend.
    if (place && i + 16 < count) {
      __builtin_prefetch(px + place[i + 16], 1);
      __builtin_prefetch(records + place[i + 16], 1);
      if (levels) __builtin_prefetch(levels + pixel_of[i + 16]);
      if (points) __builtin_prefetch(d.marks.data() + pixel_of[i + 16], 1);
    }
    // A slot whose owner kept writing it is picked up on the owner's next visit.
    if (!read_pixel(states[i], u) || u.epoch == 0 || u.seq == seq[i]) continue;
    seq[i] = u.seq;
    const size_t pixel = pixel_of ? pixel_of[i] : first + i;
    const size_t at = place ? place[i] : first + i;
    DisplayPixel& m = px[at];
    PlaceRecord& rec = records[at];
    uint8_t* mark = nullptr;  // reprojection's mark of this pixel (null: reprojection off)
    if (points) {
      if (u.epoch < d.reproject_epoch && d.image_moved) {
        // The update's own point (read in the same sequence lock); if a newer update has replaced
        // it, that one is collected at the next tick instead.
        ScenePoint point;
        if (read_point_of(states[i], u.seq, points[pixel], point)) redirect(u, point);
        continue;
      }
      mark = &d.marks[pixel];
    }
    const bool guess = mark && (*mark & kMarkGuess);
    if (wanted && !guess && jumps(m, u)) {
      wanted->want(first + i);
      asked = true;
    }
    show(m, rec, u, guess);
    // Unmarked: the engine's point is this pixel's (read at the next reprojection), so a tick
    // costs a byte per update here, not a point.
    if (mark && *mark) *mark = kMarkNone;
    // Read after the state's seq: these levels are the shown update's or a newer one's.
    if (levels) rec.levels = levels[pixel].load(std::memory_order_relaxed);
  }
  mark_dirty_engine(first, count);
  if (asked) {  // inside collect(): the asks stay valid (the layout is locked)
    wanted->publish();
    asked = false;
  }
}

void TickSink::frame(const std::vector<PixelSnapshot>& pixels) {
  const size_t n = std::min(pixels.size(), image->px.size());
  for (size_t i = 0; i < n; ++i) {
    if (pixels[i].epoch == 0) continue;
    show(image->px[i], image->rec[i], pixels[i], false);
    d.shown_seq[i] = 0;  // frames carry no sequence number; frameless updates compare against 0
    image->rec[i].levels = pixels[i].levels;
  }
  full = true;
}

}  // namespace frameless
