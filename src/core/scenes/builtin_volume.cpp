// The built-in volume scenes "volume:KIND:SIZE[:MODE]" (issue 27): a generated grid in the unit
// cube around the origin, shown as an isosurface (default), through the volume shader ("direct")
// or by maximum intensity projection ("mip"), over a floor, lit by a soft light.
#include <cmath>

#include "core/scene/scene_build.h"
#include "core/scene/scene_finalize.h"
#include "core/scenes/builtin_scenes.h"
#include "core/volume/volume_generators.h"

namespace frameless {

Result<std::unique_ptr<Scene>> make_volume_scene(const std::string& name) {
  std::string grid_name = name, mode = "isosurface";
  const size_t last = name.rfind(':');
  for (const char* m : {"isosurface", "direct", "mip"})
    if (name.compare(last + 1, std::string::npos, m) == 0) {
      grid_name = name.substr(0, last);
      mode = m;
    }
  auto grid = make_builtin_volume(grid_name, default_build_executor());  // on every core, as builds
  if (!grid) return Error{grid.error().message + "; a mode may follow: :isosurface, :direct or :mip"};
  const std::string kind = grid_name.substr(7, grid_name.find(':', 7) - 7);
  auto s = std::make_unique<Scene>();
  s->name = name;
  VolumeObject v;
  v.source = grid_name;
  v.grid = *grid;
  const VolumeGrid& g = **grid;
  if (mode == "isosurface") {
    v.mode = VolumeMode::kIsosurface;
    // The signal's usual level (Marschner-Lobb), the skull (Shepp-Logan), a sphere of a third
    // of the grid (distances: inside below).
    const float iso = kind == "marschner-lobb" ? 0.5f : kind == "shepp-logan" ? 1600.0f : float(g.nx - 1) / 3.0f;
    v.isovalues = {iso};
    v.inside_above = kind != "sphere";
    v.iso_materials = {add_material(*s, kind == "shepp-logan" ? polished("bone", Vec3(0.9f, 0.85f, 0.72f), 0.04f)
                                                              : polished("iso", Vec3(0.75f, 0.45f, 0.3f), 0.05f))};
  } else {
    v.mode = mode == "direct" ? VolumeMode::kDirect : VolumeMode::kMip;
    const char* preset = v.mode == VolumeMode::kMip ? "grayscale" : kind == "shepp-logan" ? "ct-bone" : kind == "marschner-lobb" ? "hot" : "grayscale";
    v.tf = std::make_shared<TransferFunction>(*TransferFunction::preset(preset, g.min_value, g.max_value, "transfer"));
  }
  // Into the cube [-1, 1]^3 (the largest side); the head phantom stands up (its z is our y).
  const Vec3 ext = g.extent();
  const float k = 2.0f / max_component(ext);
  Affine place;
  place.m = glm::mat3(k);
  place.t = -0.5f * k * ext;
  if (kind == "shepp-logan") {  // rotate -90 degrees about x: z -> y, y -> -z
    const glm::mat3 r(Vec3(1, 0, 0), Vec3(0, 0, -1), Vec3(0, 1, 0));
    place.m = r * place.m;
    place.t = r * place.t;
  }
  place_volume(v, place);
  s->volumes.push_back(std::move(v));
  const uint16_t floor = add_material(*s, diffuse("floor", Vec3(0.55f)));
  add_quad(*s, Vec3(0.0f, -1.05f, 0.0f), Vec3(0.0f, 1.0f, 0.0f), 8.0f, floor);
  Light sun;
  sun.position = Vec3(2.5f, 4.0f, 3.0f);
  sun.radius = 0.3f;
  sun.color = Vec3(0.9f);
  s->lights.push_back(sun);
  s->ambient = default_hemisphere_ambient();
  s->settings.background = Vec3(0.12f, 0.13f, 0.16f);
  s->camera.eye = Vec3(1.6f, 0.9f, 3.6f);
  s->camera.look = Vec3(0.0f, -0.1f, 0.0f);
  s->camera.fov_deg = 38.0f;
  s->settings.width = 512;
  s->settings.height = 512;
  finalize_scene(*s);
  return s;
}

}  // namespace frameless
