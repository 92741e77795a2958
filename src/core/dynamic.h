// Objects that move while you look (seed section 4): kept out of the static acceleration
// structure and tested per ray, as RTRT did. A DynamicFrame is what one sample sees: each
// dynamic object at that sample's instant, plus the current lights and materials (which the
// application may change too). Render threads own their frames; nothing here locks.
#pragma once
#include <memory>
#include <string>
#include <vector>

#include "core/geometry.h"
#include "core/light.h"
#include "core/material.h"
#include "core/motion.h"
#include "core/ray.h"
#include "core/surface.h"

namespace frameless {

struct Scene;
struct InstanceTop;

// Hits on dynamic object i carry prim = kDynamicPrimBase + i.
inline constexpr uint32_t kDynamicPrimBase = 0xc0000000u;
inline bool is_dynamic_prim(uint32_t prim) { return prim >= kDynamicPrimBase && prim != kInvalidId; }

struct DynamicObject {
  std::string name;
  Sphere sphere;         // rest position and radius
  uint16_t material = 0;
  Motion motion;         // offset from the rest (or application-set) position as time passes
};

// An instance that moves: declared instance `index` translated from its declared placement.
struct InstanceMotion {
  uint32_t index = 0;
  Motion motion;
};

// What the application side may change while rendering (published through the engine's motion
// channel): where each dynamic object sits (before its own motion adds to it), the lights, and
// the changeable parameters of each material.
struct WorldState {
  std::vector<Vec3> object_position;    // one per dynamic object: its base centre
  std::vector<Light> lights;            // same count and kinds as the scene's
  std::vector<MaterialParams> materials;  // same count and classes as the scene's
};

// The world as a scene declares it (rest positions, its lights and materials).
WorldState initial_world(const Scene& scene);

// Floats per object, light and material in the flat form the motion channel carries.
inline constexpr int kObjectFloats = 3;   // base centre
inline constexpr int kLightFloats = 7;    // position, colour, radius
inline constexpr int kMaterialFloats = 10;  // kd, ks, kh, phong exponent
size_t world_floats(const Scene& scene);
// Flat form of `w` for a scene with the same counts (world_floats(scene) floats).
void pack_world(const WorldState& w, std::vector<float>& out);
// Reads the flat form back over `w` (whose counts, kinds and classes stay); false and no change
// when the size does not match or a value is not finite.
bool unpack_world(const float* data, size_t n, WorldState& w);

// One sample's view of everything that moves.
struct DynamicFrame {
  std::vector<Sphere> spheres;            // each dynamic object at the frame's instant
  std::vector<uint16_t> sphere_material;  // material of each
  std::vector<Light> lights;              // current lights
  std::vector<MaterialParams> materials;  // current material parameters
  // Instances moved since the scene was built: the newest top level picked up (null: none moved).
  std::shared_ptr<const InstanceTop> instances;
  double time = -1.0;                     // instant the spheres were evaluated at
  uint32_t shade_path = 15u;              // shading path for these lights and materials
};

// Sets `frame` to world `w` at time t (allocates only when the counts grow).
void evaluate_frame(const Scene& scene, const WorldState& w, double t, DynamicFrame& frame);
// Moves the spheres to time t only (the per-sample path: no allocation).
void advance_frame(const Scene& scene, const WorldState& w, double t, DynamicFrame& frame);

// The moved instances' top level a frame sees (null: the scene's own, as built).
inline const InstanceTop* frame_instances(const DynamicFrame* frame) {
  return frame ? frame->instances.get() : nullptr;
}

// Closest hit over the static structure and the dynamic objects (frame may be null).
bool scene_intersect(const Scene& scene, const DynamicFrame* frame, const Ray& ray, Hit& hit);
// Adds the frame's moving objects to `hit`, the static scene's closest hit of `ray` (invalid on a
// miss); returns whether anything was hit.
bool merge_dynamic_hit(const DynamicFrame* frame, const Ray& ray, Hit& hit);
// Any hit over both (shadow rays).
bool scene_occluded(const Scene& scene, const DynamicFrame* frame, const Ray& ray);
// Surface point of a hit from scene_intersect (static or dynamic).
SurfacePoint scene_surface_point(const Scene& scene, const DynamicFrame* frame, const Ray& ray,
                                 const Hit& hit);
// frame_material() and frame_lights() (the parameters in effect) are in core/scene.h.

}  // namespace frameless
