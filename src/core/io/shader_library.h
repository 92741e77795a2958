// Plug-in shader libraries (issue 28; include/frameless/shader.h): where they are looked for,
// loading each once (dlopen), and checking what they declare, so that a broken or mismatched
// library is one line, not a crash. Loading happens on the loading thread; the libraries stay
// loaded for the process (their code runs on the render threads). Loading thread only: the
// search path and the loaded libraries are its own state.
#pragma once
#include <string>
#include <vector>

#include "core/base/error.h"
#include "frameless/shader.h"

namespace frameless {

// Folders searched first, in order (the command line's --shader-path); then the folders of the
// FRAMELESS_SHADER_PATH variable (:-separated); then the scene file's folder; last the example
// shaders of this build (its build tree's shaders/, then the installation's lib/frameless/shaders).
void set_shader_search_path(std::vector<std::string> folders);
std::vector<std::string> shader_search_path(const std::string& scene_dir);

struct LoadedShader {
  const fl_shader* shader = nullptr;
  std::string library;  // the file loaded
};

// The shader NAME (letters, digits, '_' and '-'): NAME.so or libNAME.so in the first folder of
// the search path that has one, loaded once per process, its entry point called and its
// declaration checked (interface version, a name, shade(), parameters well formed).
Result<LoadedShader> load_shader(const std::string& name, const std::string& scene_dir);

// The declaration of parameter `name` and where its values sit in a material's parameter block
// (`offset`); null when the shader declares no parameter of that name.
const fl_param* find_shader_param(const fl_shader& s, const std::string& name, int& offset);
// The block of default values, in declaration order.
std::vector<float> shader_defaults(const fl_shader& s);
// The values one parameter takes in the material's table: 3 for a colour, else 1.
inline int shader_param_floats(fl_param_type type) { return type == FL_PARAM_COLOR ? 3 : 1; }

}  // namespace frameless
