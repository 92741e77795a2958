// glTF input internals shared by mesh_gltf.cpp (tinygltf, geometry), gltf_instances.cpp (the
// node tree, instances, cameras, lights), gltf_check.cpp (what tinygltf lets through) and
// gltf_material.cpp (materials, textures, images); loading thread only.
#pragma once
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <tuple>
#include <utility>
#include <vector>

// The Debian package builds tinygltf as a shared library: the header alone declares it, and its
// class layouts do not depend on the TINYGLTF_NO_* macros, so none is defined here.
#include <tiny_gltf.h>

#include "core/io/mesh_readers.h"

namespace frameless::gltf {

inline Error fail(const std::string& path, const std::string& what) {
  return Error{path + ": " + what};
}

inline std::string str(long long i) { return std::to_string(i); }

// What gltf_check found safe to hand to tinygltf: the container kind and the buffer files
// tinygltf may read (its own spelling of the path, and the file we read for it).
struct Checked {
  bool binary = false;
  std::vector<std::pair<std::string, std::string>> buffer_files;
};

// The checks tinygltf does not make, before it sees the bytes: GLB chunk bounds, JSON syntax,
// nesting depth and the types of the members we read, extensionsRequired, buffer files that
// cannot be read. Errors are one line naming PATH.
Result<Checked> check_gltf(const std::string& bytes, const std::string& path,
                           const std::string& base_dir);

// Routes tinygltf's file access to checked's buffer files only, and makes its image callback
// decode nothing (gltf_material loads the images textures use), keeping the bytes of data: URI
// images in `embedded` by image index. `checked` and `embedded` must outlive the loads.
void restrict_loader(tinygltf::TinyGLTF& loader, Checked& checked,
                     std::map<int, std::string>& embedded);

// A node the default scene reaches, with its world matrix (its parents' and its own).
struct NodeVisit {
  int node = 0;
  glm::dmat4 world{1.0};
  bool invertible = false;  // it has a mesh and an Instance can be made with `world`
  bool instance = false;    // its mesh is shared (placed by two or more invertible visits)
};

// The default scene's nodes (else scene 0's, else every node that is no node's child),
// depth-first in file order. One-line errors: a node or mesh index out of range, a node reached
// twice (a cycle or two parents), a malformed or non-finite transform, too many instances.
Result<std::vector<NodeVisit>> walk_nodes(const tinygltf::Model& m, const std::string& path);

// The perspective camera of node n (looking down its -Z, +Y up) into out.cameras; other camera
// types and invalid ones are skipped with a warning.
std::optional<Error> add_camera(const tinygltf::Model& m, const std::string& path, int n, int index,
                                const glm::dmat4& world, ModelData& out);

// KHR_lights_punctual lights (index, node world matrix) into out.lights, scaled by their
// illuminance at the centre of out.mesh (flat triangles and placed shared meshes).
void add_lights(const tinygltf::Model& m, const std::vector<std::pair<int, glm::dmat4>>& lights,
                ModelData& out);

// RFC 3986 percent-decoding ("%20" -> ' '); malformed escapes are kept as written.
std::string percent_decode(const std::string& uri);
// dir/rel, or rel when dir is empty.
std::string join_path(const std::string& dir, const std::string& rel);
// Replaces line breaks with "; " and drops trailing ones (tinygltf's messages are multi-line).
std::string one_line(const std::string& text);

// Converts glTF materials on first use into MeshData::materials and their textures into
// MeshData::textures, loading each image once.
class MaterialMap {
 public:
  MaterialMap(const tinygltf::Model& model, const std::string& path, const std::string& base_dir,
              ImageCache& images, const std::map<int, std::string>& embedded, MeshData& mesh,
              std::vector<std::string>& warnings)
      : model_(model),
        path_(path),
        base_dir_(base_dir),
        images_(images),
        embedded_(embedded),
        mesh_(mesh),
        warnings_(warnings) {}

  // Index into mesh.materials for glTF material `index` (-1: the default material).
  Result<uint16_t> get(int index);

 private:
  Result<Material> convert(int index);
  // Index into mesh.textures for a texture reference, or kNoTexture when `index` is -1.
  Result<uint32_t> texture(int index, const tinygltf::ExtensionMap& ext, bool srgb,
                           const std::string& where);
  Result<std::shared_ptr<const Image>> image(int index);
  void warn_once(const std::string& w);

  const tinygltf::Model& model_;
  const std::string& path_;
  const std::string& base_dir_;
  ImageCache& images_;
  const std::map<int, std::string>& embedded_;  // data: URI images, decoded bytes by index
  MeshData& mesh_;
  std::vector<std::string>& warnings_;
  std::map<int, uint16_t> materials_;
  std::map<int, std::shared_ptr<const Image>> decoded_;
  std::map<std::tuple<int, bool, float, float, float, float>, uint32_t> textures_;
};

}  // namespace frameless::gltf
