// JSON scene files; placeholder until the reader lands.
#include "core/scene_io.h"

namespace frameless {

Result<std::unique_ptr<Scene>> parse_scene_json(const std::string&, const std::string& path,
                                                const std::string&) {
  return Error{path + ": JSON scenes not implemented yet"};
}

}  // namespace frameless
