// PLY input (ascii, binary little and big endian); placeholder until the reader lands.
#include "core/scene_io.h"

namespace frameless {

Result<MeshData> parse_ply(const std::string&, const std::string& path) {
  return Error{path + ": PLY reader not implemented yet"};
}

}  // namespace frameless
