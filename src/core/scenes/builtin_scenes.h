// Built-in scenes that need no files, and the animated state of Parker's bouncing balls;
// loading thread (pure functions).
#pragma once
#include <initializer_list>
#include <memory>
#include <vector>

#include "core/base/error.h"
#include "core/geometry/geometry.h"
#include "core/scene/scene.h"

namespace frameless {

// Parker's bouncing balls (figure 2; builtin_balls.cpp): dynamic spheres moved by a baked
// physics simulation (core/scene/motion.h), soft shadows from a spherical light. Not yet finalized.
std::unique_ptr<Scene> make_balls();

// The Cornell box (builtin_cornell.cpp): published geometry, diffuse walls, an emissive ceiling
// light, no Parker lights; rendered by the path tracer by default. Not yet finalized.
std::unique_ptr<Scene> make_cornell();

// "volume:KIND:SIZE[:MODE]" (builtin_volume.cpp): a generated grid (core/volume/volume_generators.h)
// as an isosurface, through the volume shader (direct) or by MIP, over a floor. Finalized.
Result<std::unique_ptr<Scene>> make_volume_scene(const std::string& name);

// Materials of the built-in scenes, one per class (Parker's models, core/scene/material.h).
Material diffuse(const char* name, Vec3 kd);
Material metal(const char* name, Vec3 ks, float phong);
Material dielectric(const char* name, float ior, Vec3 extinction);
Material polished(const char* name, Vec3 kd, float r0);

// Largest N that "spheres:N" accepts.
inline constexpr uint64_t kMaxRandomSpheres = 35'000'000;

// The random scenes' setting (spheres:N, soup:N): the camera framing all geometry, one white
// light above and beside it, the hemisphere ambient, the seed recorded.
void frame_random_scene(Scene& scene, uint64_t seed);

// "soup:N[:SEED]" (builtin_soup.cpp): N random overlapping triangles about one unit across in a
// cube of side cbrt(N), seeded. Not yet finalized. At most kMaxSoupTriangles.
std::unique_ptr<Scene> make_soup(uint64_t count, uint64_t seed);
inline constexpr uint64_t kMaxSoupTriangles = 20'000'000;

// Path of the Stanford bunny shipped by Debian's glmark2-data.
// A scene kept in the binary as JSON whose files lie under /usr/share; each need names a folder
// and the Debian package that brings it (a one-line error names the missing one).
struct EmbeddedNeed {
  const char* dir;
  const char* package;
};
Result<std::unique_ptr<Scene>> load_embedded_scene(const char* json, const char* name,
                                                   std::initializer_list<EmbeddedNeed> needs);

// The textured showcase scene (builtin_showcase.cpp), finalized.
Result<std::unique_ptr<Scene>> make_showcase();

// The Utah teapot as 32 spline patches, and the room of the seed's figure 16
// (builtin_teapot.cpp), finalized.
Result<std::unique_ptr<Scene>> make_teapot();
Result<std::unique_ptr<Scene>> make_room();

// OpenRT's office (builtin_office.cpp): plug-in wood and marble, a bump-mapped mirror showing a
// lightfield object baked at load, the volume shader's phantom, glass, soft shadows. Finalized.
Result<std::unique_ptr<Scene>> make_office();

// OpenRT's sunflower field (builtin_sunflowers.cpp): ten plant kinds instanced `plants` times
// (plus a few trees), finalized. The default count represents about one billion triangles.
// flat: the same field copied into one plain mesh, without instancing (big-mesh benchmarks).
inline constexpr uint64_t kDefaultSunflowers = 46000;
inline constexpr uint64_t kMaxSunflowers = 1'000'000;
Result<std::unique_ptr<Scene>> make_sunflowers(uint64_t plants = kDefaultSunflowers,
                                               bool flat = false);
inline constexpr uint64_t kMaxFlatSunflowers = 20000;  // about 430 million triangles

inline constexpr const char* kBunnyPath = "/usr/share/glmark2/models/bunny.obj";

}  // namespace frameless
