// The Accel's own top level (core/accel/instance_top.h) over geom.instances, and the queries that
// let a caller substitute a newer top (instances moved since the build).
// The layers' one intended recursion: an Accel holds a top level whose instances point at
// InstancedMeshes, each with an Accel of its own. It ends after one level: the readers never put
// instances into a shared mesh (a JSON scene's "meshes" and the glTF loader place copies there).
#include "core/accel/accel_impl.h"
#include "core/accel/instance.h"
#include "core/accel/instance_top.h"

namespace frameless {

void Accel::build_instances(Geometry& geom, const AccelConfig& config) {
  Impl& im = *impl_;
  im.top.reset();
  if (geom.instances.empty()) return;
  std::shared_ptr<InstanceTop> top = build_instance_top(geom.instances, geom.instance_meshes, config);
  im.stats.bytes += top->nodes.size() * sizeof(Bvh8Node);
  im.stats.geometry_bytes += top->bytes() - top->nodes.size() * sizeof(Bvh8Node);
  // Each shared mesh counts once, however many instances place it.
  for (const std::shared_ptr<InstancedMesh>& m : geom.instance_meshes)
    im.stats.geometry_bytes += m->accel.stats().bytes + m->accel.stats().geometry_bytes;
  im.top = std::move(top);
}

std::shared_ptr<const InstanceTop> Accel::instance_top() const { return impl_->top; }

bool Accel::has_instances() const { return impl_->top != nullptr; }

const InstanceTop* Accel::top_in_use(const InstanceTop* top) const {
  return top ? top : impl_->top.get();
}

bool Accel::occluded_instances(const Ray& ray, const InstanceTop* top) const {
  top = top_in_use(top);
  return top && frameless::occluded_instances(*top, ray);
}

}  // namespace frameless
