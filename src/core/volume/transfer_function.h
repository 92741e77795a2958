// OpenRT's volume shader maps each sample's value to colour and opacity through a transfer
// function: piecewise linear between points sorted by value (JSON points or a named preset over
// the grid's value range). Opacity is per `unit` voxels of path: the volume shader corrects it
// for its actual step, so images do not depend on the sampling rate.
#pragma once
#include <string>
#include <vector>

#include "core/base/error.h"
#include "core/base/types.h"

namespace frameless {

struct TransferPoint {
  float value = 0.0f;
  Vec3 color{1.0f};
  float opacity = 0.0f;  // in [0, 1], per unit voxels
};

class TransferFunction {
 public:
  static constexpr int kTable = 1024;  // entries of the lookup table over [lo, hi]
  // Points sorted by strictly increasing value, at least two, colours finite and non-negative,
  // opacities in [0, 1]; `what` names the field in errors.
  static Result<TransferFunction> make(std::vector<TransferPoint> points, const std::string& what);
  // Presets over [lo, hi] (the grid's range): "ct-bone", "ct-skin", "grayscale", "hot", "cool-warm".
  static Result<TransferFunction> preset(const std::string& name, float lo, float hi, const std::string& what);
  static const char* preset_names();  // "ct-bone, ct-skin, ...": for messages and --help
  static constexpr const char* kPresets[] = {"ct-bone", "ct-skin", "grayscale", "hot", "cool-warm"};
  const std::string& preset() const { return preset_; }  // its preset's name, "" for points

  // The table entry of value v (clamped to the end points).
  int index(float v) const {
    const float x = (v - lo_) * scale_;
    return x <= 0.0f ? 0 : x >= float(kTable - 1) ? kTable - 1 : int(x + 0.5f);
  }
  // Colour and opacity at value v, from the table.
  void lookup(float v, Vec3& color, float& opacity) const {
    const int i = index(v);
    color = color_[size_t(i)];
    opacity = opacity_[size_t(i)];
  }
  const Vec3& color_at(int i) const { return color_[size_t(i)]; }
  float opacity_at(int i) const { return opacity_[size_t(i)]; }
  // Each entry's opacity over a stretch of `step` voxels, 1 - (1 - a)^step: what the volume
  // shader would compute per sample, once per entry.
  std::vector<float> step_opacity(float step) const;
  // The largest opacity over values [a, b] (macrocells holding only transparent values are skipped).
  float max_opacity(float a, float b) const;
  const std::vector<TransferPoint>& points() const { return points_; }

 private:
  std::vector<TransferPoint> points_;
  std::string preset_;
  float lo_ = 0.0f, scale_ = 0.0f;
  std::vector<Vec3> color_;
  std::vector<float> opacity_;
  void exact(float v, Vec3& color, float& opacity) const;  // piecewise linear, not tabulated
};

// Shadow rays' colour through a sample of colour c (a chosen model, stated in docs/volumes.md:
// emission-absorption alone has grey shadows): the sample's optical depth weighted per channel
// by 1.05 - c (c clamped to [0, 1]) over the mean of those weights, so a medium absorbs least
// where its colour is strongest, grey media keep exp(-sigma d) exactly, and the mean optical
// depth over the channels is the grey one.
inline Vec3 shadow_tint(const Vec3& c) {
  const Vec3 w = Vec3(1.05f) - glm::clamp(c, Vec3(0.0f), Vec3(1.0f));
  if (w.x == w.y && w.y == w.z) return Vec3(1.0f);
  return w * (3.0f / (w.x + w.y + w.z));
}

}  // namespace frameless
