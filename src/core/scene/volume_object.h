// Volumes placed in a scene (issue 27): a grid with its macrocells, what the renderer makes of it
// (Parker's isosurfaces, OpenRT's volume shader, maximum intensity projection), and where it sits.
// Built on the loading thread; read-only while rendering (any thread).
#pragma once
#include <memory>
#include <string>
#include <vector>

#include "core/geometry/geometry.h"
#include "core/volume/macrocells.h"
#include "core/volume/transfer_function.h"
#include "core/volume/volume_march.h"

namespace frameless {

enum class VolumeMode : uint8_t {
  kIsosurface,  // surfaces where the interpolant crosses each isovalue, shaded by their materials
  kDirect,      // emission-absorption through a transfer function (OpenRT's volume shader)
  kMip,         // maximum intensity projection through the transfer function
};
const char* volume_mode_name(VolumeMode mode);

// Isosurface hits carry prim = kVolumePrimBase + volume * kMaxIsovalues + isovalue index.
inline constexpr uint32_t kVolumePrimBase = 0xb0000000u;
inline constexpr uint32_t kMaxIsovalues = 16;
inline bool is_volume_prim(uint32_t prim) { return prim >= kVolumePrimBase && prim < 0xc0000000u; }

// Adaptive sampling's threshold: macrocells whose largest opacity per voxel is below it are
// sampled every kThinStretches steps (docs/volumes.md gives its error).
inline constexpr float kAdaptiveOpacity = 0.02f;

struct VolumeObject {
  std::string source;  // file name or built-in generator, for messages
  std::shared_ptr<const VolumeGrid> grid;
  std::shared_ptr<const Macrocells> cells;
  VolumeMode mode = VolumeMode::kIsosurface;
  std::vector<float> isovalues;          // kIsosurface: each a surface of its own
  std::vector<uint16_t> iso_materials;   // one per isovalue
  bool inside_above = true;              // the inside holds values above the isovalue (densities)
  std::shared_ptr<const TransferFunction> tf;  // kDirect, kMip
  std::vector<float> cell_opacity;       // the transfer function's largest opacity per macrocell
  std::vector<float> step_opacity;       // its opacities per step (TransferFunction::step_opacity)
  float step = 0.5f;                     // voxels between the volume shader's samples
  bool shade = true;                     // kDirect: light samples by their gradient
  bool adaptive = true;                  // kDirect: thin samples in nearly transparent macrocells
  Affine to_world;                       // grid index space -> world
  Affine to_index;                       // world -> grid index space
  glm::mat3 normal_to_world{1.0f};       // gradients (index space) -> world normals
  Vec3 lo{0.0f}, hi{0.0f};               // world bounds
  float scale = 1.0f;                    // largest world coordinate magnitude of the bounds

  MarchSetup march() const {
    return MarchSetup{grid.get(), cells.get(), &cell_opacity, tf.get(), step, step_opacity.empty() ? nullptr : &step_opacity,
                      adaptive ? kAdaptiveOpacity : 0.0f};
  }
  // Sets the transfer function and what is derived from it (needs the macrocells).
  void set_transfer(std::shared_ptr<const TransferFunction> f);
};

// Places the grid: world = transform (object space: voxel (i, j, k) at (i, j, k) * spacing),
// and fills the derived fields (macrocells, per-macrocell opacity, bounds).
void place_volume(VolumeObject& v, const Affine& transform);

}  // namespace frameless
