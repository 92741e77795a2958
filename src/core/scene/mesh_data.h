// A mesh or model as a reader hands it over (positions, materials, shared meshes, cameras,
// lights), before scene_build's add_mesh places it into a Scene. Plain data, loading thread.
#pragma once
#include <string>
#include <vector>

#include <glm/mat4x4.hpp>

#include "core/scene/camera.h"
#include "core/scene/light.h"
#include "core/scene/material.h"

namespace frameless {

// One placement of a shared mesh of a model: model space = to_model * the mesh's object space.
struct MeshPlacement {
  uint32_t mesh = 0;  // index into MeshData::shared
  glm::mat4 to_model{1.0f};
};

// A mesh as read from a file. Files that carry materials (OBJ+MTL, glTF) fill `materials`
// (their texture slots index `textures`) and give each triangle one of them in face_material;
// add_mesh maps both into the scene. Otherwise the caller's material applies to every face.
struct MeshData {
  std::vector<Vec3> positions;
  std::vector<Vec3> normals;  // empty or one per position
  std::vector<Vec2> uvs;      // empty or one per position
  std::vector<UVec3> triangles;
  std::vector<uint16_t> face_material;  // empty, or one index into materials per triangle
  std::vector<Material> materials;
  std::vector<Texture> textures;
  // Meshes the file places more than once (glTF meshes that two or more nodes reference), each
  // stored once in its own object space with the same invariants as above, except that their
  // face_material indexes this mesh's `materials` (their own materials and textures stay
  // empty). add_mesh copies them per placement, or places one shared InstancedMesh each.
  std::vector<MeshData> shared;
  std::vector<MeshPlacement> placements;
};

// What a model file brings besides its mesh (glTF): its cameras and lights, in model space
// after the node transforms, and warnings to print once (unsupported features).
struct ModelData {
  MeshData mesh;
  std::vector<Camera> cameras;
  std::vector<Light> lights;
  std::vector<std::string> warnings;
};

}  // namespace frameless
