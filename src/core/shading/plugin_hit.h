// What plug-in shaders (include/frameless/shader.h) are given: the hit as an fl_hit, the host
// calls that do not depend on the sample (noise, turbulence, textures), and the limited host of
// the path tracer's BSDF calls. Pure, any thread.
#pragma once
#include "core/geometry/surface.h"
#include "core/scene/scene.h"
#include "frameless/shader.h"

namespace frameless {

inline fl_vec3 to_fl(const Vec3& a) { return fl_vec3{a.x, a.y, a.z}; }
inline Vec3 from_fl(const fl_vec3& a) { return Vec3(a.x, a.y, a.z); }

// The hit: position, normals, direction, texture coordinates where the primitive has its own
// (not instances, moving objects or volumes), and the tangent frame around the shading normal.
fl_hit make_plugin_hit(const Scene& scene, const Ray& ray, const Hit& hit, const SurfacePoint& sp, int depth);

float plugin_noise(fl_vec3 p);
float plugin_turbulence(fl_vec3 p, int octaves);
// The scene's texture `slot` (a FL_PARAM_TEXTURE value) at (u, v) or point p; 0 when it names none.
fl_vec4 plugin_texture(const Scene& scene, float slot, float u, float v, fl_vec3 p);

// The host of eval() and sample(): ctx is the scene; lights, ambient, trace and random are inert.
fl_host path_plugin_host(const Scene& scene);

}  // namespace frameless
