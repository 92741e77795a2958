// What moves while you look (seed section 4), at one instant: the flat world state the motion
// channel carries, and a DynamicFrame is what one sample sees: each
// dynamic object at that sample's instant, plus the current lights and materials (which the
// application may change too). Render threads own their frames; nothing here locks.
#pragma once
#include <memory>
#include <string>
#include <vector>

#include "core/scene/scene.h"

namespace frameless {

struct InstanceTop;

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

// What is wrong with `w` as the world of a scene whose initial world is `shape` (its counts):
// "" when it is usable, else one line naming the item ("light 2: colour must be finite and >= 0").
// Every value finite; light colours and radii, material colours, exponents and emission >= 0.
std::string world_problem(const WorldState& w, const WorldState& shape);

// Floats per object, light and material in the flat form the motion channel carries.
inline constexpr int kObjectFloats = 3;   // base centre
inline constexpr int kLightFloats = 7;    // position, colour, radius
inline constexpr int kMaterialFloats = 13;  // kd, ks, kh, phong exponent, emission
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


// Material parameters in effect for a sample: the frame's (changed while you look) or the scene's.
inline const MaterialParams& frame_material(const Scene& scene, const DynamicFrame* frame,
                                            uint16_t id) {
  if (frame && id < frame->materials.size()) return frame->materials[id];
  return scene.materials[id];
}

// Lights in effect for a sample.
inline const std::vector<Light>& frame_lights(const Scene& scene, const DynamicFrame* frame) {
  return frame && frame->lights.size() == scene.lights.size() ? frame->lights : scene.lights;
}

}  // namespace frameless
