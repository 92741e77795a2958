// Textures of a hit on an instance, evaluated where the mesh's texture coordinates live.
#include "core/scene/instance_texturing.h"

#include "core/accel/instance.h"
#include "core/scene/texturing.h"

namespace frameless {

void apply_instance_textures(const Scene& scene, const InstanceTop& top, const Ray& ray,
                             const Hit& hit, MaterialParams& m, SurfacePoint& sp) {
  const Instance& inst = top.instances[hit.inst];
  const InstancedMesh& mesh = *(*top.meshes)[inst.mesh];
  const Ray oray = to_object_ray(inst, ray);
  Hit local = hit;
  local.inst = kInvalidId;
  SurfacePoint osp = surface_point(mesh.geometry, oray, local);
  apply_textures(scene, mesh.geometry, oray, local, m, osp);
  sp.ns = unit_or(inst.normal_to_world * osp.ns, sp.ns);
}

}  // namespace frameless
