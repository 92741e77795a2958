// Parker's four material classes as shader declarations (include/frameless/shader.h): built in,
// never loaded. A scene may name them like plug-ins ("shader": "polished", "params": {...}),
// checked by the same declarations; such materials run as the compiled classes (the kernel's
// switch, specialised per shading path: no indirect call). Each declaration also carries a
// shade() that writes Parker's equations 1 and 2 against the interface alone: the reference a
// plug-in author can read, and what `bench ablation` times against the compiled kernel. Loading
// thread (the declarations are constants; shade() is pure, any thread).
#pragma once
#include <string>

#include "core/scene/scene.h"
#include "frameless/shader.h"

namespace frameless {

// "diffuse", "metal", "dielectric" or "polished"; null for any other name.
const fl_shader* parker_shader(const std::string& name);
// The four, in that order.
const fl_shader* const* parker_shaders();
inline constexpr int kParkerShaders = 4;

// The compiled-class material a built-in declaration's parameter block describes.
Material parker_material(const fl_shader& shader, const float* params);

// Rebinds every untextured material of the compiled classes to its declaration's shade(), as if
// it were a plug-in (for tests and benchmarks: what going through the interface costs and that
// it gives the same image). Call before finalize_scene; returns how many it rebound.
int route_through_interface(Scene& scene);

}  // namespace frameless
