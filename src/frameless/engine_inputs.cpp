// What the application side publishes while the engine renders: the camera, the world (dynamic
// objects, lights, materials) and moved instances, each through its lock-free channel; render
// threads pick them up after a set share of their pixels (frameless/engine_impl.h).
#include <stdexcept>

#include "core/scene/dynamic.h"
#include "core/scene/instance_moves.h"
#include "frameless/engine.h"
#include "frameless/engine_impl.h"

namespace frameless {

uint32_t Engine::publish_camera(const Camera& camera) {
  if (!camera_is_valid(camera)) throw std::invalid_argument("publish_camera: invalid camera");
  return impl_->channel.publish(camera);
}
uint32_t Engine::publish_camera_as(const Camera& camera, uint32_t epoch) {
  if (!camera_is_valid(camera)) throw std::invalid_argument("publish_camera: invalid camera");
  return impl_->channel.publish_as(camera, epoch);
}
uint32_t Engine::camera_epoch() const { return impl_->channel.epoch(); }

uint32_t Engine::publish_world(const WorldState& world) {
  Impl& e = *impl_;
  if (const std::string p = world_problem(world, initial_world(e.scene)); !p.empty())
    throw std::invalid_argument("publish_world: " + p);
  std::vector<float> flat;
  pack_world(world, flat);
  return e.world_channel.publish(flat.data(), flat.size());
}

uint32_t Engine::world_epoch() const { return impl_->world_channel.epoch(); }

uint32_t Engine::move_instances(const std::vector<InstanceMove>& moves, InstanceUpdate* info) {
  Impl& e = *impl_;
  std::lock_guard<std::mutex> publishing(e.instances_publish);
  const std::shared_ptr<const InstanceTop> from = instance_top();  // the newest: moves build on it
  if (!from) throw std::invalid_argument("move_instances: the scene has no instances");
  auto moved = frameless::move_instances(*from, moves, AccelConfig{}, info);
  if (!moved) throw std::invalid_argument("move_instances: " + moved.error().message);
  std::lock_guard<std::mutex> lock(e.instances_mutex);
  e.instances = std::move(*moved);
  const uint32_t epoch = e.instances_epoch.load(std::memory_order_relaxed) + 1;
  e.instances_epoch.store(epoch, std::memory_order_release);
  return epoch;
}

uint32_t Engine::animate_instances(double t, InstanceUpdate* info) {
  if (impl_->scene.instance_motions.empty()) return 0;
  return move_instances(instance_moves_at(impl_->scene, t), info);
}

uint32_t Engine::instances_epoch() const { return impl_->instances_epoch.load(std::memory_order_acquire); }

std::shared_ptr<const InstanceTop> Engine::instance_top() const {
  const Impl& e = *impl_;
  std::lock_guard<std::mutex> lock(e.instances_mutex);
  return e.instances ? e.instances : e.scene.accel.instance_top();
}

Affine Engine::instance_transform(uint32_t i) const {
  const std::shared_ptr<const InstanceTop> top = instance_top();
  if (!top || i >= top->position.size())
    throw std::out_of_range("instance_transform: instance " + std::to_string(i) + " out of range");
  return top->instances[top->position[i]].to_world;
}

WorldState Engine::world() const {
  std::vector<float> flat;
  impl_->world_channel.read(flat);
  WorldState w = initial_world(impl_->scene);
  unpack_world(flat.data(), flat.size(), w);
  return w;
}
Camera Engine::camera() const { return impl_->channel.read(); }
Camera Engine::camera(uint32_t* epoch) const { return impl_->channel.read(epoch); }

}  // namespace frameless
