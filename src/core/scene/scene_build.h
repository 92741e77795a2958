// Helpers the scene loaders share to put geometry into a Scene (meshes, quads, boxes, framing
// camera); loading thread only.
#pragma once
#include <string>

#include <glm/mat4x4.hpp>

#include "core/base/error.h"
#include "core/scene/mesh_data.h"
#include "core/scene/scene.h"

namespace frameless {

// Adds a material and returns its id.
uint16_t add_material(Scene& scene, const Material& m);

// Appends a mesh transformed by m: positions by m, normals by the inverse transpose, and the
// winding flipped when m mirrors, so that geometric normals keep pointing outward. UVs are
// kept (scene uvs stay empty or one per position: zeros for geometry without). A mesh that
// carries materials brings them and its textures into the scene and `material` is ignored,
// unless override_material asks for `material` on every face. The mesh's shared meshes are
// copied per placement (under m * to_model) or, with instancing, each becomes one InstancedMesh
// of the scene placed by one Instance per placement (transform m * to_model); a placement whose
// transform cannot be inverted is copied. Instancing needs `scene` to be the one rendered: a
// shared mesh of a JSON scene's "meshes" must not hold instances itself.
void add_mesh(Scene& scene, const MeshData& mesh, const glm::mat4& m, uint16_t material,
              bool override_material = false, bool instancing = false);

// Bounds of the triangles add_mesh places under m: the flat ones and every placement of a
// shared mesh (its vertices, or past 2^27 placed vertices its transformed object box); empty
// (lo > hi) when there are none.
void mesh_bounds(const MeshData& mesh, const glm::mat4& m, Vec3& lo, Vec3& hi);

// Finite quad: centre, unit normal, side length (square), oriented to face along normal; uv
// 0..1 across the square.
void add_quad(Scene& scene, const Vec3& center, const Vec3& normal, float size, uint16_t material);

// Axis-aligned box as 12 triangles with outward normals; 4 vertices per face, uv 0..1 on each.
void add_box(Scene& scene, const Vec3& lo, const Vec3& hi, uint16_t material);

void add_sphere(Scene& scene, const Vec3& center, float radius, uint16_t material);

// A camera that frames the box [lo, hi] from the front-right-above, for a width x height image.
Camera frame_camera(const Vec3& lo, const Vec3& hi, int width, int height);

// Mesh shown alone: its own materials or a default one, shared meshes as instances, one light
// over it, hemisphere ambient, framing camera.
std::unique_ptr<Scene> make_mesh_scene(MeshData mesh, const std::string& name);

// Hemisphere ambient used by the mesh viewer and the built-ins: cool sky above, warm ground below.
Ambient default_hemisphere_ambient();

}  // namespace frameless
