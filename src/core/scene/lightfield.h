// Lightfield objects (issue 28; Levoy and Hanrahan 1996, the light slab): a box in the scene whose
// inside shows radiance stored in a 4-D table L(u, v, s, t). The slab's own frame is the box
// [-1, 1]^3: the uv plane is its front face z = +1, the st plane its middle z = 0, and the table
// holds the light travelling along each line from (u, v, 1) through (s, t, 0), i.e. towards -z,
// premultiplied by its coverage alpha (0 where the line misses the baked model). Built on the
// loading thread, read-only while rendering (any thread).
#pragma once
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "core/geometry/geometry.h"

namespace frameless {

struct Vec4Color {
  Vec3 rgb{0.0f};  // premultiplied by alpha
  float alpha = 0.0f;
};

// The table: nu x nv views of ns x nt texels each, RGBA as IEEE half floats, laid out as the
// file's mosaic (docs/lightfields.md): view (i, j) is the tile at column i, row nv - 1 - j, and
// texel (s, t) of a view sits at column s, row nt - 1 - t of its tile (views look upright).
struct LightField {
  uint32_t nu = 0, nv = 0, ns = 0, nt = 0;
  std::vector<uint16_t> rgba;  // (nu ns) x (nv nt) pixels, 4 halves each
  Affine slab_to_model;        // the slab's frame [-1, 1]^3 in the baked model's coordinates
  std::string source;          // file or what baked it, for messages

  uint32_t width() const { return nu * ns; }
  uint32_t height() const { return nv * nt; }
  size_t bytes() const { return rgba.size() * sizeof(uint16_t); }
  size_t texel_offset(uint32_t i, uint32_t j, uint32_t s, uint32_t t) const {
    const size_t x = size_t(i) * ns + s, y = size_t(nv - 1 - j) * nt + (nt - 1 - t);
    return (y * width() + x) * 4;
  }
  // Slab coordinates of node (i, j) / (s, t): cell centres of the [-1, 1] range.
  float u_of(uint32_t i) const { return (2.0f * float(i) + 1.0f) / float(nu) - 1.0f; }
  float v_of(uint32_t j) const { return (2.0f * float(j) + 1.0f) / float(nv) - 1.0f; }
  float s_of(uint32_t s) const { return (2.0f * float(s) + 1.0f) / float(ns) - 1.0f; }
  float t_of(uint32_t t) const { return (2.0f * float(t) + 1.0f) / float(nt) - 1.0f; }

  // Quadrilinear interpolation between the 16 nodes around (u, v, s, t), each in [-1, 1]
  // (clamped to the outermost nodes within the range); outside the range: nothing (alpha 0).
  Vec4Color lookup(float u, float v, float s, float t) const;
  // The texel as stored.
  Vec4Color texel(uint32_t i, uint32_t j, uint32_t s, uint32_t t) const;
};

// Checks a table's sizes and values (finite, alpha in [0, 1], colour >= 0); returns "" or what is
// wrong, for one-line errors.
std::string check_lightfield(const LightField& lf);

// A lightfield placed in a scene: world = transform * slab_to_model.
struct LightfieldObject {
  std::shared_ptr<const LightField> table;
  Affine to_world;  // slab frame -> world
  Affine to_slab;   // world -> slab frame
  Vec3 lo{0.0f}, hi{0.0f};  // world bounds of the box
};
LightfieldObject place_lightfield(std::shared_ptr<const LightField> table, const Affine& transform);

// Where a ray meets a lightfield: the box entry's ray parameter and what the slab shows there.
struct LightfieldHit {
  float t = 0.0f;
  Vec4Color color;
};

// What `object` shows along `ray` when its box is entered within [ray.tmin, t_end): false when
// the ray misses the box, starts inside it, travels away from the st plane (the slab stores one
// direction) or passes outside the slab's range.
bool lightfield_along(const LightfieldObject& object, const Ray& ray, float t_end, LightfieldHit& hit);

}  // namespace frameless
