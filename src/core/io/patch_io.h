// Reader for the bicubic_patch subset of POV-Ray scene files (the Utah teapot of povray-examples,
// /usr/share/doc/povray/examples/advanced/teapot/teapot.inc); loading thread only.
#pragma once
#include <string>
#include <string_view>
#include <vector>

#include "core/base/error.h"
#include "core/geometry/bezier.h"

namespace frameless {

// Every `bicubic_patch { ... }` block of a POV-Ray file, in file order. Inside a block: the
// keywords type, flatness, u_steps, v_steps, accuracy, each with a number or a #declared name,
// are accepted and ignored; then exactly 16 control points <x, y, z> (commas between points
// optional, as in POV-Ray); then texture/pigment/finish/normal/interior/material { ... } and the
// flags no_shadow, no_image, no_reflection, no_radiosity, double_illuminate, which are ignored.
// Transforms inside a block, names or expressions inside a vector, and any other keyword are
// errors. Everything outside the blocks (#declare, union { }, transforms, comments // and
// nested /* */, strings, ...) is skipped: patches keep the coordinates written in their block
// (the teapot is z-up).
//
// Mapping: POV-Ray's 4 rows of 4 points are rows i = 0..3 of BezierPatch (row i along v, the
// point within a row along u). POV-Ray itself runs its u along the rows (Control_Points[i][j],
// i with u), the transpose; the surface is the same, and this order makes du x dv point outward
// on all 32 teapot patches where POV-Ray's own normal points inward (it flips normals to face
// the ray, so files do not care).
//
// Errors are one line, "FILE:LINE: what is wrong" ("FILE: ..." for an unreadable file or one
// without any bicubic_patch).
Result<std::vector<BezierPatch>> load_bicubic_patches(const std::string& path);

// The same on text in memory; `name` stands for the file in messages (for the fuzzer: no I/O).
Result<std::vector<BezierPatch>> parse_bicubic_patches(std::string_view text, const std::string& name);

}  // namespace frameless
