// Converged reference renders for the benchmarks, cached on disk by a hash of everything that
// determines them (scene, size, camera, samples, code); control thread (renders with render_tiles).
#pragma once
#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include "core/base/error.h"
#include "core/scene/camera.h"
#include "core/scene/scene.h"

namespace frameless {

// What a reference depends on. Two specs with equal key_text() give the same image.
struct ReferenceSpec {
  std::string scene_id;      // scene_identity(spec): the spec plus a hash of a scene file's bytes
  std::string code_version;  // e.g. version + renderer_fingerprint(scene): a renderer change misses
  Camera camera;
  int width = 0;
  int height = 0;
  int spp = 64;  // samples per pixel, rendered as two independent halves
};

struct Reference {
  int width = 0, height = 0;
  std::vector<float> rgb;  // 3 floats per pixel: mean of both halves (linear RGB, row 0 at top)
  double noise_mse = 0;  // MSE the reference's own noise adds to a comparison (half_difference_mse)
  bool from_cache = false;  // read from the cache rather than rendered
  double seconds = 0;       // render or read time
  std::string path;         // cache file ("" when caching is off)
};

// Scene identity for the key: `spec`, plus an FNV-1a hash of the file's bytes when `spec` names
// a readable file (a scene JSON that includes meshes should be edited with a version bump).
std::string scene_identity(const std::string& spec);

// Hash of a tiny fixed render of `scene` (8x8 pixels, 2 samples, its own camera): changes when
// the renderer's output changes, so stale references are not reused after a code change.
std::string renderer_fingerprint(const Scene& scene);

// Canonical text of a spec (cameras in exact hex floats) and its 64-bit FNV-1a hash in hex.
std::string reference_key_text(const ReferenceSpec& spec);
std::string reference_key_hash(const ReferenceSpec& spec);

// $XDG_CACHE_HOME/frameless/references when XDG_CACHE_HOME is set, else OUT_DIR/cache.
std::string default_reference_cache_dir(const std::string& out_dir);

// The reference from `cache_dir` when a file with the same key text is there; otherwise renders it
// (render_tiles, `threads` threads, spp/2 + spp/2 samples with disjoint sample indices) and
// stores it (temporary file, then rename). Empty cache_dir: no caching.
// `progress` (may be empty) gets the fraction done while rendering.
Result<Reference> load_or_render_reference(const Scene& scene, const ReferenceSpec& spec,
                                           const std::string& cache_dir, int threads,
                                           const std::function<void(double)>& progress = {});

// The file format (exposed for tests): "FLREF1\n", key text, "\n", "W H NOISE_MSE\n", then
// W*H*3 little-endian floats.
Result<bool> write_reference_file(const std::string& path, const std::string& key_text,
                                  const Reference& ref);
// Reads a reference; an error when the file is missing, truncated or holds another key.
Result<Reference> read_reference_file(const std::string& path, const std::string& key_text);

}  // namespace frameless
