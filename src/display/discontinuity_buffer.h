// OpenRT's discontinuity buffer for instant global illumination (Wald, Kollig, Benthin, Keller
// and Slusallek 2002): interleaved sampling gives each pixel of an n x n block a different set of
// virtual point lights, so the indirect light carries an n x n pattern; averaging it over that
// block on the same surface removes the pattern. Display or consumer thread; allocation-free
// once its buffer has grown.
#pragma once
#include <vector>

#include "display/display_image.h"
#include "frameless/pixel_points.h"

namespace frameless {

// Two pixels lie on the same surface when both show a surface with a normal and an albedo, their
// normals are within about 25 degrees (dot >= 0.9), and the step between their points stays near
// the first one's tangent plane (|n . d| <= 0.1 |d|: a crease or a depth jump breaks it).
bool same_surface(const PointGuide& a, const PointGuide& b);

struct DiscontinuityBuffers {
  std::vector<float> fields;  // per pixel: normal, point, indirect light over albedo (arrays)
  std::vector<float> row;     // one row's sums and counts
};

// Replaces each surface pixel's own indirect light (`indirect`: the mean the render threads keep
// for igi, pixel order) by the average over the n x n window around it (every class of the
// interleaving pattern once) of its same-surface neighbours' indirect light divided by their
// albedo, times its own albedo (irradiance is what is smooth; textures stay sharp). Direct light,
// emitters and the sky are not touched.
void filter_discontinuity(DisplayImage& img, const std::vector<PointGuide>& guides,
                          const std::vector<Vec3>& indirect, int n, DiscontinuityBuffers& buffers);

}  // namespace frameless
