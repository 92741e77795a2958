// libFuzzer target for every parser of scene input. The first byte picks the parser (its value
// modulo 15), the rest is that parser's input:
//   0  JSON scene, base folder /nonexistent ("mesh" and "textures" files are missing)
//   1  OBJ (parse_obj)
//   2  PLY (parse_ply)
//   3  glTF text (parse_gltf, base folder /nonexistent: external buffers and images must fail)
//   4  GLB (parse_gltf on the same bytes; it tells GLB from text by the "glTF" magic)
//   5  MTL: written as fuzz.mtl into a per-process work folder, next to a fixed OBJ that names it
//      and uses its materials a, b, c and m, then read with load_obj_with_materials (the MTL
//      parser has no entry point of its own); the folder holds t.png (RGBA) and g.png (grey)
//      for map statements
//   6  image (decode_image): the second byte picks a magic put in front of the rest, so that
//      mutations stay inside one decoder: 0 PNG, 1 JPEG, 2 OpenEXR, 3 none (the bytes as given),
//      4 Radiance HDR
//   7  JSON scene whose base folder is the work folder, so "textures" entries naming t.png or
//      g.png load
//   8  POV-Ray bicubic_patch text (parse_bicubic_patches); patches that load are built at depth 2
//      and traced by a few rays, whose hits must be finite and inside the patch's bounds
//   9  binary sphere file (parse_sphere_bytes, with a colour map); spheres that load are built
//      into a scene (finalize_scene) and traced
//  11  NRRD volume with attached data (decode_nrrd, base folder /nonexistent)
//  12  raw volume: bytes 0-2 are nx, ny, nz less 2, byte 3 % 3 the voxel type (uint8, uint16,
//      float32), byte 4 & 1 big-endian, bytes 5-15 unused, the rest the voxels (decode_raw_volume);
//      a grid that loads must hold exactly its voxels and a sane value range
//  13  OpenVDB file (decode_vdb, the first float or double grid); a grid that loads must be
//      bricked with every table entry naming a stored brick, and a sane value range
//  14  lightfield file (decode_lightfield); a table that loads must pass check_lightfield and be
//      looked up (finite, alpha in [0, 1]) through its slab
// Every call must return a value or a one-line, non-empty error; an error message that is empty
// or holds a newline traps (__builtin_trap), as does a returned value that breaks its documented
// invariants (mesh indices, per-vertex arrays, material and texture slots, image sizes, finite
// texels and samples). Meshes that load are then built into a scene as `frameless MESH` would
// (make_mesh_scene + finalize_scene). Cluster messages (first byte 10) must decode or be
// refused in one line, and what decodes must encode back to the same bytes. SCENE_FUZZER_VERBOSE=1 prints each input's outcome (handy
// when replaying one file). Build with -DFRAMELESS_FUZZ=ON and clang.
#include <fcntl.h>
#include <signal.h>
#include <unistd.h>

#include <cerrno>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <string>
#include <system_error>

#include "cluster/wire.h"
#include "core/io/lightfield_file.h"
#include "core/io/patch_io.h"
#include "core/io/sphere_file.h"
#include "core/io/volume_nrrd.h"
#include "core/io/volume_raw.h"
#include "core/io/volume_vdb.h"
#include "core/scene/scene.h"
#include "core/scene/scene_build.h"
#include "core/scene/scene_finalize.h"
#include "core/scene/texture.h"
#include "core/scenes/scene_load.h"
#include "core/volume/macrocells.h"

