// The environment image of a scene file: read, checked and turned into a sampled map.
#include "core/io/scene_json_environment.h"

#include <cmath>

namespace frameless::scene_json {

void parse_environment(const json& j, Scene& s, const std::string& base_dir, ImageCache& images) {
  const std::string f = "settings.environment";
  require_object(j, f);
  check_keys(j, f, {"file", "rotate", "scale"});
  const std::string file = get_string(need(j, f, "file"), f + ".file");
  const std::string full = !file.empty() && file[0] == '/' ? file : base_dir + "/" + file;
  const float rotate = j.contains("rotate") ? get_float(j["rotate"], f + ".rotate", -360.0, 360.0, "in [-360, 360] degrees") : 0.0f;
  const float scale = j.contains("scale") ? get_float(j["scale"], f + ".scale", 0.0, 1e6, "in [0, 1e6]") : 1.0f;
  auto image = images.get(full);
  if (!image) fail(f + ".file", image.error().message);
  auto env = EnvironmentMap::make(**image, rotate * float(kPi / 180.0), scale);
  if (!env) fail(f + ".file", env.error().message);
  s.environment = *env;
}

}  // namespace frameless::scene_json
