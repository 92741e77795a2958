// Motion as a function of time, and the bouncing-ball simulation baked into trajectories.
#include "core/scene/motion.h"

#include <cmath>

namespace frameless {
namespace {

// t mapped into [0, period) (also for negative t).
double wrap(double t, double period) {
  if (!(period > 0.0)) return 0.0;
  const double r = std::fmod(t, period);
  return r < 0.0 ? r + period : r;
}

Vec3 keyframes_offset(const Motion& m, double t) {
  const std::vector<Keyframe>& k = m.keys;
  if (k.empty()) return Vec3(0.0f);
  const double first = k.front().time, last = k.back().time;
  if (m.loop && last > first) t = first + wrap(t - first, last - first);
  if (t <= first) return k.front().translate;
  if (t >= last) return k.back().translate;
  size_t i = 1;
  while (i + 1 < k.size() && k[i].time < t) ++i;  // few keys: a linear scan beats a search
  const double span = double(k[i].time) - double(k[i - 1].time);
  const float s = span > 0.0 ? float((t - k[i - 1].time) / span) : 1.0f;
  return k[i - 1].translate + s * (k[i].translate - k[i - 1].translate);
}

Vec3 bounce_offset(const Bounce& b, double t) {
  if (!(b.period > 0.0f)) return Vec3(0.0f);
  // Phase in [0, 1): 0 and 1 touch the floor, 0.5 is the top: h (1 - (2s - 1)^2).
  const float s = float(wrap(t / b.period + b.phase, 1.0));
  const float x = 2.0f * s - 1.0f;
  return Vec3(0.0f, b.height * (1.0f - x * x), 0.0f);
}

// Cubic Hermite between two samples: positions and velocities make it C1 and exact for the
// parabolas of free flight.
Vec3 trajectory_offset(const Trajectory& tr, double t) {
  const size_t n = tr.position.size();
  if (n == 0) return Vec3(0.0f);
  if (n == 1) return tr.position[0];
  // Forward, then backward in time: elastic physics is time-reversible, so the ping-pong
  // is still a valid motion and never jumps.
  const double end = double(tr.step) * double(n - 1);
  double u = wrap(t, 2.0 * end);
  if (u > end) u = 2.0 * end - u;
  const double f = u / tr.step;
  size_t i = size_t(f);
  if (i >= n - 1) i = n - 2;
  const float s = float(f - double(i));
  const float h = tr.step;
  const float s2 = s * s, s3 = s2 * s;
  const float h00 = 2 * s3 - 3 * s2 + 1, h10 = s3 - 2 * s2 + s, h01 = -2 * s3 + 3 * s2,
              h11 = s3 - s2;
  return h00 * tr.position[i] + h10 * h * tr.velocity[i] + h01 * tr.position[i + 1] +
         h11 * h * tr.velocity[i + 1];
}

}  // namespace

Vec3 motion_offset(const Motion& m, double t) {
  if (!std::isfinite(t)) t = 0.0;
  switch (m.kind) {
    case MotionKind::kNone: return Vec3(0.0f);
    case MotionKind::kKeyframes: return keyframes_offset(m, t);
    case MotionKind::kBounce: return bounce_offset(m.bounce, t);
    case MotionKind::kTrajectory: return trajectory_offset(m.trajectory, t);
  }
  return Vec3(0.0f);
}

std::vector<Trajectory> simulate_balls(const BallWorld& world, const std::vector<BallState>& balls) {
  constexpr double kSubstep = 1.0 / 1920.0;  // 16 substeps per stored sample
  constexpr int kSubsteps = 16;
  const size_t nb = balls.size();
  std::vector<Trajectory> out(nb);
  const float step = float(kSubstep * kSubsteps);
  const size_t samples = size_t(std::ceil(std::max(0.0f, world.duration) / step)) + 1;
  std::vector<BallState> s = balls;
  std::vector<Vec3> start(nb);
  for (size_t b = 0; b < nb; ++b) {
    start[b] = s[b].center;
    out[b].step = step;
    out[b].position.reserve(samples);
    out[b].velocity.reserve(samples);
  }
  const Vec3 g(0.0f, -world.gravity, 0.0f);
  const float e = std::clamp(world.restitution, 0.0f, 1.0f);
  for (size_t k = 0; k < samples; ++k) {
    for (size_t b = 0; b < nb; ++b) {
      out[b].position.push_back(s[b].center - start[b]);
      out[b].velocity.push_back(s[b].velocity);
    }
    for (int sub = 0; sub < kSubsteps && k + 1 < samples; ++sub) {
      const float dt = float(kSubstep);
      for (BallState& ball : s) {  // semi-implicit Euler: velocity first keeps energy bounded
        ball.velocity += dt * g;
        ball.center += dt * ball.velocity;
        for (int a = 0; a < 3; ++a) {
          const float lo = world.box_lo[a] + ball.radius, hi = world.box_hi[a] - ball.radius;
          if (ball.center[a] < lo && ball.velocity[a] < 0.0f) {
            ball.center[a] = lo + (lo - ball.center[a]);  // reflect the overshoot
            ball.velocity[a] = -e * ball.velocity[a];
          } else if (ball.center[a] > hi && ball.velocity[a] > 0.0f) {
            ball.center[a] = hi - (ball.center[a] - hi);
            ball.velocity[a] = -e * ball.velocity[a];
          }
        }
      }
      if (!world.collisions) continue;
      for (size_t i = 0; i < nb; ++i)
        for (size_t j = i + 1; j < nb; ++j) {
          BallState &a = s[i], &b = s[j];
          const Vec3 d = b.center - a.center;
          const float dist = glm::length(d), reach = a.radius + b.radius;
          if (!(dist < reach) || !(dist > 0.0f)) continue;
          const Vec3 n = d / dist;
          const float closing = glm::dot(a.velocity - b.velocity, n);
          if (closing <= 0.0f) continue;  // already separating
          // Masses as volumes (equal density); impulse along the line of centres.
          const float ma = a.radius * a.radius * a.radius, mb = b.radius * b.radius * b.radius;
          const float j_imp = (1.0f + e) * closing / (1.0f / ma + 1.0f / mb);
          a.velocity -= (j_imp / ma) * n;
          b.velocity += (j_imp / mb) * n;
        }
    }
  }
  return out;
}

}  // namespace frameless