namespace {

namespace fs = std::filesystem;
using namespace frameless;

// 4x4 8-bit RGBA and 2x2 8-bit grey PNGs (written by make_seeds.py's png()).
const unsigned char kRgbaPng[] = {
    0x89, 0x50, 0x4e, 0x47, 0x0d, 0x0a, 0x1a, 0x0a, 0x00, 0x00, 0x00, 0x0d, 0x49, 0x48, 0x44,
    0x52, 0x00, 0x00, 0x00, 0x04, 0x00, 0x00, 0x00, 0x04, 0x08, 0x06, 0x00, 0x00, 0x00, 0xa9,
    0xf1, 0x9e, 0x7e, 0x00, 0x00, 0x00, 0x2f, 0x49, 0x44, 0x41, 0x54, 0x78, 0xda, 0x15, 0xca,
    0x31, 0x01, 0x00, 0x30, 0x10, 0x02, 0x31, 0xa4, 0x21, 0x0d, 0x69, 0x8c, 0xb8, 0xfa, 0x5e,
    0xa7, 0x2c, 0x91, 0xb4, 0x58, 0xbb, 0x60, 0x51, 0xf2, 0xce, 0x5e, 0x82, 0x45, 0x29, 0x8c,
    0x30, 0xb0, 0xf9, 0xa3, 0x8c, 0x32, 0xb0, 0xf8, 0x00, 0x63, 0x3c, 0x24, 0x79, 0x68, 0x14,
    0xb0, 0x09, 0x00, 0x00, 0x00, 0x00, 0x49, 0x45, 0x4e, 0x44, 0xae, 0x42, 0x60, 0x82};
const unsigned char kGreyPng[] = {
    0x89, 0x50, 0x4e, 0x47, 0x0d, 0x0a, 0x1a, 0x0a, 0x00, 0x00, 0x00, 0x0d, 0x49, 0x48, 0x44,
    0x52, 0x00, 0x00, 0x00, 0x02, 0x00, 0x00, 0x00, 0x02, 0x08, 0x00, 0x00, 0x00, 0x00, 0x57,
    0xdd, 0x52, 0xf8, 0x00, 0x00, 0x00, 0x0e, 0x49, 0x44, 0x41, 0x54, 0x78, 0xda, 0x63, 0x60,
    0xf8, 0xcf, 0xd0, 0xe0, 0x00, 0x00, 0x05, 0x42, 0x01, 0xc0, 0x6d, 0x5e, 0x78, 0xa0, 0x00,
    0x00, 0x00, 0x00, 0x49, 0x45, 0x4e, 0x44, 0xae, 0x42, 0x60, 0x82};

// The OBJ next to fuzz.mtl: uvs and normals (so textured materials get per-vertex uvs), one
// face before any usemtl (default material) and one face per MTL material a, b, c, m.
constexpr char kObjWithMtl[] =
    "mtllib fuzz.mtl\n"
    "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 1 1 0\nv 0.5 0.5 1\n"
    "vt 0 0\nvt 1 0\nvt 0 1\nvt 1 1\n"
    "vn 0 0 1\nvn 0 1 0\n"
    "f 1/1/1 2/2/1 3/3/1\n"
    "usemtl a\nf 2/2/1 4/4/1 3/3/1\n"
    "usemtl b\nf 1/1/2 2/2/2 5/4/2\n"
    "usemtl c\nf 3 4 5\n"
    "usemtl m\nf 1/1 3/3 5/4\n";

bool verbose() {
  static const bool v = [] {
    const char* e = std::getenv("SCENE_FUZZER_VERBOSE");
    return e && *e && *e != '0';
  }();
  return v;
}

[[noreturn]] void broken(const char* what, const std::string& detail) {
  std::fprintf(stderr, "scene_fuzzer: %s: [%s]\n", what, detail.c_str());
  __builtin_trap();
}

// An error is one line of output: non-empty, no line break.
void check_error(const Error& e) {
  if (e.message.empty()) broken("error message is empty", "");
  if (e.message.find_first_of("\n\r") != std::string::npos)
    broken("error message is not one line", e.message);
  if (verbose()) std::fprintf(stderr, "scene_fuzzer: error: %s\n", e.message.c_str());
}

bool finite(const Vec3& v) { return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z); }

