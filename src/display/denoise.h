// The display's denoiser for light that bounces: an edge-avoiding a-trous wavelet filter
// (Dammertz, Sewtz, Hanika and Lensch 2010) with SVGF's variance-guided luminance weights
// (Schied et al. 2017), on the shown image only. Albedo is divided out first and multiplied
// back, so textures stay sharp; normals, positions and the pixels' own variance stop it at edges.
// Display or consumer thread; allocation-free once its buffers have grown.
#pragma once
#include <cstdint>
#include <vector>

#include "display/display_image.h"
#include "frameless/pixel_points.h"

namespace frameless {

struct DenoiseBuffers {
  std::vector<float> a, b;          // illumination ping-pong, 3 floats per pixel
  std::vector<float> var, var2;     // variance of each pixel's shown luminance
  std::vector<float> footprint;     // world distance to the nearest neighbour on its surface
  std::vector<Vec3> normal, albedo;
};

// The luminance weights need each pixel's variance (EngineConfig::track_variance); without it only
// normals and positions stop the filter.
// Filters img.rgb in place with `iterations` a-trous passes (steps 1, 2, 4, ...), guided by one
// PointGuide per pixel (pixel order). Pixels that show the sky or nothing are left as they are
// and guide nothing.
void denoise_image(DisplayImage& img, const std::vector<PointGuide>& guides, int iterations,
                   DenoiseBuffers& buffers);

}  // namespace frameless
