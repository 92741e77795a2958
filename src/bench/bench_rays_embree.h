// Embree 3 reference for `frameless bench rays` and `bench build`: the same scene and rays through
// rtcIntersect1 / rtcOccluded1 and 8-wide packets (instances as Embree's own instances, for rays),
// and its build time with 1 or N build threads; built on the main thread, queried from bench
// threads.
#pragma once
#include <embree3/rtcore.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <time.h>

#include <vector>

#include "core/accel/instance.h"
#include "core/scene/scene.h"

namespace frameless::bench {

struct EmbreeHit {
  float t = kInfinity;
  unsigned geom = RTC_INVALID_GEOMETRY_ID;
  unsigned prim = 0;
  unsigned inst = RTC_INVALID_GEOMETRY_ID;  // the declared instance (Geometry::instances) hit, if any
  bool valid() const { return geom != RTC_INVALID_GEOMETRY_ID; }
};

// How Embree builds its scenes: its robust mode or not (RTC_SCENE_FLAG_ROBUST) and its build
// quality (RTC_BUILD_QUALITY_*: medium is its default, high adds spatial splits).
struct EmbreeMode {
  bool robust = false;
  RTCBuildQuality quality = RTC_BUILD_QUALITY_MEDIUM;
};

// A build quality by the name --embree-quality takes (low, high; medium otherwise).
inline RTCBuildQuality embree_quality_of(const std::string& name) {
  return name == "low" ? RTC_BUILD_QUALITY_LOW : name == "high" ? RTC_BUILD_QUALITY_HIGH : RTC_BUILD_QUALITY_MEDIUM;
}

class EmbreeBench {
 public:
  // Triangles are geometry 0, spheres geometry 1, declared instance d geometry kFirstInstance + d
  // (each mesh its own committed scene, as ours is its own BVH). The device gets `threads` build
  // threads so its pool does not oversubscribe the machine.
  // mode.robust: every scene gets RTC_SCENE_FLAG_ROBUST (Embree's mode that avoids optimizations
  // which lose accuracy, its nearest to our watertight test and conservative boxes); every scene
  // is built at mode.quality.
  EmbreeBench(const Scene& s, int threads, EmbreeMode mode = {}) : mode_(mode) {
    const std::string config = "threads=" + std::to_string(threads);
    device_ = rtcNewDevice(config.c_str());
    if (!device_) {
      std::fprintf(stderr, "frameless: embree: rtcNewDevice failed\n");
      std::exit(1);
    }
    rtcSetDeviceMemoryMonitorFunction(device_, &EmbreeBench::monitor, this);
    scene_ = new_scene(device_, s.geometry, &mesh_scenes_, mode);
    rtcCommitScene(scene_);  // its build is timed apart (build_ms_with_threads), before this device exists
  }
  ~EmbreeBench() {
    rtcReleaseScene(scene_);
    for (RTCScene m : mesh_scenes_) rtcReleaseScene(m);
    rtcReleaseDevice(device_);
  }
  EmbreeBench(const EmbreeBench&) = delete;
  EmbreeBench& operator=(const EmbreeBench&) = delete;

  void intersect1(const Ray* rays, EmbreeHit* hits, size_t n) const {
    RTCIntersectContext ctx;
    rtcInitIntersectContext(&ctx);
    for (size_t i = 0; i < n; ++i) {
      RTCRayHit rh;
      set_ray(rh.ray, rays[i]);
      rh.hit.geomID = RTC_INVALID_GEOMETRY_ID;
      rtcIntersect1(scene_, &ctx, &rh);
      hits[i] = {rh.ray.tfar, rh.hit.geomID, rh.hit.primID, instance_of(rh.hit.instID[0])};
    }
  }

  void intersect8(const Ray* rays, EmbreeHit* hits, size_t n) const {
    RTCIntersectContext ctx;
    rtcInitIntersectContext(&ctx);
    ctx.flags = RTC_INTERSECT_CONTEXT_FLAG_COHERENT;  // consecutive primary rays
    for (size_t b = 0; b < n; b += 8) {
      alignas(32) RTCRayHit8 rh;
      alignas(32) int valid[8];
      for (int k = 0; k < 8; ++k) {
        const Ray& r = rays[std::min(b + k, n - 1)];
        valid[k] = b + k < n ? -1 : 0;
        rh.ray.org_x[k] = r.org.x, rh.ray.org_y[k] = r.org.y, rh.ray.org_z[k] = r.org.z;
        rh.ray.dir_x[k] = r.dir.x, rh.ray.dir_y[k] = r.dir.y, rh.ray.dir_z[k] = r.dir.z;
        rh.ray.tnear[k] = r.tmin, rh.ray.tfar[k] = r.tmax, rh.ray.time[k] = 0.0f;
        rh.ray.mask[k] = ~0u, rh.ray.id[k] = unsigned(k), rh.ray.flags[k] = 0;
        rh.hit.geomID[k] = RTC_INVALID_GEOMETRY_ID;
      }
      rtcIntersect8(valid, scene_, &ctx, &rh);
      for (int k = 0; k < 8 && b + k < n; ++k)
        hits[b + k] = {rh.ray.tfar[k], rh.hit.geomID[k], rh.hit.primID[k], instance_of(rh.hit.instID[0][k])};
    }
  }