void check_image(const Image& img) {
  const uint64_t n = uint64_t(img.width) * uint64_t(img.height) * uint64_t(img.channels);
  if (img.width <= 0 || img.height <= 0 || img.channels < 1 || img.channels > 4 ||
      uint64_t(img.width) * uint64_t(img.height) > kMaxTexturePixels)
    broken("decoded image has a bad size",
           std::to_string(img.width) + "x" + std::to_string(img.height) + "x" +
               std::to_string(img.channels));
  if (!((img.ldr.size() == n && img.hdr.empty()) || (img.hdr.size() == n && img.ldr.empty())))
    broken("decoded image's texels do not match its size", img.path);
  for (float v : img.hdr)
    if (!std::isfinite(v)) broken("decoded EXR has a non-finite texel", img.path);
  // Sampling: bilinear inside, repeat and clamp outside [0, 1]; never NaN/Inf.
  Texture t;
  t.image = std::shared_ptr<const Image>(std::shared_ptr<const Image>(), &img);
  for (TextureWrap wrap : {TextureWrap::kRepeat, TextureWrap::kClamp})
    for (Vec2 uv : {Vec2(0.3f, 0.7f), Vec2(-1.6f, 2.25f), Vec2(1.0f, 0.0f)}) {
      t.wrap = wrap;
      const Vec4 c = sample_texture(t, TexturePoint{uv, Vec3(0.0f)});
      if (!std::isfinite(c.x) || !std::isfinite(c.y) || !std::isfinite(c.z) || !std::isfinite(c.w))
        broken("sample_texture returned a non-finite value", img.path);
    }
}

// The invariants core/scene/mesh_data.h documents for MeshData (what add_mesh relies on). A shared
// mesh uses its model's materials: `materials` is their count (~0: the mesh's own).
void check_mesh(const MeshData& m, size_t materials = ~size_t(0)) {
  if (materials == ~size_t(0)) materials = m.materials.size();
  const size_t nv = m.positions.size();
  for (const Vec3& p : m.positions)
    if (!finite(p)) broken("mesh has a non-finite position", "");
  if (!m.normals.empty() && m.normals.size() != nv)
    broken("mesh normals are neither empty nor one per position", std::to_string(m.normals.size()));
  if (!m.uvs.empty() && m.uvs.size() != nv)
    broken("mesh uvs are neither empty nor one per position", std::to_string(m.uvs.size()));
  for (const UVec3& t : m.triangles)
    if (t[0] >= nv || t[1] >= nv || t[2] >= nv) broken("triangle index out of range", "");
  if (!m.face_material.empty()) {
    if (m.face_material.size() != m.triangles.size())
      broken("face_material is neither empty nor one per triangle", "");
    for (uint16_t f : m.face_material)
      if (f >= materials) broken("face_material out of range", std::to_string(f));
  }
  for (const Material& mat : m.materials) {
    for (uint32_t t : {mat.kd_tex, mat.kh_tex, mat.ks_tex, mat.alpha_tex, mat.normal_tex,
                       mat.bump_tex})
      if (t != kNoTexture && t >= m.textures.size())
        broken("material texture slot out of range", mat.name);
  }
  for (const Texture& t : m.textures)
    if (t.kind == TextureKind::kImage && !t.image) broken("image texture without an image", "");
  // Shared meshes (glTF meshes several nodes place): each valid on its own, with the model's
  // materials, and every placement naming one with an invertible, finite transform.
  for (const MeshData& sm : m.shared) {
    check_mesh(sm, m.materials.size());
  }
  for (const MeshPlacement& p : m.placements) {
    if (p.mesh >= m.shared.size()) broken("placement of a shared mesh out of range", std::to_string(p.mesh));
    for (int c = 0; c < 4; ++c)
      if (!finite(Vec3(p.to_model[c]))) broken("placement transform is not finite", "");
  }
}

// A mesh that loaded is shown the way `frameless MESH` shows it.
void build_scene(MeshData mesh) {
  check_mesh(mesh);
  auto scene = make_mesh_scene(std::move(mesh), "fuzz");
  finalize_scene(*scene);
}

void run_mesh(Result<MeshData> r) {
  if (!r) return check_error(r.error());
  if (verbose())
    std::fprintf(stderr, "scene_fuzzer: mesh: %zu positions, %zu triangles, %zu materials, %zu textures\n",
                 r->positions.size(), r->triangles.size(), r->materials.size(), r->textures.size());
  build_scene(std::move(*r));
}

