// Motion that is a pure function of time (seed section 4: objects that move while you look):
// keyframed translations, a bounce, and Parker's bouncing balls as a baked physics trajectory.
// Evaluated per sample on render threads, so every function here is const and allocation-free.
#pragma once
#include <string>
#include <vector>

#include "core/base/types.h"

namespace frameless {

struct Keyframe {
  float time = 0.0f;             // seconds
  Vec3 translate{0.0f};          // offset from the object's rest position
};

// A ball bouncing on a floor: a parabola of the given height above its rest position, hitting
// the rest height every `period` seconds (elastic: the same height forever).
struct Bounce {
  float height = 1.0f;
  float period = 1.0f;
  float phase = 0.0f;  // fraction of a period, [0, 1)
};

// A trajectory sampled at fixed steps (a baked simulation): positions and velocities every
// `step` seconds over [0, step * (n - 1)]; times wrap around the end (the sequence repeats).
struct Trajectory {
  float step = 1.0f / 120.0f;
  std::vector<Vec3> position;  // offsets from the rest position
  std::vector<Vec3> velocity;
};

enum class MotionKind : uint8_t { kNone, kKeyframes, kBounce, kTrajectory };

struct Motion {
  MotionKind kind = MotionKind::kNone;
  std::vector<Keyframe> keys;  // kKeyframes: sorted by time, at least one
  bool loop = true;            // kKeyframes: repeat after the last key (else hold it)
  Bounce bounce;               // kBounce
  Trajectory trajectory;       // kTrajectory
};

// Offset from the rest position at time t (seconds); zero for kNone. Finite for finite t.
Vec3 motion_offset(const Motion& m, double t);

// Parker's bouncing balls (figure 2) as physics: gravity, elastic bounces on the floor and the
// walls of a box, optional ball-ball collisions. The simulation runs once, at load, with a fixed
// step, and is stored as one Trajectory per ball, so motion stays a pure function of time
// (deterministic captures stay bit-identical; every sample can see its own instant).
struct BallWorld {
  Vec3 box_lo{-5.0f, 0.0f, -5.0f};  // floor at box_lo.y; walls at the x and z bounds
  Vec3 box_hi{5.0f, 100.0f, 5.0f};
  float gravity = 9.81f;             // downward acceleration, units / s^2
  float restitution = 1.0f;          // speed kept at a bounce (1: elastic, bounces forever)
  bool collisions = true;            // balls bounce off each other (equal-density spheres)
  float duration = 120.0f;           // seconds simulated before the motion repeats
};

struct BallState {
  Vec3 center{0.0f};
  float radius = 0.5f;
  Vec3 velocity{0.0f};
};

// Simulates the balls and returns one trajectory per ball (offsets from each starting centre).
std::vector<Trajectory> simulate_balls(const BallWorld& world, const std::vector<BallState>& balls);

}  // namespace frameless
