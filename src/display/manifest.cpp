#include "display/manifest.h"

#include <cerrno>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <sstream>

#include "display/atomic_file.h"

namespace frameless {
namespace {

nlohmann::json vec(const Vec3& v) { return {v.x, v.y, v.z}; }

bool read_vec(const nlohmann::json& j, const char* key, Vec3& out) {
  if (!j.contains(key) || !j[key].is_array() || j[key].size() != 3) return false;
  for (int i = 0; i < 3; ++i) {
    if (!j[key][i].is_number()) return false;
    out[i] = j[key][i].get<float>();
  }
  return true;
}

}  // namespace

nlohmann::json manifest_to_json(const Manifest& m) {
  nlohmann::json frames = nlohmann::json::array();
  for (const ManifestFrame& f : m.frames) {
    frames.push_back({{"index", f.index},
                      {"file", f.file},
                      {"display_tick", f.display_tick},
                      {"wall_time", f.wall_time < 0 ? nlohmann::json(nullptr) : nlohmann::json(f.wall_time)},
                      {"virtual_time", f.virtual_time},
                      {"camera",
                       {{"eye", vec(f.camera.eye)},
                        {"look", vec(f.camera.look)},
                        {"up", vec(f.camera.up)},
                        {"fov", f.camera.fov_deg},
                        {"epoch", f.camera_epoch}}},
                      {"samples", f.samples},
                      {"coverage", f.coverage},
                      {"mode", f.mode}});
    if (!f.views.empty()) frames.back()["views"] = f.views;
  }
  return {{"format", "frameless-capture-1"}, {"settings", m.settings}, {"frames", frames}};
}

Result<Manifest> manifest_from_json(const nlohmann::json& j, const std::string& path) {
  Manifest m;
  try {
    m.settings = j.at("settings");
    const auto& frames = j.at("frames");
    for (size_t i = 0; i < frames.size(); ++i) {
      const auto& fj = frames[i];
      ManifestFrame f;
      f.index = fj.at("index").get<int>();
      f.file = fj.at("file").get<std::string>();
      f.display_tick = fj.at("display_tick").get<uint64_t>();
      f.wall_time = fj.at("wall_time").is_null() ? -1.0 : fj.at("wall_time").get<double>();
      f.virtual_time = fj.at("virtual_time").get<double>();
      const auto& c = fj.at("camera");
      if (!read_vec(c, "eye", f.camera.eye) || !read_vec(c, "look", f.camera.look) ||
          !read_vec(c, "up", f.camera.up))
        return Error{path + ": frames[" + std::to_string(i) + "].camera: expected eye, look, up"};
      f.camera.fov_deg = c.at("fov").get<float>();
      f.camera_epoch = c.at("epoch").get<uint32_t>();
      f.samples = fj.at("samples").get<uint64_t>();
      f.coverage = fj.at("coverage").get<double>();
      f.mode = fj.at("mode").get<std::string>();
      if (fj.contains("views")) f.views = fj.at("views").get<std::map<std::string, std::string>>();
      m.frames.push_back(f);
    }
  } catch (const nlohmann::json::exception& e) {
    return Error{path + ": " + e.what()};
  }
  return m;
}

Result<bool> write_text_file_atomic(const std::string& path, const std::string& text) {
  const std::string tmp = temporary_path_for(path);
  std::FILE* f = std::fopen(tmp.c_str(), "wb");
  if (!f) return Error{path + ": cannot write: " + std::strerror(errno)};
  const bool ok = std::fwrite(text.data(), 1, text.size(), f) == text.size();
  const int err = errno;
  if (std::fclose(f) != 0 || !ok) {
    std::remove(tmp.c_str());
    return Error{path + ": cannot write: " + std::strerror(ok ? errno : err)};
  }
  std::string error;
  if (!commit_temporary(tmp, path, error)) return Error{error};
  return true;
}

Result<bool> write_manifest(const std::string& path, const Manifest& manifest) {
  return write_text_file_atomic(path, manifest_to_json(manifest).dump(1) + "\n");
}

Result<Manifest> read_manifest(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) return Error{path + ": cannot open manifest"};
  std::stringstream ss;
  ss << in.rdbuf();
  try {
    return manifest_from_json(nlohmann::json::parse(ss.str()), path);
  } catch (const nlohmann::json::parse_error& e) {
    return Error{path + ": " + e.what()};
  }
}

}  // namespace frameless