  void occluded1(const Ray* rays, uint8_t* occ, size_t n) const {
    RTCIntersectContext ctx;
    rtcInitIntersectContext(&ctx);
    for (size_t i = 0; i < n; ++i) {
      RTCRay r;
      set_ray(r, rays[i]);
      rtcOccluded1(scene_, &ctx, &r);
      occ[i] = r.tfar < 0.0f;  // Embree sets tfar = -inf on a hit
    }
  }

  void occluded8(const Ray* rays, uint8_t* occ, size_t n) const {
    RTCIntersectContext ctx;
    rtcInitIntersectContext(&ctx);
    for (size_t b = 0; b < n; b += 8) {
      alignas(32) RTCRay8 r;
      alignas(32) int valid[8];
      for (int k = 0; k < 8; ++k) {
        const Ray& s = rays[std::min(b + k, n - 1)];
        valid[k] = b + k < n ? -1 : 0;
        r.org_x[k] = s.org.x, r.org_y[k] = s.org.y, r.org_z[k] = s.org.z;
        r.dir_x[k] = s.dir.x, r.dir_y[k] = s.dir.y, r.dir_z[k] = s.dir.z;
        r.tnear[k] = s.tmin, r.tfar[k] = s.tmax, r.time[k] = 0.0f;
        r.mask[k] = ~0u, r.id[k] = unsigned(k), r.flags[k] = 0;
      }
      rtcOccluded8(valid, scene_, &ctx, &r);
      for (int k = 0; k < 8 && b + k < n; ++k) occ[b + k] = r.tfar[k] < 0.0f;
    }
  }

  // Our primitive id convention for an Embree hit on g (within its mesh for an instance's).
  static uint32_t prim_id(const EmbreeHit& h, const Geometry& g) {
    const Geometry& hit_geometry =
        h.inst == RTC_INVALID_GEOMETRY_ID ? g : g.instance_meshes[g.instances[h.inst].mesh]->geometry;
    return h.geom == 0 ? h.prim : hit_geometry.num_triangles() + h.prim;
  }
  // Best of `reps` builds (rtcCommitScene of a fresh scene each time) on a device with `threads`
  // build threads (1: Embree builds on the calling thread alone), in ms; the mode as the constructor's.
  static double build_ms_with_threads(const Scene& s, int threads, int reps, EmbreeMode mode = {}) {
    BuildTimer timer(threads, mode);
    double best = 1e30;
    for (int r = 0; r < reps; ++r) best = std::min(best, timer.build_ms(s.geometry));
    return best;
  }

  // CPU time of the process (all its threads), in ms.
  static double process_cpu_ms() {
    timespec t;
    clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &t);
    return double(t.tv_sec) * 1e3 + double(t.tv_nsec) * 1e-6;
  }

  // One device kept for repeated timed builds, so a caller can interleave them with its own.
  class BuildTimer {
   public:
    explicit BuildTimer(int threads, EmbreeMode mode = {}) : mode_(mode) {
      const std::string config = "threads=" + std::to_string(threads);
      device_ = rtcNewDevice(config.c_str());
      if (!device_) {
        std::fprintf(stderr, "frameless: embree: rtcNewDevice failed\n");
        std::exit(1);
      }
    }
    ~BuildTimer() { rtcReleaseDevice(device_); }
    BuildTimer(const BuildTimer&) = delete;
    BuildTimer& operator=(const BuildTimer&) = delete;
    // Milliseconds of rtcCommitScene over a fresh scene of g (buffers filled, and the scenes of
    // instanced meshes built, before the clock: like Accel::build, it times the flat geometry
    // and the instances' top level); cpu_ms, when given, gets the CPU time the whole process
    // spent meanwhile.
    double build_ms(const Geometry& g, double* cpu_ms = nullptr) {
      std::vector<RTCScene> meshes;
      RTCScene scene = new_scene(device_, g, &meshes, mode_);
      const double cpu_start = process_cpu_ms();
      const auto start = std::chrono::steady_clock::now();
      rtcCommitScene(scene);
      const double ms = std::chrono::duration<double, std::milli>(
                            std::chrono::steady_clock::now() - start).count();
      if (cpu_ms) *cpu_ms = process_cpu_ms() - cpu_start;
      rtcReleaseScene(scene);
      for (RTCScene m : meshes) rtcReleaseScene(m);
      return ms;
    }

   private:
    EmbreeMode mode_;
    RTCDevice device_ = nullptr;
  };
  size_t bytes() const { return size_t(std::max<long long>(0, bytes_.load())); }
  bool robust() const { return mode_.robust; }
  std::string version() const {
    return std::to_string(rtcGetDeviceProperty(device_, RTC_DEVICE_PROPERTY_VERSION_MAJOR)) + "." +
           std::to_string(rtcGetDeviceProperty(device_, RTC_DEVICE_PROPERTY_VERSION_MINOR)) + "." +
           std::to_string(rtcGetDeviceProperty(device_, RTC_DEVICE_PROPERTY_VERSION_PATCH));
  }

