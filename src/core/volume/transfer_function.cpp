// Transfer functions: checks, presets and the lookup table.
#include "core/volume/transfer_function.h"

#include <algorithm>
#include <cmath>

namespace frameless {

Result<TransferFunction> TransferFunction::make(std::vector<TransferPoint> points, const std::string& what) {
  if (points.size() < 2) return Error{what + ": needs at least two points"};
  for (size_t i = 0; i < points.size(); ++i) {
    const TransferPoint& p = points[i];
    const std::string at = what + "[" + std::to_string(i) + "]";
    if (!std::isfinite(p.value)) return Error{at + ": value is not a finite number"};
    if (i > 0 && !(p.value > points[i - 1].value))
      return Error{at + ": values must increase strictly (" + std::to_string(points[i - 1].value) + " then " +
                   std::to_string(p.value) + ")"};
    if (!is_finite(p.color) || std::min({p.color.x, p.color.y, p.color.z}) < 0.0f) return Error{at + ": colour must be finite and non-negative"};
    if (!(p.opacity >= 0.0f && p.opacity <= 1.0f)) return Error{at + ": opacity must be in [0, 1]"};
  }
  TransferFunction f;
  f.points_ = std::move(points);
  f.lo_ = f.points_.front().value;
  const float span = f.points_.back().value - f.lo_;
  f.scale_ = float(kTable - 1) / span;
  f.color_.resize(kTable);
  f.opacity_.resize(kTable);
  for (int i = 0; i < kTable; ++i) f.exact(f.lo_ + span * float(i) / float(kTable - 1), f.color_[size_t(i)], f.opacity_[size_t(i)]);
  return f;
}

void TransferFunction::exact(float v, Vec3& color, float& opacity) const {
  if (v <= points_.front().value) {
    color = points_.front().color;
    opacity = points_.front().opacity;
    return;
  }
  for (size_t i = 1; i < points_.size(); ++i)
    if (v <= points_[i].value) {
      const TransferPoint &a = points_[i - 1], &b = points_[i];
      const float s = (v - a.value) / (b.value - a.value);
      color = a.color + s * (b.color - a.color);
      opacity = a.opacity + s * (b.opacity - a.opacity);
      return;
    }
  color = points_.back().color;
  opacity = points_.back().opacity;
}

std::vector<float> TransferFunction::step_opacity(float step) const {
  std::vector<float> out(opacity_.size());
  for (size_t i = 0; i < out.size(); ++i) out[i] = 1.0f - std::pow(1.0f - std::min(opacity_[i], 0.999999f), step);
  return out;
}

float TransferFunction::max_opacity(float a, float b) const {
  // Piecewise linear: the maximum is at an end or at a point inside. The table rounds values to
  // its nearest entry, so the range grows by one entry on each side.
  const float pad = 1.0f / scale_;
  a -= pad;
  b += pad;
  Vec3 c;
  float oa, ob;
  exact(a, c, oa);
  exact(b, c, ob);
  float m = std::max(oa, ob);
  for (const TransferPoint& p : points_)
    if (p.value > a && p.value < b) m = std::max(m, p.opacity);
  return m;
}

const char* TransferFunction::preset_names() { return "ct-bone, ct-skin, grayscale, hot, cool-warm"; }

Result<TransferFunction> TransferFunction::preset(const std::string& name, float lo, float hi, const std::string& what) {
  if (!(hi > lo)) hi = lo + 1.0f;  // a constant volume: any span will do
  const auto at = [&](float s) { return lo + s * (hi - lo); };
  std::vector<TransferPoint> p;
  if (name == "ct-bone") {  // tissue almost clear, denser spots red, bone ivory and half see-through
    p = {{at(0.0f), Vec3(0.0f), 0.0f},          {at(0.15f), Vec3(0.8f, 0.5f, 0.45f), 0.0f},
         {at(0.2f), Vec3(0.85f, 0.55f, 0.5f), 0.004f}, {at(0.25f), Vec3(0.9f, 0.4f, 0.3f), 0.004f},
         {at(0.3f), Vec3(0.95f, 0.25f, 0.15f), 0.1f}, {at(0.45f), Vec3(0.9f, 0.6f, 0.4f), 0.0f},
         {at(0.7f), Vec3(0.95f, 0.9f, 0.8f), 0.1f}, {at(1.0f), Vec3(1.0f, 0.98f, 0.92f), 0.4f}};
  } else if (name == "ct-skin") {  // the outer surface and little inside
    p = {{at(0.0f), Vec3(0.0f), 0.0f}, {at(0.1f), Vec3(0.9f, 0.7f, 0.6f), 0.0f},
         {at(0.2f), Vec3(0.95f, 0.75f, 0.65f), 0.6f}, {at(1.0f), Vec3(1.0f, 0.9f, 0.85f), 0.8f}};
  } else if (name == "grayscale") {
    p = {{at(0.0f), Vec3(0.0f), 0.0f}, {at(1.0f), Vec3(1.0f), 0.5f}};
  } else if (name == "hot") {
    p = {{at(0.0f), Vec3(0.0f), 0.0f}, {at(0.35f), Vec3(1.0f, 0.0f, 0.0f), 0.1f},
         {at(0.7f), Vec3(1.0f, 1.0f, 0.0f), 0.4f}, {at(1.0f), Vec3(1.0f), 0.8f}};
  } else if (name == "cool-warm") {  // Moreland's diverging map, its ends and middle
    p = {{at(0.0f), Vec3(0.23f, 0.30f, 0.75f), 0.05f}, {at(0.5f), Vec3(0.87f, 0.87f, 0.87f), 0.0f},
         {at(1.0f), Vec3(0.71f, 0.02f, 0.15f), 0.6f}};
  } else {
    return Error{what + ": unknown transfer function preset '" + name + "' (expected " + preset_names() + ")"};
  }
  auto tf = make(std::move(p), what);
  if (tf) tf->preset_ = name;
  return tf;
}

}  // namespace frameless