void run_model(Result<ModelData> r) {
  if (!r) return check_error(r.error());
  if (verbose()) {
    std::fprintf(stderr, "scene_fuzzer: model: %zu cameras, %zu lights, %zu warnings\n",
                 r->cameras.size(), r->lights.size(), r->warnings.size());
    for (const std::string& w : r->warnings) std::fprintf(stderr, "scene_fuzzer: warning: %s\n", w.c_str());
  }
  for (const Texture& t : r->mesh.textures)
    if (t.image) check_image(*t.image);
  run_mesh(std::move(r->mesh));
}

void run_scene(const Result<std::unique_ptr<Scene>>& r) {
  if (!r) return check_error(r.error());
  if (verbose()) std::fprintf(stderr, "scene_fuzzer: scene loaded\n");
}

void write_file(const std::string& path, const void* data, size_t size) {
  std::ofstream f(path, std::ios::binary | std::ios::trunc);
  f.write(static_cast<const char*>(data), std::streamsize(size));
  f.close();
  if (!f) {
    std::fprintf(stderr, "scene_fuzzer: cannot write %s\n", path.c_str());
    std::abort();
  }
}

// The per-process work folder of modes 5 and 7, removed at exit. A crash (_Exit) leaves it
// behind: folders of processes that no longer exist are removed at the next start.
class WorkDir {
 public:
  WorkDir() {
    std::error_code ec;
    const fs::path tmp = fs::temp_directory_path(ec);
    const fs::path root = ec ? fs::path("/tmp") : tmp;
    const std::string prefix = "frameless_scene_fuzzer.";
    for (fs::directory_iterator it(root, ec), end; !ec && it != end; it.increment(ec)) {
      const std::string name = it->path().filename().string();
      if (name.rfind(prefix, 0) != 0) continue;
      const long pid = std::strtol(name.c_str() + prefix.size(), nullptr, 10);
      if (pid > 0 && ::kill(pid_t(pid), 0) != 0 && errno == ESRCH) {
        std::error_code ignored;
        fs::remove_all(it->path(), ignored);
      }
    }
    dir_ = (root / (prefix + std::to_string(::getpid()))).string();
    fs::remove_all(dir_, ec);
    fs::create_directories(dir_);
    write_file(dir_ + "/t.png", kRgbaPng, sizeof kRgbaPng);
    write_file(dir_ + "/g.png", kGreyPng, sizeof kGreyPng);
    write_file(obj(), kObjWithMtl, sizeof kObjWithMtl - 1);
  }
  ~WorkDir() {
    std::error_code ec;
    fs::remove_all(dir_, ec);
  }
  const std::string& dir() const { return dir_; }
  std::string obj() const { return dir_ + "/fuzz.obj"; }
  std::string mtl() const { return dir_ + "/fuzz.mtl"; }

 private:
  std::string dir_;
};

WorkDir& work_dir() {
  static WorkDir dir;
  return dir;
}

}  // namespace

extern "C" int LLVMFuzzerInitialize(int*, char***) {
  // No parser may block on a terminal or a pipe (a file named /dev/stdin, /proc/self/fd/0).
  const int null_fd = ::open("/dev/null", O_RDONLY);
  if (null_fd >= 0 && null_fd != 0) {
    ::dup2(null_fd, 0);
    ::close(null_fd);
  }
  (void)work_dir();
  return 0;
}

// Patches that parse: finite controls, a built surface whose hits lie in its bounds.
void run_patches(Result<std::vector<BezierPatch>> r) {
  if (!r) return check_error(r.error());
  if (verbose()) std::fprintf(stderr, "scene_fuzzer: %zu patches\n", r->size());
  for (size_t i = 0; i < r->size() && i < 64; ++i) {
    for (const Vec3& c : (*r)[i].p)
      if (!is_finite(c)) __builtin_trap();
    const PatchSurface ps((*r)[i], 2);
    const Vec3 mid = 0.5f * (ps.lo() + ps.hi());
    for (int k = 0; k < 6; ++k) {
      Ray ray;
      ray.dir = Vec3(k % 3 == 0, k % 3 == 1, k % 3 == 2) * (k < 3 ? 1.0f : -1.0f);
      ray.org = mid - ray.dir * (1.0f + max_component(ps.hi() - ps.lo()));
      float t, u, v;
      if (!ps.intersect(ray, 0.0f, kInfinity, t, u, v)) continue;
      if (!std::isfinite(t) || !(u >= 0.0f && u <= 1.0f && v >= 0.0f && v <= 1.0f)) __builtin_trap();
      if (!is_finite(bezier_normal((*r)[i], u, v))) __builtin_trap();
    }
  }
}

