// Moving objects in JSON scenes: keyframes, bounce and physics motions.
#include "core/io/scene_json_motion.h"

namespace frameless::scene_json {
namespace {

Motion parse_motion(const json& j, const std::string& f, Vec3& velocity, bool& physics) {
  require_object(j, f);
  Motion m;
  const std::string type = get_string(need(j, f, "type"), f + ".type");
  physics = false;
  if (type == "bounce") {
    check_keys(j, f, {"type", "height", "period", "phase"});
    m.kind = MotionKind::kBounce;
    m.bounce.height = get_float(need(j, f, "height"), f + ".height", 0.0, 1e6, "0..1e6");
    m.bounce.period = get_float(need(j, f, "period"), f + ".period", 1e-3, 1e6, "0.001..1e6");
    if (j.contains("phase")) m.bounce.phase = get_float(j["phase"], f + ".phase", 0.0, 1.0, "0..1");
  } else if (type == "keyframes") {
    check_keys(j, f, {"type", "keys", "loop"});
    m.kind = MotionKind::kKeyframes;
    if (j.contains("loop")) m.loop = get_bool(j["loop"], f + ".loop");
    const json& keys = need(j, f, "keys");
    if (!keys.is_array() || keys.empty() || keys.size() > 100000)
      fail(f + ".keys", "expected an array of 1..100000 {time, translate}");
    for (size_t i = 0; i < keys.size(); ++i) {
      const std::string kf = f + ".keys[" + std::to_string(i) + "]";
      require_object(keys[i], kf);
      check_keys(keys[i], kf, {"time", "translate"});
      Keyframe k;
      k.time = get_float(need(keys[i], kf, "time"), kf + ".time", -1e6, 1e6, "-1e6..1e6");
      k.translate = get_vec3(need(keys[i], kf, "translate"), kf + ".translate");
      if (!m.keys.empty() && !(k.time > m.keys.back().time))
        fail(kf + ".time", "must be later than the previous key's");
      m.keys.push_back(k);
    }
  } else if (type == "physics") {
    check_keys(j, f, {"type", "velocity"});
    physics = true;
    if (j.contains("velocity")) velocity = get_vec3(j["velocity"], f + ".velocity");
  } else {
    fail(f + ".type", "unknown motion '" + type + "' (bounce, keyframes or physics)");
  }
  return m;
}

}  // namespace

void parse_dynamic_sphere(const json& o, const std::string& f, Scene& s, const Sphere& sphere,
                          uint16_t material, PendingPhysics& physics) {
  if (s.dynamic.size() >= 65536) fail(f, "too many dynamic objects (at most 65536)");
  DynamicObject d;
  d.name = o.contains("name") ? get_string(o["name"], f + ".name") : f;
  d.sphere = sphere;
  d.material = material;
  if (o.contains("motion")) {
    Vec3 velocity(0.0f);
    bool is_physics = false;
    d.motion = parse_motion(o["motion"], f + ".motion", velocity, is_physics);
    if (is_physics) {
      physics.objects.push_back(s.dynamic.size());
      physics.balls.push_back(BallState{sphere.center, sphere.radius, velocity});
    }
  }
  s.dynamic.push_back(std::move(d));
}

void parse_instance_motion(const json& o, const std::string& f, Scene& s, uint32_t index) {
  Vec3 velocity(0.0f);
  bool is_physics = false;
  InstanceMotion m;
  m.index = index;
  m.motion = parse_motion(o, f, velocity, is_physics);
  if (is_physics) fail(f + ".type", "physics motion is for spheres only (bounce or keyframes)");
  s.instance_motions.push_back(std::move(m));
}

void finish_physics(const json* pj, Scene& s, PendingPhysics& pending) {
  BallWorld w;
  if (pj) {
    const std::string f = "physics";
    require_object(*pj, f);
    check_keys(*pj, f, {"gravity", "restitution", "collisions", "box_min", "box_max", "duration"});
    if (pj->contains("gravity")) w.gravity = get_float((*pj)["gravity"], f + ".gravity", -1e4, 1e4, "-1e4..1e4");
    if (pj->contains("restitution"))
      w.restitution = get_float((*pj)["restitution"], f + ".restitution", 0.0, 1.0, "0..1");
    if (pj->contains("collisions")) w.collisions = get_bool((*pj)["collisions"], f + ".collisions");
    if (pj->contains("box_min")) w.box_lo = get_vec3((*pj)["box_min"], f + ".box_min");
    if (pj->contains("box_max")) w.box_hi = get_vec3((*pj)["box_max"], f + ".box_max");
    if (pj->contains("duration"))
      w.duration = get_float((*pj)["duration"], f + ".duration", 1.0, 600.0, "1..600 seconds");
    if (!(w.box_lo.x < w.box_hi.x && w.box_lo.y < w.box_hi.y && w.box_lo.z < w.box_hi.z))
      fail(f, "box_min must be below box_max on every axis");
  }
  if (pending.balls.empty()) return;
  for (size_t i = 0; i < pending.balls.size(); ++i) {
    const BallState& b = pending.balls[i];
    for (int a = 0; a < 3; ++a)
      if (b.center[a] - b.radius < w.box_lo[a] || b.center[a] + b.radius > w.box_hi[a])
        fail(s.dynamic[pending.objects[i]].name, "physics ball starts outside the physics box");
  }
  const std::vector<Trajectory> paths = simulate_balls(w, pending.balls);
  for (size_t i = 0; i < paths.size(); ++i) {
    Motion& m = s.dynamic[pending.objects[i]].motion;
    m.kind = MotionKind::kTrajectory;
    m.trajectory = paths[i];
  }
}

}  // namespace frameless::scene_json
