// Spline surfaces in JSON scenes: POV-Ray files or inline control points, transformed.
#include "core/io/scene_json_patches.h"

#include "core/io/patch_io.h"

namespace frameless::scene_json {

void parse_bezier(const json& o, const std::string& f, Scene& s, const std::string& base_dir,
                  uint16_t material, const glm::mat4& m) {
  check_keys(o, f, {"type", "file", "patches", "depth", "transform", "material"});
  if (o.contains("file") == o.contains("patches"))
    fail(f, "needs exactly one of \"file\" (POV-Ray bicubic_patch) and \"patches\" (control points)");
  const int depth = o.contains("depth") ? int(get_int(o["depth"], f + ".depth", 0, kMaxPatchDepth))
                                        : kDefaultPatchDepth;
  std::vector<BezierPatch> patches;
  if (o.contains("file")) {
    const std::string file = get_string(o["file"], f + ".file");
    const std::string full = !file.empty() && file[0] == '/' ? file : base_dir + "/" + file;
    auto loaded = load_bicubic_patches(full);
    if (!loaded) fail(f + ".file", loaded.error().message);
    patches = std::move(*loaded);
  } else {
    const json& list = o["patches"];
    if (!list.is_array() || list.empty()) fail(f + ".patches", "expected an array of patches");
    for (size_t i = 0; i < list.size(); ++i) {
      const std::string pf = f + ".patches[" + std::to_string(i) + "]";
      if (!list[i].is_array() || list[i].size() != 16)
        fail(pf, "expected 16 control points [x, y, z] (4 rows of 4)");
      BezierPatch p;
      for (size_t k = 0; k < 16; ++k) p.p[k] = get_vec3(list[i][k], pf + "[" + std::to_string(k) + "]");
      patches.push_back(p);
    }
  }
  if (s.geometry.patches.size() + patches.size() > 1'000'000) fail(f, "too many patches (at most 1000000)");
  for (BezierPatch& p : patches) {
    for (Vec3& c : p.p) {
      c = Vec3(m * Vec4(c, 1.0f));  // Bézier patches are affine invariant: transform the controls
      if (!is_finite(c)) fail(f + ".transform", "moves a control point beyond finite coordinates");
    }
    s.geometry.patches.emplace_back(p, depth);
    s.geometry.patch_material.push_back(material);
  }
}

}  // namespace frameless::scene_json