void run_spheres(const std::string& input) {
  auto scene = std::make_unique<Scene>();
  Material m;
  scene->materials.assign(8, m);
  auto r = parse_sphere_bytes(input, "fuzz.spheres", scene->geometry, 0, 8);
  if (!r) {
    check_error(r.error());
    if (!scene->geometry.spheres.empty()) __builtin_trap();  // rolled back on error
    return;
  }
  const Geometry& g = scene->geometry;
  if (!g.sphere_material.empty() && g.sphere_material.size() != g.spheres.size()) __builtin_trap();
  for (uint16_t id : g.sphere_material)
    if (id >= 8) __builtin_trap();
  for (const Sphere& sp : g.spheres)
    if (!is_finite(sp.center) || !(sp.radius >= 0.0f)) __builtin_trap();
  if (g.spheres.size() > 100000) return;  // keep each input fast
  finalize_scene(*scene);
  run_scene(Result<std::unique_ptr<Scene>>(std::move(scene)));
}

// Cluster messages as they arrive from the network (cluster/wire.h): refused with one line, or
// decoded into values that encode back to exactly the same bytes.
void run_wire(const std::string& input) {
  if (input.empty()) return;
  const auto* p = reinterpret_cast<const uint8_t*>(input.data()) + 1;
  const size_t n = input.size() - 1;
  try {
    std::vector<uint8_t> again;
    switch (uint8_t(input[0]) % 4) {
      case 0: again = cluster::encode(cluster::decode_hello(p, n)); break;
      case 1: again = cluster::encode(cluster::decode_control(p, n)); break;
      case 2: again = cluster::encode(cluster::decode_updates(p, n)); break;
      default: again = cluster::encode(cluster::decode_results(p, n)); break;
    }
    if (again.size() != n || std::memcmp(again.data(), p, n) != 0) {
      std::fprintf(stderr, "scene_fuzzer: a wire message does not encode back to its bytes\n");
      std::abort();
    }
  } catch (const std::invalid_argument& e) {
    check_error(Error{e.what()});
  }
}

// A volume that loads holds exactly its voxels, a sane range, and its macrocells hold that range.
void run_volume(const Result<std::shared_ptr<const VolumeGrid>>& r) {
  if (!r) return check_error(r.error());
  const VolumeGrid& g = *r.value();
  if (!g.storage || g.storage->size() != g.voxels() * voxel_bytes(g.type)) broken("volume storage size", std::to_string(g.bytes()));
  if (!(g.min_value <= g.max_value) || !std::isfinite(g.min_value) || !std::isfinite(g.max_value))
    broken("volume value range", std::to_string(g.min_value) + " " + std::to_string(g.max_value));
  const Macrocells m = build_macrocells(g);
  for (size_t i = 0; i < m.lo.size(); ++i)
    if (m.lo[i] < g.min_value || m.hi[i] > g.max_value) broken("macrocell outside the range", std::to_string(i));
}

void run_vdb(const Result<VdbVolume>& r) {
  if (!r) return check_error(r.error());
  const VolumeGrid& g = *r.value().bricked.grid;
  if (!g.bricks || g.storage) broken("an OpenVDB grid that is not bricked", r.value().name);
  const BrickPool& p = *g.bricks;
  if (p.table.size() != size_t(p.bx) * size_t(p.by) * size_t(p.bz) || p.voxels.size() != p.stored() * kBrickVoxels)
    broken("brick table size", std::to_string(p.table.size()));
  for (uint32_t b : p.table)
    if (b >= p.stored()) broken("brick table entry past the pool", std::to_string(b));
  if (!(g.min_value <= g.max_value) || !std::isfinite(g.min_value) || !std::isfinite(g.max_value))
    broken("volume value range", std::to_string(g.min_value) + " " + std::to_string(g.max_value));
  if (g.voxels() > (size_t(1) << 24)) return;  // the macrocells of huge sparse bounds take long
  const Macrocells m = build_macrocells(g);
  for (size_t i = 0; i < m.lo.size(); ++i)
    if (m.lo[i] < g.min_value || m.hi[i] > g.max_value) broken("macrocell outside the range", std::to_string(i));
}

