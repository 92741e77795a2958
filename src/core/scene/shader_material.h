// Materials shaded by plug-in shaders (issue 28; include/frameless/shader.h): the shader a
// library provided and the material's parameter values in the shader's declaration order. The
// library stays loaded for the process (core/io/shader_library.h); read-only while rendering.
#pragma once
#include <string>
#include <vector>

#include "frameless/shader.h"

namespace frameless {

struct ShaderMaterial {
  const fl_shader* shader = nullptr;
  std::vector<float> params;  // 1 value per FL_PARAM_FLOAT, 3 per FL_PARAM_COLOR
  std::string library;        // the file it came from, for messages
};

}  // namespace frameless
