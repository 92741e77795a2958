// The viewer's keys for volumes (issue 27; the panels issue gives them a UI): Z and X lower and
// raise every isosurface's isovalues by 2 % of its grid's value range, B switches the volume
// shader's and MIP's volumes to the next transfer-function preset. The caller stops the render
// threads around the edit (the scene is read-only while they run) and restarts the pixels.
#pragma once
#include <string>

#include "core/scene/scene.h"

namespace frameless {

// Applies the key ('Z', 'X' or 'B') to the scene's volumes; returns the status line to show, or
// "" when no volume takes that key.
std::string edit_volumes(Scene& scene, int key);

// Whether a key is one of the volume keys and the scene has a volume it applies to.
bool is_volume_key(const Scene& scene, int key);

}  // namespace frameless
