// The mesh side of `bench volume`: marching tetrahedra, a BVH over the triangles, one frame.
#include "bench/bench_volume_mesh.h"

#include <chrono>

#include "bench/bench_options.h"
#include "bench/bench_report.h"
#include "core/io/scene_json.h"
#include "core/scene/scene_build.h"
#include "core/scene/scene_finalize.h"
#include "core/volume/marching_tetrahedra.h"
#include "frameless/image_error.h"
#include "frameless/tile_render.h"

namespace frameless::bench {

nlohmann::json compare_with_mesh(const Scene& iso_scene, const std::string& mesh_only_json, const std::string& dir,
                                 int w, int h, int spp, int threads, const std::vector<float>& iso_rgb,
                                 double iso_seconds) {
  using Clock = std::chrono::steady_clock;
  const VolumeObject& v = iso_scene.volumes.at(0);
  nlohmann::json j;
  const double rss0 = rss_bytes();
  auto t0 = Clock::now();
  IsoMesh iso = marching_tetrahedra(*v.grid, *v.cells, v.isovalues[0], v.inside_above, thread_parallel_for(threads));
  j["mesh_seconds"] = std::chrono::duration<double>(Clock::now() - t0).count();
  j["triangles"] = iso.positions.size() / 3;
  auto scene = parse_scene_json(mesh_only_json, dir + "/mesh.json", dir);
  if (!scene) throw std::runtime_error(scene.error().message);
  MeshData mesh;
  mesh.positions.reserve(iso.positions.size());
  for (const Vec3& p : iso.positions) mesh.positions.push_back(v.to_world.point(p));
  for (const Vec3& n : iso.normals) mesh.normals.push_back(glm::normalize(v.normal_to_world * n));
  mesh.triangles.reserve(iso.positions.size() / 3);
  for (uint32_t i = 0; i + 2 < uint32_t(iso.positions.size()); i += 3) mesh.triangles.push_back(UVec3(i, i + 1, i + 2));
  iso = IsoMesh{};  // the world copy is the scene's now
  const Material bone = iso_scene.materials[v.iso_materials[0]];
  add_mesh(**scene, mesh, glm::mat4(1.0f), add_material(**scene, bone));
  mesh = MeshData{};
  t0 = Clock::now();
  finalize_scene(**scene);
  j["bvh_build_seconds"] = std::chrono::duration<double>(Clock::now() - t0).count();
  j["resident_bytes_mesh_and_bvh"] = rss_bytes() - rss0;
  TileRenderOptions o;
  o.spp = spp;
  o.threads = threads;
  const RenderedImage img = render_tiles(**scene, make_camera_basis((*scene)->camera, w, h), o);
  j["frame_seconds"] = img.seconds;
  j["samples_per_s"] = double(w) * h * spp / img.seconds;
  j["isosurface_over_mesh_time"] = iso_seconds / img.seconds;
  j["rmse_against_isosurface"] = image_error(img.rgb, iso_rgb).rmse;
  return j;
}

}  // namespace frameless::bench
