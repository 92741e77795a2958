// A renderable scene: geometry + acceleration structure, materials, lights, ambient, default view
// and render settings. Built by loaders on one thread, then read-only for all render threads.
#pragma once
#include <string>
#include <vector>

#include "core/accel/accel.h"
#include "core/geometry/geometry.h"
#include "core/scene/camera.h"
#include "core/scene/dynamic_object.h"
#include "core/scene/emitters.h"
#include "core/scene/environment.h"
#include "core/scene/light.h"
#include "core/scene/lightfield.h"
#include "core/scene/material.h"
#include "core/scene/shader_material.h"
#include "core/scene/volume_object.h"

namespace frameless {

// Switches for the specialisations of the per-sample path (docs/adaptive.md). Each one only lets
// the shading skip work the scene cannot need; the ablation benchmark turns them off one by one to
// measure what each saves. All on by default. Plain data, read by render threads.
struct SkipConfig {
  bool shadows = true;     // no lights: shading compiled without the light loop and shadow rays
  bool refraction = true;  // no dielectric: compiled without refraction, media and absorption
  bool highlights = true;  // no highlight on any material: compiled without Phong lobes
  bool prune = true;       // prune ray-tree branches below min_contribution (off: only weight 0)
  bool any_hit = true;     // shadow rays stop at the first occluder (off: closest-hit traversal)
  // Path tracing without emitters and with a black environment: no emitter or environment
  // sampling (off: the black environment is sampled anyway, shadow rays and all).
  bool emitters = true;
};

// How a sample's light is computed (docs/global-illumination.md): Parker's Whitted-style model,
// or unbiased path tracing. kAuto becomes path for scenes with emitters, Whitted otherwise
// (finalize_scene decides).
enum class Integrator : uint8_t { kAuto, kWhitted, kPath, kIgi };
const char* integrator_name(Integrator i);
// "whitted", "path" or "igi" into out; false for anything else.
bool parse_integrator(const std::string& name, Integrator& out);

// Instant global illumination (core/shading/igi.h): light paths per VPL set, the side of the
// interleaved-sampling pattern (a different set for each of its pixels), and the clamping
// distance of the geometry term as a fraction of the scene's bounding-box diagonal.
struct IgiSettings {
  int paths = 16;       // 1..4096
  int interleave = 3;   // 1..8
  float clamp = 0.02f;  // [0, 1]
};

struct RenderSettings {
  int width = 640;
  int height = 480;
  int spp = 16;                        // samples per pixel for one-shot renders
  int max_depth = 25;                  // Whitted recursion limit (OpenRT's headlight model needed 25)
  float min_contribution = 1.0f / 512; // prune ray-tree branches whose weight falls below this
  Vec3 background{0.0f};               // radiance of rays that escape (without an environment map)
  uint64_t seed = 1;                   // global seed mixed into every sample
  SkipConfig skips;                    // which specialisations may be used (ablation switches)
  // Shadows: mode for lights with an extent (lights without one always cast hard shadows),
  // rays per light in area mode, and whether dielectrics attenuate shadow rays instead of
  // blocking them (transmittance k_t and Beer's law through each dielectric crossed).
  ShadowMode shadows = ShadowMode::kSoft;
  int shadow_samples = 16;
  bool transparent_shadows = false;
  AccelKind accel = AccelKind::kBvh;  // acceleration structure (bvh, grid, auto: core/accel/accel.h)
  Integrator integrator = Integrator::kAuto;
  IgiSettings igi;
};

// What the scene needs, found at finalize time so the per-sample path skips the rest.
struct SceneFeatures {
  bool has_lights = false;
  bool has_spheres = false;
  bool has_triangles = false;
  bool has_dielectric = false;
  bool has_reflection = false;  // metal, dielectric or polished
  bool has_highlights = false;  // some material with k_h != 0
  bool has_vertex_normals = false;
  bool has_absorption = false;  // some dielectric with extinction > 0 (Beer's law along the ray)
  bool has_ambient = false;     // ambient kind other than none
  bool has_textures = false;     // some material has a texture slot: hits compute UVs
  bool has_cutouts = false;      // some material has an alpha cut-out: traversal tests alpha
  bool has_soft_lights = false;  // some light has an extent and shadows are soft or area
  bool has_dynamic = false;      // some object moves: rays also test Scene::dynamic
  bool has_emission = false;     // some material emits: hits add its emission
};

struct Scene {
  std::string name;
  Geometry geometry;
  std::vector<Material> materials;  // geometry material ids index this
  std::vector<Texture> textures;    // material texture slots index this
  std::vector<ShaderMaterial> shaders;  // plug-in shaded materials' MaterialParams::shader indexes this
  std::vector<uint8_t> cutout_materials;  // per material: has an alpha cut-out (accel reads it)
  std::vector<Light> lights;
  EmitterTable emitters;  // emissive triangles as area lights (finalize_scene builds it)
  // settings.environment: the radiance of escaping rays from an image (null: settings.background).
  std::shared_ptr<const EnvironmentMap> environment;
  Ambient ambient;
  Camera camera;
  RenderSettings settings;
  SceneFeatures features;
  Accel accel;
  // Volumes (core/scene/volume_object.h): isosurfaces are surfaces outside `accel`, tested per
  // ray like the moving objects; the volume shader's and MIP's are composited along rays.
  std::vector<VolumeObject> volumes;
  bool see_through_volumes = false;  // some volume is not an isosurface (finalize_scene sets it)
  // Lightfield objects (core/scene/lightfield.h): composited along rays like the volume shader's.
  std::vector<LightfieldObject> lightfields;
  bool see_through = false;  // see-through volumes or lightfields (finalize_scene sets it)
  // Objects that move (seed section 4): outside `accel`, tested per ray (core/scene/dynamic.h).
  std::vector<DynamicObject> dynamic;
  // Instances that move (JSON "motion" on an instance): offsets from their declared placement,
  // applied by the application side (Engine::animate_instances), which publishes a refit top.
  std::vector<InstanceMotion> instance_motions;
  // Unique in the process, set by finalize_scene: per-thread caches (igi's VPL sets) key on it,
  // since a new scene can be allocated where a freed one was.
  uint64_t serial = 0;
};

}  // namespace frameless
