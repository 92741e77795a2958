// The viewer's controls, typed and by name (viewer_controls.h).
#include "viewer/viewer_controls.h"

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <memory>

#include "core/scene/scene_finalize.h"
#include "display/manifest.h"
#include "display/camera_path.h"
#include "frameless/engine_config.h"

namespace frameless {
namespace {

bool parse_shadow_mode(const std::string& name, ShadowMode& out) {
  for (ShadowMode m : {ShadowMode::kHard, ShadowMode::kSoft, ShadowMode::kArea, ShadowMode::kBeam})
    if (name == shadow_mode_name(m)) return out = m, true;
  return false;
}

// A control's values as numbers: exactly `count` finite floats, else an error naming the control.
Result<std::vector<float>> numbers(const std::string& name, const std::vector<std::string>& values, size_t count) {
  if (values.size() != count)
    return Error{name + ": expected " + std::to_string(count) + (count == 1 ? " number" : " numbers")};
  std::vector<float> out;
  for (const std::string& s : values) {
    char* end = nullptr;
    const float f = std::strtof(s.c_str(), &end);
    if (end == s.c_str() || *end || !std::isfinite(f)) return Error{name + ": '" + s + "' is not a number"};
    out.push_back(f);
  }
  return out;
}

Result<bool> on_off(const std::string& name, const std::vector<std::string>& values, bool& out) {
  if (values.size() == 1 && (values[0] == "on" || values[0] == "1")) return out = true, true;
  if (values.size() == 1 && (values[0] == "off" || values[0] == "0")) return out = false, true;
  return Error{name + ": expected on or off"};
}

// "light3.color" -> ("light", 3, "color"); false when the name has no index.
bool indexed(const std::string& name, std::string& kind, size_t& index, std::string& field) {
  const size_t dot = name.find('.');
  size_t digits = 0;
  while (digits < name.size() && !std::isdigit((unsigned char)name[digits])) ++digits;
  if (dot == std::string::npos || digits == 0 || digits >= dot) return false;
  kind = name.substr(0, digits);
  char* end = nullptr;
  const unsigned long i = std::strtoul(name.c_str() + digits, &end, 10);
  if (end != name.c_str() + dot) return false;
  index = size_t(i), field = name.substr(dot + 1);
  return true;
}

Vec3 vec(const std::vector<float>& f) { return Vec3(f[0], f[1], f[2]); }

// A world edit's refusal under the control's name ("light0.color: light 0: colour must be ...").
Result<bool> named(const std::string& name, Result<bool> r) {
  if (!r.ok()) return Error{name + ": " + r.error().message};
  return true;
}

// "NAME: the scene has 1 light" / "... 3 lights".
Error too_few(const std::string& name, size_t n, const char* what) {
  return Error{name + ": the scene has " + std::to_string(n) + " " + what + (n == 1 ? "" : "s")};
}

Result<bool> apply_display(Viewer& v, const std::string& name, const std::vector<std::string>& values) {
  bool flag = false;
  if (name == "alpha" || name == "refresh") {
    auto f = numbers(name, values, 1);
    if (!f.ok()) return f.error();
    const float x = f.value()[0];
    if (name == "alpha" && !(x > 0.0f && x <= 1.0f)) return Error{"alpha: must be in (0, 1]"};
    if (name == "refresh" && !(x >= 1.0f && x <= 240.0f)) return Error{"refresh: must be 1..240 Hz"};
    v.change_display([&](DisplayConfig& c) { name == "alpha" ? void(c.blend.alpha = x) : void(c.refresh_hz = x); });
    return true;
  }
  if (auto r = on_off(name, values, flag); !r.ok()) return r.error();
  v.change_display([&](DisplayConfig& c) {
    (name == "reproject" ? c.blend.reproject : name == "temporal" ? c.blend.temporal : c.blend.denoise) = flag;
  });
  return true;
}

Result<bool> apply_camera(Viewer& v, const std::string& field, const std::vector<std::string>& values) {
  const std::string name = "camera." + field;
  Camera c = v.camera;
  if (field == "fov") {
    auto f = numbers(name, values, 1);
    if (!f.ok()) return f.error();
    c.fov_deg = f.value()[0];
  } else if (field == "eye" || field == "look" || field == "up") {
    auto f = numbers(name, values, 3);
    if (!f.ok()) return f.error();
    (field == "eye" ? c.eye : field == "look" ? c.look : c.up) = vec(f.value());
  } else if (field == "save" || field == "load") {
    if (values.size() != 1) return Error{name + ": expected a file name"};
    if (field == "save") {
      if (auto r = write_text_file_atomic(values[0], camera_path_to_json(v.recording, "frameless view")); !r.ok())
        return r.error();
      v.status = "saved " + std::to_string(v.recording.keyframes.size()) + " camera poses to " + values[0];
      return true;
    }
    auto p = load_camera_path(values[0]);
    if (!p.ok()) return p.error();
    if (p.value().keyframes.empty()) return Error{values[0] + ": keyframes: empty"};
    v.playing = p.value(), v.playing_since = v.now();
    v.status = "playing " + values[0];
    return true;
  } else {
    return Error{name + ": unknown camera field (eye, look, up, fov, save, load)"};
  }
  if (!camera_is_valid(c)) return Error{name + ": the camera would be degenerate"};
  v.set_camera(c);
  return true;
}

Result<bool> apply_world(Viewer& v, const std::string& name, const std::string& kind, size_t i,
                         const std::string& field, const std::vector<std::string>& values) {
  const bool vector_field = field != "radius" && field != "phong" && field != "isovalue";
  auto f = numbers(name, values, vector_field ? 3 : 1);
  if (kind == "light") {
    if (i >= v.world.lights.size()) return too_few(name, v.world.lights.size(), "light");
    if (!f.ok()) return f.error();
    Light l = v.world.lights[i];
    if (field == "position") l.position = vec(f.value());
    else if (field == "color") l.color = vec(f.value());
    else if (field == "radius") l.radius = f.value()[0];
    else return Error{name + ": unknown light field (position, color, radius)"};
    return named(name, set_light(v, i, l));
  } else if (kind == "material") {
    if (i >= v.world.materials.size()) return too_few(name, v.world.materials.size(), "material");
    if (!f.ok()) return f.error();
    MaterialParams m = v.world.materials[i];
    if (field == "kd") m.kd = vec(f.value());
    else if (field == "ks") m.ks = vec(f.value());
    else if (field == "kh") m.kh = vec(f.value());
    else if (field == "emission") m.emission = vec(f.value());
    else if (field == "phong") m.phong_exponent = f.value()[0];
    else return Error{name + ": unknown material field (kd, ks, kh, phong, emission)"};
    return named(name, set_material(v, i, m));
  } else if (kind == "object") {
    if (i >= v.world.object_position.size()) return too_few(name, v.world.object_position.size(), "moving object");
    if (field != "position") return Error{name + ": unknown object field (position)"};
    if (!f.ok()) return f.error();
    return named(name, set_object_position(v, i, vec(f.value())));
  } else if (kind == "instance") {
    if (i >= v.scene->geometry.instances.size()) return too_few(name, v.scene->geometry.instances.size(), "instance");
    if (field != "translation") return Error{name + ": unknown instance field (translation)"};
    if (!f.ok()) return f.error();
    v.set_instance_translation(uint32_t(i), vec(f.value()));
  } else if (kind == "volume") {
    if (i >= v.scene->volumes.size()) return too_few(name, v.scene->volumes.size(), "volume");
    if (field == "isovalue") {
      if (!f.ok()) return f.error();
      if (v.scene->volumes[i].mode != VolumeMode::kIsosurface) return Error{name + ": volume " + std::to_string(i) + " is not an isosurface"};
      set_isovalue(v, i, f.value()[0]);
    } else if (field == "preset") {
      if (values.size() != 1) return Error{name + ": expected a preset name"};
      return set_transfer_preset(v, i, values[0]);
    } else if (field == "points") {
      if (values.empty() || values.size() % 5) return Error{name + ": expected VALUE R G B OPACITY per point"};
      auto all = numbers(name, values, values.size());
      if (!all.ok()) return all.error();
      std::vector<TransferPoint> points;
      for (size_t k = 0; k < values.size(); k += 5) {
        const float* p = all.value().data() + k;
        points.push_back({p[0], Vec3(p[1], p[2], p[3]), p[4]});
      }
      return set_transfer(v, i, points);
    } else {
      return Error{name + ": unknown volume field (isovalue, preset, points)"};
    }
  } else {
    return Error{name + ": unknown control"};
  }
  return true;
}

}  // namespace

void set_integrator(Viewer& v, Integrator integrator) {
  v.rebuild(std::string("integrator ") + integrator_name(integrator), [integrator](Scene& s, EngineConfig&) { s.settings.integrator = integrator; });
}

void set_shadows(Viewer& v, ShadowMode mode) {
  v.rebuild(std::string("shadows ") + shadow_mode_name(mode), [mode](Scene& s, EngineConfig&) {
    set_shadow_settings(s, mode, s.settings.shadow_samples, s.settings.transparent_shadows);
  });
}

void set_accel(Viewer& v, AccelKind kind) {
  v.rebuild(std::string("acceleration ") + accel_kind_name(kind), [kind](Scene& s, EngineConfig&) { frameless::set_accel(s, kind); });
}

void set_closed_loop(Viewer& v, bool on) {
  v.rebuild(on ? "closed loop on" : "closed loop off", [on](Scene&, EngineConfig& c) { c.closed_loop = on; });
}

Result<bool> set_light(Viewer& v, size_t index, const Light& light) {
  v.world.lights[index] = light;
  return v.publish_world();
}

Result<bool> set_material(Viewer& v, size_t index, const MaterialParams& material) {
  v.world.materials[index] = material;
  return v.publish_world();
}

Result<bool> set_object_position(Viewer& v, size_t index, const Vec3& position) {
  v.world.object_position[index] = position;
  return v.publish_world();
}

void set_isovalue(Viewer& v, size_t volume, float isovalue) {
  v.edit_volumes([volume, isovalue](Scene& s) {
    VolumeObject& vol = s.volumes[volume];
    const float iso = std::clamp(isovalue, vol.grid->min_value, vol.grid->max_value);
    for (float& x : vol.isovalues) x = iso;
    char line[120];
    std::snprintf(line, sizeof line, "volume %zu: isovalue %g", volume, double(iso));
    return std::string(line);
  });
}

Result<bool> set_transfer(Viewer& v, size_t volume, const std::vector<TransferPoint>& points) {
  auto tf = TransferFunction::make(points, "volume" + std::to_string(volume) + ".points");
  if (!tf.ok()) return tf.error();
  auto shared = std::make_shared<const TransferFunction>(std::move(tf.value()));
  v.edit_volumes([volume, shared](Scene& s) {
    s.volumes[volume].set_transfer(shared);
    return "volume " + std::to_string(volume) + ": transfer function of " +
           std::to_string(shared->points().size()) + " points";
  });
  return true;
}

Result<bool> set_transfer_preset(Viewer& v, size_t volume, const std::string& preset) {
  const VolumeGrid& g = *v.scene->volumes[volume].grid;
  auto tf = TransferFunction::preset(preset, g.min_value, g.max_value, "volume" + std::to_string(volume) + ".preset");
  if (!tf.ok()) return tf.error();
  auto shared = std::make_shared<const TransferFunction>(std::move(tf.value()));
  v.edit_volumes([volume, shared, preset](Scene& s) {
    s.volumes[volume].set_transfer(shared);
    return "volume " + std::to_string(volume) + ": transfer function " + preset;
  });
  return true;
}

Result<bool> apply_control(Viewer& v, const std::string& name, const std::vector<std::string>& values) {
  const std::string one = values.size() == 1 ? values[0] : "";
  const bool fixed = v.opt.fixed_layout;
  if (name == "alpha" || name == "refresh" || name == "reproject" || name == "temporal" || name == "denoise") {
    if (fixed && name == "reproject") return Error{"reproject: fixed on the cluster master"};
    return apply_display(v, name, values);
  }
  if (name == "mode" || name == "threads" || name == "update") {
    if (fixed) return Error{name + ": fixed on the cluster master"};
    if (name == "mode") {
      auto m = parse_render_mode(one);
      if (!m) return Error{"mode: expected frameless or conventional"};
      v.engine->set_mode(*m);
    } else {
      auto f = numbers(name, values, 1);
      if (!f.ok()) return f.error();
      const float x = f.value()[0];
      if (name == "threads" && !(x >= 1 && x <= 256 && x == std::floor(x))) return Error{"threads: must be 1..256"};
      if (name == "update" && !(x >= 0.01f && x <= 100.0f)) return Error{"update: must be 0.01..100 (%)"};
      name == "threads" ? v.engine->set_threads(int(x)) : v.engine->set_update_percent(x);
    }
  } else if (name == "integrator") {
    Integrator i;
    if (!parse_integrator(one, i)) return Error{"integrator: expected whitted, path or igi"};
    if (!v.may_rebuild()) return Error{v.status};
    set_integrator(v, i);
  } else if (name == "shadows") {
    ShadowMode m;
    if (!parse_shadow_mode(one, m)) return Error{"shadows: expected hard, soft, area or beam"};
    if (!v.may_rebuild()) return Error{v.status};
    set_shadows(v, m);
  } else if (name == "accel") {
    AccelKind k;
    if (!parse_accel_kind(one, k)) return Error{"accel: expected bvh, grid or auto"};
    if (!v.may_rebuild()) return Error{v.status};
    set_accel(v, k);
  } else if (name == "closed_loop") {
    bool on = false;
    if (auto r = on_off(name, values, on); !r.ok()) return r.error();
    if (!v.may_rebuild()) return Error{v.status};
    set_closed_loop(v, on);
  } else if (name == "view") {
    if (!parse_view(one, v.view)) return Error{"view: expected shaded, age, count, variance, epoch or levels"};
  } else if (name == "capture") {
    bool on = false;
    if (auto r = on_off(name, values, on); !r.ok()) return r.error();
    on ? v.start_capture() : v.stop_capture();
  } else if (name == "save") {
    if (one != "exr" && one != "png") return Error{"save: expected exr or png"};
    v.save_image(one);
  } else if (name == "reference") {
    auto f = numbers(name, values, 1);
    if (!f.ok()) return f.error();
    if (!(f.value()[0] >= 2 && f.value()[0] <= 256)) return Error{"reference: samples per pixel must be 2..256 (a restart waits for it)"};
    v.request_reference(int(f.value()[0]));
  } else if (name.rfind("camera.", 0) == 0) {
    return apply_camera(v, name.substr(7), values);
  } else {
    std::string kind, field;
    size_t index = 0;
    if (!indexed(name, kind, index, field)) return Error{name + ": unknown control"};
    if (kind == "volume" && !v.may_rebuild()) return Error{v.status};
    return apply_world(v, name, kind, index, field, values);
  }
  v.dirty = true;
  return true;
}

}  // namespace frameless