 private:
  static constexpr unsigned kFirstInstance = 2;
  static unsigned instance_of(unsigned inst_id) {
    return inst_id == RTC_INVALID_GEOMETRY_ID ? inst_id : inst_id - kFirstInstance;
  }

  // A scene holding g's triangles (geometry 0) and spheres (geometry 1), not yet committed; with
  // `meshes`, g's instances too (geometry kFirstInstance + d), over mesh scenes committed here and
  // appended to *meshes (the caller releases them).
  static RTCScene new_scene(RTCDevice device, const Geometry& g, std::vector<RTCScene>* meshes = nullptr,
                            EmbreeMode mode = {}) {
    RTCScene scene = flat_scene(device, g, mode);
    if (!meshes || g.instances.empty()) return scene;
    const size_t first = meshes->size();
    for (const auto& mesh : g.instance_meshes) {
      meshes->push_back(flat_scene(device, mesh->geometry, mode));
      rtcCommitScene(meshes->back());
    }
    for (size_t d = 0; d < g.instances.size(); ++d) {
      const Instance& in = g.instances[d];
      RTCGeometry geo = rtcNewGeometry(device, RTC_GEOMETRY_TYPE_INSTANCE);
      rtcSetGeometryInstancedScene(geo, (*meshes)[first + in.mesh]);
      float xfm[12];  // columns of m, then t
      for (int c = 0; c < 3; ++c)
        for (int r = 0; r < 3; ++r) xfm[3 * c + r] = in.to_world.m[c][r];
      for (int r = 0; r < 3; ++r) xfm[9 + r] = in.to_world.t[r];
      rtcSetGeometryTransform(geo, 0, RTC_FORMAT_FLOAT3X4_COLUMN_MAJOR, xfm);
      rtcCommitGeometry(geo);
      rtcAttachGeometryByID(scene, geo, kFirstInstance + unsigned(d));
      rtcReleaseGeometry(geo);
    }
    return scene;
  }
  // A scene holding g's triangles (geometry 0) and spheres (geometry 1), not yet committed.
  static RTCScene flat_scene(RTCDevice device, const Geometry& g, EmbreeMode mode = {}) {
    RTCScene scene = rtcNewScene(device);
    if (mode.robust) rtcSetSceneFlags(scene, RTC_SCENE_FLAG_ROBUST);
    rtcSetSceneBuildQuality(scene, mode.quality);
    RTCGeometry tri = rtcNewGeometry(device, RTC_GEOMETRY_TYPE_TRIANGLE);
    float* v = static_cast<float*>(rtcSetNewGeometryBuffer(
        tri, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3, 3 * sizeof(float), g.positions.size()));
    for (size_t i = 0; i < g.positions.size(); ++i)
      for (int k = 0; k < 3; ++k) v[3 * i + k] = g.positions[i][k];
    unsigned* idx = static_cast<unsigned*>(rtcSetNewGeometryBuffer(
        tri, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3, 3 * sizeof(unsigned), g.triangles.size()));
    for (size_t i = 0; i < g.triangles.size(); ++i)
      for (int k = 0; k < 3; ++k) idx[3 * i + k] = g.triangles[i][k];
    rtcCommitGeometry(tri);
    rtcAttachGeometryByID(scene, tri, 0);
    rtcReleaseGeometry(tri);
    if (!g.spheres.empty()) {
      RTCGeometry sph = rtcNewGeometry(device, RTC_GEOMETRY_TYPE_SPHERE_POINT);
      float* p = static_cast<float*>(rtcSetNewGeometryBuffer(
          sph, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT4, 4 * sizeof(float), g.spheres.size()));
      for (size_t i = 0; i < g.spheres.size(); ++i) {
        for (int k = 0; k < 3; ++k) p[4 * i + k] = g.spheres[i].center[k];
        p[4 * i + 3] = g.spheres[i].radius;
      }
      rtcCommitGeometry(sph);
      rtcAttachGeometryByID(scene, sph, 1);
      rtcReleaseGeometry(sph);
    }
    return scene;
  }
  static bool monitor(void* self, ssize_t bytes, bool) {
    static_cast<EmbreeBench*>(self)->bytes_ += bytes;
    return true;
  }
  static void set_ray(RTCRay& out, const Ray& r) {
    out.org_x = r.org.x, out.org_y = r.org.y, out.org_z = r.org.z;
    out.dir_x = r.dir.x, out.dir_y = r.dir.y, out.dir_z = r.dir.z;
    out.tnear = r.tmin, out.tfar = r.tmax, out.time = 0.0f;
    out.mask = ~0u, out.id = 0, out.flags = 0;
  }

  EmbreeMode mode_;
  RTCDevice device_ = nullptr;
  RTCScene scene_ = nullptr;
  std::vector<RTCScene> mesh_scenes_;  // instanced meshes' scenes
  std::atomic<long long> bytes_{0};
};

}  // namespace frameless::bench