void run_lightfield(const Result<std::shared_ptr<const LightField>>& r) {
  if (!r) return check_error(r.error());
  const LightField& lf = *r.value();
  if (!check_lightfield(lf).empty()) broken("lightfield", check_lightfield(lf));
  for (int k = 0; k < 64; ++k) {
    const float a = float(k % 8) / 3.5f - 1.0f, b = float(k / 8) / 3.5f - 1.0f;
    const Vec4Color c = lf.lookup(a, b, -b, a);
    if (!is_finite(c.rgb) || !(c.alpha >= 0.0f && c.alpha <= 1.0f + 1e-6f)) broken("lightfield lookup", std::to_string(k));
  }
}

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  if (size < 1) return 0;
  const std::string input(reinterpret_cast<const char*>(data + 1), size - 1);
  switch (data[0] % 15) {
    case 0:
      run_scene(parse_scene_json(input, "fuzz.json", "/nonexistent"));
      break;
    case 1:
      run_mesh(parse_obj(input, "fuzz.obj"));
      break;
    case 2:
      run_mesh(parse_ply(input, "fuzz.ply"));
      break;
    case 3:
    case 4: {
      ImageCache images;
      run_model(parse_gltf(input, data[0] % 10 == 3 ? "fuzz.gltf" : "fuzz.glb", "/nonexistent",
                           images));
      break;
    }
    case 5: {
      const WorkDir& w = work_dir();
      write_file(w.mtl(), input.data(), input.size());
      {
        ImageCache images;
        run_mesh(load_obj_with_materials(w.obj(), images));
      }
      std::error_code ec;
      fs::remove(w.mtl(), ec);
      break;
    }
    case 6: {
      if (input.empty()) {
        if (const auto r = decode_image(input, "fuzz.img"); !r) check_error(r.error());
        break;
      }
      static const std::string kMagic[5] = {std::string("\x89PNG\r\n\x1a\n", 8),
                                            std::string("\xff\xd8\xff", 3),
                                            std::string("\x76\x2f\x31\x01", 4), std::string(),
                                            std::string("#?RADIANCE\n")};
      const std::string bytes = kMagic[uint8_t(input[0]) % 5] + input.substr(1);
      auto r = decode_image(bytes, "fuzz.img");
      if (!r) {
        check_error(r.error());
      } else {
        if (verbose())
          std::fprintf(stderr, "scene_fuzzer: image: %dx%dx%d\n", (*r)->width, (*r)->height,
                       (*r)->channels);
        check_image(**r);
      }
      break;
    }
    case 7:
      run_scene(parse_scene_json(input, "fuzz.json", work_dir().dir()));
      break;
    case 8:
      run_patches(parse_bicubic_patches(input, "fuzz.inc"));
      break;
    case 9:
      run_spheres(input);
      break;
    case 10:
      run_wire(input);
      break;
    case 11:
      run_volume(decode_nrrd(input, "fuzz.nrrd", "/nonexistent"));
      break;
    case 12: {
      if (input.size() < 16) break;
      RawVolumeSpec spec;
      spec.nx = uint8_t(input[0]) + 2;
      spec.ny = uint8_t(input[1]) + 2;
      spec.nz = uint8_t(input[2]) + 2;
      spec.type = VoxelType(uint8_t(input[3]) % 3);
      spec.big_endian = input[4] & 1;
      run_volume(decode_raw_volume(input.substr(16), spec, "fuzz.raw"));
      break;
    }
    case 13:
      // Bricks held to 16 MB: a few kilobytes of tiles can ask for gigabytes (libFuzzer's limit is
      // 2 GB), and a grid of millions of bricks takes seconds an input.
      run_vdb(decode_vdb(reinterpret_cast<const uint8_t*>(input.data()), input.size(), "fuzz.vdb", "", uint64_t(1) << 24));
      break;
    case 14:
      run_lightfield(decode_lightfield(input, "fuzz.exr"));
      break;
  }
  return 0;
}
