// Reference renders with an on-disk cache keyed by scene, size, camera, samples and code.
#include "frameless/reference_cache.h"

#include <unistd.h>

#include <chrono>
#include <cinttypes>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "frameless/image_error.h"
#include "frameless/tile_render.h"

namespace frameless {
namespace {

constexpr uint64_t kFnvOffset = 1469598103934665603ull;
constexpr uint64_t kFnvPrime = 1099511628211ull;

uint64_t fnv1a(const void* data, size_t n, uint64_t h = kFnvOffset) {
  const auto* p = static_cast<const unsigned char*>(data);
  for (size_t i = 0; i < n; ++i) h = (h ^ p[i]) * kFnvPrime;
  return h;
}

std::string hex64(uint64_t v) {
  char buf[17];
  std::snprintf(buf, sizeof buf, "%016" PRIx64, v);
  return buf;
}

std::string hexfloat(float v) {
  char buf[40];
  std::snprintf(buf, sizeof buf, "%a", double(v));
  return buf;
}

std::string vec_text(const Vec3& v) {
  return hexfloat(v.x) + "," + hexfloat(v.y) + "," + hexfloat(v.z);
}

}  // namespace

std::string scene_identity(const std::string& spec) {
  std::error_code ec;
  if (!std::filesystem::is_regular_file(spec, ec)) return spec;
  std::ifstream in(spec, std::ios::binary);
  std::stringstream ss;
  ss << in.rdbuf();
  const std::string bytes = ss.str();
  return spec + "#" + hex64(fnv1a(bytes.data(), bytes.size()));
}

std::string renderer_fingerprint(const Scene& scene) {
  TileRenderOptions o;
  o.spp = 2;
  o.threads = 1;
  const RenderedImage img = render_tiles(scene, make_camera_basis(scene.camera, 8, 8), o);
  return hex64(fnv1a(img.rgb.data(), img.rgb.size() * sizeof(float)));
}

std::string reference_key_text(const ReferenceSpec& s) {
  std::string t = "scene=" + s.scene_id + ";code=" + s.code_version;
  t += ";size=" + std::to_string(s.width) + "x" + std::to_string(s.height);
  t += ";spp=" + std::to_string(s.spp);
  t += ";eye=" + vec_text(s.camera.eye) + ";look=" + vec_text(s.camera.look);
  t += ";up=" + vec_text(s.camera.up) + ";fov=" + hexfloat(s.camera.fov_deg);
  // The key is one line: newlines in a scene spec must not break the file header.
  for (char& c : t)
    if (c == '\n' || c == '\r') c = ' ';
  return t;
}

std::string reference_key_hash(const ReferenceSpec& spec) {
  const std::string t = reference_key_text(spec);
  return hex64(fnv1a(t.data(), t.size()));
}

std::string default_reference_cache_dir(const std::string& out_dir) {
  const char* xdg = std::getenv("XDG_CACHE_HOME");
  if (xdg && *xdg) return std::string(xdg) + "/frameless/references";
  return out_dir + "/cache";
}

Result<bool> write_reference_file(const std::string& path, const std::string& key_text,
                                  const Reference& ref) {
  if (ref.rgb.size() != size_t(ref.width) * size_t(ref.height) * 3)
    return Error{path + ": reference size does not match its pixels"};
  const std::string tmp = path + ".tmp" + std::to_string(::getpid());
  {
    std::ofstream out(tmp, std::ios::binary | std::ios::trunc);
    if (!out) return Error{tmp + ": cannot open for writing: " + std::strerror(errno)};
    char header[96];
    std::snprintf(header, sizeof header, "%d %d %.17g\n", ref.width, ref.height, ref.noise_mse);
    out << "FLREF1\n" << key_text << "\n" << header;
    out.write(reinterpret_cast<const char*>(ref.rgb.data()),
              std::streamsize(ref.rgb.size() * sizeof(float)));
    out.flush();
    if (!out) {
      std::remove(tmp.c_str());
      return Error{tmp + ": write failed"};
    }
  }
  if (std::rename(tmp.c_str(), path.c_str()) != 0) {
    const std::string why = std::strerror(errno);
    std::remove(tmp.c_str());
    return Error{path + ": cannot rename into place: " + why};
  }
  return true;
}

Result<Reference> read_reference_file(const std::string& path, const std::string& key_text) {
  std::ifstream in(path, std::ios::binary);
  if (!in) return Error{path + ": cannot open"};
  std::string magic, key, dims;
  if (!std::getline(in, magic) || magic != "FLREF1") return Error{path + ": not a reference file"};
  if (!std::getline(in, key) || key != key_text) return Error{path + ": holds another key"};
  if (!std::getline(in, dims)) return Error{path + ": truncated header"};
  Reference r;
  if (std::sscanf(dims.c_str(), "%d %d %lg", &r.width, &r.height, &r.noise_mse) != 3 ||
      r.width < 1 || r.height < 1 || r.width > 16384 || r.height > 16384)
    return Error{path + ": bad size line"};
  r.rgb.resize(size_t(r.width) * size_t(r.height) * 3);
  in.read(reinterpret_cast<char*>(r.rgb.data()), std::streamsize(r.rgb.size() * sizeof(float)));
  if (in.gcount() != std::streamsize(r.rgb.size() * sizeof(float)))
    return Error{path + ": truncated pixels"};
  r.from_cache = true;
  r.path = path;
  return r;
}

Result<Reference> load_or_render_reference(const Scene& scene, const ReferenceSpec& spec,
                                           const std::string& cache_dir, int threads,
                                           const std::function<void(double)>& progress) {
  if (spec.width < 1 || spec.height < 1 || spec.spp < 2)
    return Error{"reference: need a positive size and at least 2 samples per pixel"};
  const auto start = std::chrono::steady_clock::now();
  const std::string key = reference_key_text(spec);
  std::string path;
  if (!cache_dir.empty()) {
    std::error_code ec;
    std::filesystem::create_directories(cache_dir, ec);
    path = cache_dir + "/ref_" + reference_key_hash(spec) + ".bin";
    auto cached = read_reference_file(path, key);
    if (cached.ok() && cached->width == spec.width && cached->height == spec.height) {
      cached->seconds =
          std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
      return cached;
    }
  }
  // Two halves with disjoint sample indices: their mean is the reference, their difference
  // estimates its remaining noise.
  const CameraBasis basis = make_camera_basis(spec.camera, spec.width, spec.height);
  TileRenderOptions o;
  o.threads = std::max(1, threads);
  o.spp = spec.spp / 2;
  if (progress) o.progress = [&](double f) { progress(0.5 * f); };
  const RenderedImage a = render_tiles(scene, basis, o);
  o.first_sample = uint32_t(o.spp);
  o.spp = spec.spp - spec.spp / 2;
  if (progress) o.progress = [&](double f) { progress(0.5 + 0.5 * f); };
  const RenderedImage b = render_tiles(scene, basis, o);
  Reference r;
  r.width = spec.width;
  r.height = spec.height;
  r.rgb.resize(a.rgb.size());
  const double wa = double(spec.spp / 2) / spec.spp, wb = 1.0 - wa;
  for (size_t i = 0; i < r.rgb.size(); ++i) r.rgb[i] = float(wa * a.rgb[i] + wb * b.rgb[i]);
  r.noise_mse = half_difference_mse(a.rgb, b.rgb);
  r.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  if (!path.empty()) {
    auto w = write_reference_file(path, key, r);
    if (!w.ok()) return w.error();
    r.path = path;
  }
  return r;
}

}  // namespace frameless
