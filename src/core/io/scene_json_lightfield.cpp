// {"type": "lightfield", "file": "slab.exr", "transform": ...}: the slab as baked, moved by the
// transform (the baked model's coordinates -> world).
#include "core/io/scene_json_lightfield.h"

#include <cmath>

#include "core/io/lightfield_file.h"

namespace frameless::scene_json {

void parse_lightfield(const json& o, const std::string& f, Scene& s, const std::string& base_dir) {
  check_keys(o, f, {"type", "file", "transform"});
  if (s.lightfields.size() >= 256) fail(f, "too many lightfields (at most 256)");
  const std::string file = get_string(need(o, f, "file"), f + ".file");
  const std::string full = !file.empty() && file[0] == '/' ? file : base_dir + "/" + file;
  auto table = load_lightfield(full);
  if (!table) fail(f + ".file", table.error().message);
  const glm::mat4 m = o.contains("transform") ? parse_transform(o["transform"], f + ".transform") : glm::mat4(1.0f);
  const Affine a = to_affine(m);
  if (!(std::abs(glm::determinant(a.m)) > 1e-12f)) fail(f + ".transform", "is singular");
  s.lightfields.push_back(place_lightfield(*table, a));
}

}  // namespace frameless::scene_json
