// Finding, loading and checking plug-in shader libraries.
#include "core/io/shader_library.h"

#include <dlfcn.h>

#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <map>
#include <set>

namespace frameless {
namespace {

// The loading thread's own state (the command line sets the folders, scenes load shaders).
std::vector<std::string> g_folders;
std::map<std::string, LoadedShader> g_loaded;  // by file

bool plain_name(const std::string& s, size_t max) {
  if (s.empty() || s.size() > max) return false;
  for (char c : s)
    if (!std::isalnum(static_cast<unsigned char>(c)) && c != '_' && c != '-') return false;
  return true;
}

// What is wrong with a declaration, or "".
std::string declaration_problem(const fl_shader* s) {
  if (!s) return "its entry point returned no shader";
  if (s->api_version != FRAMELESS_SHADER_API_VERSION)
    return "it was built for shader interface version " + std::to_string(s->api_version) + ", frameless has version " +
           std::to_string(FRAMELESS_SHADER_API_VERSION) + " (rebuild it against this include/frameless/shader.h)";
  if (!s->name || !plain_name(s->name, 64)) return "it declares no valid name";
  if (!s->shade) return "it declares no shade() function";
  if (!s->eval != !s->sample) return "it declares only one of eval() and sample() (a BSDF needs both)";
  if (s->param_count > 64) return "it declares " + std::to_string(s->param_count) + " parameters (at most 64)";
  if (s->param_count > 0 && !s->params) return "it declares parameters but no parameter table";
  std::set<std::string> seen;
  for (uint32_t i = 0; i < s->param_count; ++i) {
    const fl_param& p = s->params[i];
    const std::string at = "parameter " + std::to_string(i);
    if (!p.name || !plain_name(p.name, 64)) return at + " has no valid name";
    if (!seen.insert(p.name).second) return "parameter '" + std::string(p.name) + "' is declared twice";
    if (p.type != FL_PARAM_FLOAT && p.type != FL_PARAM_COLOR && p.type != FL_PARAM_TEXTURE)
      return "parameter '" + std::string(p.name) + "' has an unknown type";
    if (p.type == FL_PARAM_TEXTURE) continue;  // a name from the scene: no range, no default
    if (!std::isfinite(p.min) || !std::isfinite(p.max) || p.min > p.max)
      return "parameter '" + std::string(p.name) + "' has a bad range";
    for (int k = 0; k < shader_param_floats(p.type); ++k)
      if (!(p.default_value[k] >= p.min && p.default_value[k] <= p.max))
        return "parameter '" + std::string(p.name) + "' has a default outside its range";
  }
  return "";
}

}  // namespace

void set_shader_search_path(std::vector<std::string> folders) { g_folders = std::move(folders); }

std::vector<std::string> shader_search_path(const std::string& scene_dir) {
  std::vector<std::string> out = g_folders;
  if (const char* env = std::getenv("FRAMELESS_SHADER_PATH")) {
    std::string all = env;
    for (size_t at = 0; at <= all.size();) {
      const size_t end = std::min(all.find(':', at), all.size());
      if (end > at) out.push_back(all.substr(at, end - at));
      at = end + 1;
    }
  }
  if (!scene_dir.empty()) out.push_back(scene_dir);
  // Last, the example shaders of this build: its own shaders/ folder, then where it installs them
  // (so the command line, the API and the Python module all find them, built or installed).
  out.push_back(FRAMELESS_BUILD_SHADER_DIR);
  out.push_back(FRAMELESS_INSTALL_SHADER_DIR);
  return out;
}

Result<LoadedShader> load_shader(const std::string& name, const std::string& scene_dir) {
  if (!plain_name(name, 64)) return Error{"shader '" + name.substr(0, 64) + "': a name is letters, digits, '_' and '-'"};
  const std::vector<std::string> folders = shader_search_path(scene_dir);
  std::string file;
  for (const std::string& dir : folders) {
    for (const std::string& leaf : {name + ".so", "lib" + name + ".so"}) {
      std::error_code ec;
      const std::filesystem::path p = std::filesystem::path(dir) / leaf;
      if (std::filesystem::is_regular_file(p, ec)) {
        file = p.string();
        break;
      }
    }
    if (!file.empty()) break;
  }
  if (file.empty()) {
    std::string where;
    for (const std::string& d : folders) where += (where.empty() ? "" : ", ") + d;
    return Error{"shader '" + name + "': no " + name + ".so or lib" + name + ".so in the shader path (" +
                 (where.empty() ? std::string("empty: use --shader-path or FRAMELESS_SHADER_PATH") : where) + ")"};
  }
  if (auto it = g_loaded.find(file); it != g_loaded.end()) return it->second;
  void* handle = dlopen(file.c_str(), RTLD_NOW | RTLD_LOCAL);
  if (!handle) {
    const char* why = dlerror();
    return Error{one_line(file + ": cannot load: " + (why ? why : "unknown reason"))};
  }
  auto entry = reinterpret_cast<fl_shader_entry>(dlsym(handle, FRAMELESS_SHADER_ENTRY));
  if (!entry) {
    dlclose(handle);
    return Error{file + ": not a frameless shader (no " FRAMELESS_SHADER_ENTRY " entry point)"};
  }
  const fl_shader* s = entry();
  if (const std::string problem = declaration_problem(s); !problem.empty()) {
    dlclose(handle);
    return Error{one_line(file + ": " + problem)};
  }
  LoadedShader out{s, file};
  g_loaded[file] = out;  // the handle stays open: the shader's code runs until the process ends
  return out;
}

const fl_param* find_shader_param(const fl_shader& s, const std::string& name, int& offset) {
  offset = 0;
  for (uint32_t i = 0; i < s.param_count; ++i) {
    if (name == s.params[i].name) return &s.params[i];
    offset += shader_param_floats(s.params[i].type);
  }
  return nullptr;
}

std::vector<float> shader_defaults(const fl_shader& s) {
  std::vector<float> out;
  for (uint32_t i = 0; i < s.param_count; ++i)
    for (int k = 0; k < shader_param_floats(s.params[i].type); ++k)
      out.push_back(s.params[i].type == FL_PARAM_TEXTURE ? -1.0f : s.params[i].default_value[k]);  // no texture
  return out;
}

}  // namespace frameless
