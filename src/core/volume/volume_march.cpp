// Ray marching through a grid: fixed-phase samples, macrocell skipping, opacity correction.
#include "core/volume/volume_march.h"

#include <algorithm>
#include <bit>
#include <cmath>

#include "core/volume/isosurface.h"
#include "core/volume/trilinear.h"

namespace frameless {
namespace {

// Walks the samples of [t0, t1]: sample k stands for the stretch [t0 + k dt, t0 + (k + 1) dt] cut
// to the part inside the grid and the segment, and is taken at the stretch's middle (clamped into
// the grid), so a segment's samples cover exactly its length whatever its ends. Calls
// visit(p, fraction of dt covered) for each (false stops); jumps over macrocells of zero opacity.
template <class Visit>
uint32_t walk_samples(const MarchSetup& s, const Vec3& org, const Vec3& dir, float t0, float t1, Visit&& visit) {
  const VolumeGrid& g = *s.grid;
  float a = t0, b = t1;
  const Vec3 top = g.extent() / g.spacing;
  if (!clip_to_box(Vec3(0.0f), top, org, dir, a, b) || !(b > a)) return 0;
  const float len = glm::length(dir);
  if (!(len > 0.0f)) return 0;
  const float dt = s.step / len;
  const Macrocells* m = s.cell_opacity ? s.cells : nullptr;
  const int shift = m ? std::countr_zero(unsigned(m->size)) : 0;  // macrocell sides are powers of two
  uint32_t taken = 0;
  for (int64_t k = int64_t(std::floor((a - t0) / dt));; ++k) {
    const float lo = std::max(a, t0 + float(k) * dt), hi = std::min(b, t0 + float(k + 1) * dt);
    if (lo >= b) break;
    if (!(hi > lo)) continue;
    const Vec3 p = glm::clamp(org + (t0 + (float(k) + 0.5f) * dt) * dir, Vec3(0.0f), top);
    if (m) {
      const int cx = std::clamp(int(p.x), 0, g.nx - 2) >> shift, cy = std::clamp(int(p.y), 0, g.ny - 2) >> shift,
                cz = std::clamp(int(p.z), 0, g.nz - 2) >> shift;
      const float opacity = (*s.cell_opacity)[m->index(cx, cy, cz)];
      if (opacity <= 0.0f || opacity < s.thin_below) {
        const Vec3 box = Vec3(float(cx), float(cy), float(cz)) * float(m->size);
        float e0 = a, e1 = b;
        const bool in_box = clip_to_box(box, box + float(m->size), org, dir, e0, e1);
        if (opacity <= 0.0f) {
          // On to the stretch where the ray leaves this macrocell's box (its samples are transparent).
          if (in_box) k = std::max(k, int64_t(std::floor((e1 - t0) / dt)) - 1);
          continue;
        }
        // Nearly transparent: one sample, at their middle, for the stretches that end in the box.
        const int64_t group = in_box ? std::min<int64_t>(kThinStretches, int64_t(std::floor((std::min(e1, b) - t0) / dt)) - k) : 1;
        if (group >= 2) {
          const float group_hi = std::min(b, t0 + float(k + group) * dt);
          const Vec3 q = glm::clamp(org + (t0 + (float(k) + 0.5f * float(group)) * dt) * dir, Vec3(0.0f), top);
          ++taken;
          if (!visit(q, (group_hi - lo) / dt)) break;
          k += group - 1;
          continue;
        }
      }
    }
    ++taken;
    // A whole stretch counts exactly once (the per-step opacity table applies to it).
    const bool whole = lo == t0 + float(k) * dt && hi == t0 + float(k + 1) * dt;
    if (!visit(p, whole ? 1.0f : (hi - lo) / dt)) break;
  }
  return taken;
}

}  // namespace

std::vector<float> macrocell_opacity(const Macrocells& cells, const TransferFunction& tf) {
  std::vector<float> out(cells.lo.size());
  for (size_t i = 0; i < out.size(); ++i) out[i] = tf.max_opacity(cells.lo[i], cells.hi[i]);
  return out;
}

VolumeSegment march_volume(const MarchSetup& s, const Vec3& org, const Vec3& dir, float t0, float t1,
                           const SampleLighting* lighting) {
  VolumeSegment out;
  with_voxels(*s.grid, [&](const auto& v) {
    out.samples = walk_samples(s, org, dir, t0, t1, [&](const Vec3& p, float cover) {
      const TrilinearCell<float> cell = cell_at<float>(v, *s.grid, p);  // the value, then maybe the gradient
      const int i = s.tf->index(cell_value(cell));
      float a = s.tf->opacity_at(i);
      if (a <= 0.0f) return true;
      Vec3 c = s.tf->color_at(i);
      // Per voxel -> per stretch: from the table for whole stretches (the same arithmetic).
      a = s.step_opacity && cover == 1.0f ? (*s.step_opacity)[size_t(i)]
                                          : 1.0f - std::pow(1.0f - std::min(a, 0.999999f), s.step * cover);
      if (lighting) c *= lighting->light(p, cell_gradient(cell));
      out.color += out.transmittance * a * c;
      out.transmittance *= 1.0f - a;
      return out.transmittance >= 1e-3f;
    });
  });
  return out;
}

Vec3 march_transmittance(const MarchSetup& s, const Vec3& org, const Vec3& dir, float t0, float t1) {
  constexpr float kOpaque = 6.9077553f;  // -ln(1e-3)
  Vec3 depth(0.0f);                      // optical depth per channel
  with_voxels(*s.grid, [&](const auto& v) {
    walk_samples(s, org, dir, t0, t1, [&](const Vec3& p, float cover) {
      Vec3 c;
      float a;
      s.tf->lookup(cell_value(cell_at<float>(v, *s.grid, p)), c, a);
      if (a > 0.0f) depth += shadow_tint(c) * (-std::log(1.0f - std::min(a, 0.999999f)) * s.step * cover);
      return std::min(depth.x, std::min(depth.y, depth.z)) < kOpaque;
    });
  });
  Vec3 t;
  for (int k = 0; k < 3; ++k) t[k] = depth[k] < kOpaque ? std::exp(-depth[k]) : 0.0f;
  return t;
}

bool march_maximum(const MarchSetup& s, const Vec3& org, const Vec3& dir, float t0, float t1, float& value,
                   uint32_t* samples) {
  MarchSetup plain = s;
  plain.cell_opacity = nullptr;  // every sample counts, transparent or not
  float best = -kInfinity;
  const uint32_t n = with_voxels(*s.grid, [&](const auto& v) {
    return walk_samples(plain, org, dir, t0, t1, [&](const Vec3& p, float) {
      best = std::max(best, cell_value(cell_at<float>(v, *s.grid, p)));
      return true;
    });
  });
  value = best;
  if (samples) *samples = n;
  return n > 0;
}

}  // namespace frameless
