// Volume objects of the JSON scene format: the grid's source and the renderer's settings.
#include "core/io/scene_json_volume.h"

#include "core/io/file_util.h"
#include "core/io/volume_nrrd.h"
#include "core/io/volume_raw.h"
#include "core/io/volume_vdb.h"
#include "core/scene/volume_object.h"
#include "core/volume/volume_generators.h"

namespace frameless::scene_json {
namespace {

// A number or [sx, sy, sz], each positive.
Vec3 parse_spacing(const json& sp, const std::string& field) {
  const Vec3 s =
      sp.is_number() ? Vec3(get_float(sp, field, 1e-9, 1e9, "in (0, 1e9]")) : get_vec3(sp, field);
  if (!(s.x > 0.0f && s.y > 0.0f && s.z > 0.0f)) fail(field, "must be positive");
  return s;
}

// Where a grid came from, beside the grid itself.
struct GridSource {
  bool raw = false;        // a raw file: the object gives its layout
  bool vdb = false;        // an OpenVDB file: it gives its own map and class
  Affine native;           // OpenVDB's grid -> world map (identity otherwise)
  std::string grid_class;  // OpenVDB's class: "level set", "fog volume", "unknown"
};

std::shared_ptr<const VolumeGrid> load_grid(const json& o, const std::string& f,
                                            const std::string& base_dir, GridSource& from) {
  const std::string file = get_string(need(o, f, "file"), f + ".file");
  if (o.contains("grid") && file_extension(file) != ".vdb") fail(f + ".grid", "only for OpenVDB files");
  if (is_builtin_volume_name(file)) {
    auto g = make_builtin_volume(file);
    if (!g) fail(f + ".file", g.error().message);
    return *g;
  }
  const std::string full = !file.empty() && file[0] == '/' ? file : base_dir + "/" + file;
  const std::string ext = file_extension(file);
  if (ext == ".vdb") {
    const std::string name = o.contains("grid") ? get_string(o["grid"], f + ".grid") : "";
    auto v = read_vdb(full, name);
    if (!v) fail(f + ".file", v.error().message);
    from.vdb = true;
    from.native = v->grid_to_world();
    from.grid_class = v->grid_class;
    return v->bricked.grid;
  }
  if (ext == ".nrrd" || ext == ".nhdr") {
    auto g = read_nrrd(full);
    if (!g) fail(f + ".file", g.error().message);
    return *g;
  }
  // Raw voxels: the layout comes from the object.
  from.raw = true;
  RawVolumeSpec spec;
  const json& dims = need(o, f, "dims");
  if (!dims.is_array() || dims.size() != 3) fail(f + ".dims", "expected [nx, ny, nz]");
  spec.nx = get_int(dims[0], f + ".dims[0]", 2, kMaxVolumeSide);
  spec.ny = get_int(dims[1], f + ".dims[1]", 2, kMaxVolumeSide);
  spec.nz = get_int(dims[2], f + ".dims[2]", 2, kMaxVolumeSide);
  const std::string format = get_string(need(o, f, "format"), f + ".format");
  if (format == "uint8")
    spec.type = VoxelType::kUint8;
  else if (format == "uint16")
    spec.type = VoxelType::kUint16;
  else if (format == "float32")
    spec.type = VoxelType::kFloat32;
  else
    fail(f + ".format", "expected uint8, uint16 or float32, got '" + format + "'");
  if (o.contains("endian")) {
    const std::string e = get_string(o["endian"], f + ".endian");
    if (e != "little" && e != "big") fail(f + ".endian", "expected little or big, got '" + e + "'");
    spec.big_endian = e == "big";
  }
  if (o.contains("spacing")) spec.spacing = parse_spacing(o["spacing"], f + ".spacing");
  if (o.contains("offset"))
    spec.offset = uint64_t(get_int(o["offset"], f + ".offset", 0, int64_t(1) << 40));
  auto g = read_raw_volume(full, spec);
  if (!g) fail(f + ".file", g.error().message);
  return *g;
}

std::shared_ptr<const TransferFunction> parse_transfer(const json& o, const std::string& f,
                                                       const VolumeGrid& g) {
  const std::string tf_field = f + ".transfer";
  if (!o.contains("transfer"))
    return std::make_shared<TransferFunction>(
        *TransferFunction::preset("grayscale", g.min_value, g.max_value, tf_field));
  const json& t = o["transfer"];
  if (t.is_string()) {
    auto tf = TransferFunction::preset(t.get<std::string>(), g.min_value, g.max_value, tf_field);
    if (!tf) fail(tf_field, tf.error().message.substr(tf_field.size() + 2));
    return std::make_shared<TransferFunction>(std::move(*tf));
  }
  if (!t.is_array())
    fail(tf_field, "expected a preset name or a list of {value, color, opacity} points");
  std::vector<TransferPoint> points;
  for (size_t i = 0; i < t.size(); ++i) {
    const std::string pf = tf_field + "[" + std::to_string(i) + "]";
    require_object(t[i], pf);
    check_keys(t[i], pf, {"value", "color", "opacity"});
    TransferPoint p;
    p.value = float(get_number(need(t[i], pf, "value"), pf + ".value"));
    p.color = t[i].contains("color") ? get_color(t[i]["color"], pf + ".color") : Vec3(1.0f);
    p.opacity = get_float(need(t[i], pf, "opacity"), pf + ".opacity", 0.0, 1.0, "in [0, 1]");
    points.push_back(p);
  }
  auto tf = TransferFunction::make(std::move(points), tf_field);
  if (!tf) fail(tf_field, tf.error().message.substr(tf_field.size() + 2));
  return std::make_shared<TransferFunction>(std::move(*tf));
}

}  // namespace

void parse_volume(const json& o, const std::string& f, Scene& s, const std::string& base_dir,
                  const MaterialLookup& material) {
  check_keys(o, f,
             {"type", "file", "grid", "dims", "format", "endian", "spacing", "offset", "transform",
              "mode", "isovalue", "material", "inside", "transfer", "sampling_rate", "shade", "adaptive"});
  if (s.volumes.size() >= 4096) fail(f, "too many volumes (at most 4096)");
  GridSource from;
  VolumeObject v;
  v.grid = load_grid(o, f, base_dir, from);
  v.source = get_string(o["file"], f + ".file");
  const bool raw = from.raw;
  // OpenVDB level sets are surfaces at 0 with negative values inside; fog volumes are densities.
  const bool level_set = from.grid_class == "level set";
  if (from.vdb && o.contains("spacing"))
    fail(f + ".spacing", "not for OpenVDB files (their map gives it)");
  if (!raw)
    for (const char* key : {"dims", "format", "endian", "offset"})
      if (o.contains(key)) fail(f + "." + key, "only for raw files (the file says it itself)");
  if (!raw && o.contains("spacing")) {
    // Spacing overrides what a generator or NRRD header says.
    auto g = std::make_shared<VolumeGrid>(*v.grid);
    g->spacing = parse_spacing(o["spacing"], f + ".spacing");
    v.grid = g;
  }
  const std::string mode = o.contains("mode") ? get_string(o["mode"], f + ".mode")
                           : o.contains("isovalue") || level_set ? "isosurface"
                                                                 : "direct";
  if (mode == "isosurface") {
    v.mode = VolumeMode::kIsosurface;
    const json& iso = level_set && !o.contains("isovalue") ? json(0.0) : need(o, f, "isovalue");
    const json list = iso.is_array() ? iso : json::array({iso});
    if (list.empty() || list.size() > kMaxIsovalues)
      fail(f + ".isovalue", "expected 1 to 16 values");
    for (size_t i = 0; i < list.size(); ++i)
      v.isovalues.push_back(float(get_number(list[i], f + ".isovalue")));
    const json& mat = need(o, f, "material");
    if (mat.is_array() && mat.size() != list.size())
      fail(f + ".material", "expected one material per isovalue");
    for (size_t i = 0; i < list.size(); ++i)
      v.iso_materials.push_back(material(mat.is_array() ? mat[i] : mat, f + ".material"));
    v.inside_above = !level_set;
    if (o.contains("inside")) {
      const std::string in = get_string(o["inside"], f + ".inside");
      if (in != "above" && in != "below")
        fail(f + ".inside", "expected above or below, got '" + in + "'");
      v.inside_above = in == "above";
    }
    for (const char* key : {"transfer", "sampling_rate", "shade", "adaptive"})
      if (o.contains(key)) fail(f + "." + key, "only for the direct and mip modes");
  } else if (mode == "direct" || mode == "mip") {
    v.mode = mode == "direct" ? VolumeMode::kDirect : VolumeMode::kMip;
    for (const char* key : {"isovalue", "material", "inside"})
      if (o.contains(key)) fail(f + "." + key, "only for the isosurface mode");
    v.tf = parse_transfer(o, f, *v.grid);
    if (o.contains("sampling_rate"))
      v.step = 1.0f / get_float(o["sampling_rate"], f + ".sampling_rate", 0.05, 64.0,
                                "in [0.05, 64] samples per voxel");
    if (o.contains("shade")) v.shade = get_bool(o["shade"], f + ".shade");
    if (o.contains("adaptive")) v.adaptive = get_bool(o["adaptive"], f + ".adaptive");
  } else {
    fail(f + ".mode", "expected isosurface, direct or mip, got '" + mode + "'");
  }
  const glm::mat4 m =
      o.contains("transform") ? parse_transform(o["transform"], f + ".transform") : glm::mat4(1.0f);
  Affine a = to_affine(m);
  if (!(std::abs(glm::determinant(a.m)) > 1e-12f)) fail(f + ".transform", "is singular");
  if (from.vdb)
    a = Affine{a.m * from.native.m, a.point(from.native.t)};  // the file's map, then the object's
  place_volume(v, a);
  s.volumes.push_back(std::move(v));
}

}  // namespace frameless::scene_json
