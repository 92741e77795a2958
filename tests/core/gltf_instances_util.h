// Renders and their comparison for gltf_instances_test.cpp and gltf_instances_assimp_test.cpp.
#pragma once
#include <cstddef>
#include <vector>

#include "core/scene/camera.h"
#include "core/scene/scene.h"
#include "core/shading/render_sample.h"

namespace frameless {
namespace test_util {

struct Image {
  int w = 48, h = 36;
  std::vector<Vec3> rgb;
};

inline Image render(const Scene& scene) {
  Image img;
  const CameraBasis cam = make_camera_basis(scene.camera, img.w, img.h);
  for (int y = 0; y < img.h; ++y)
    for (int x = 0; x < img.w; ++x)
      img.rgb.push_back(render_sample(scene, cam, x, y, 0, false).color);
  return img;
}

// Pixels whose colours differ by more than `tol` in some channel.
inline size_t differing(const Image& a, const Image& b, float tol) {
  size_t n = 0;
  for (size_t i = 0; i < a.rgb.size(); ++i)
    if (glm::any(glm::greaterThan(glm::abs(a.rgb[i] - b.rgb[i]), Vec3(tol)))) ++n;
  return n;
}

// Rays carried into an instance's space round differently from rays against transformed
// vertices: a silhouette or cut-out edge pixel may flip. Colours agree to kTolerance elsewhere.
inline constexpr float kTolerance = 2e-3f;
inline constexpr size_t kMaxDiffering = 8;  // of 48 x 36 = 1728 pixels

}  // namespace test_util
}  // namespace frameless
