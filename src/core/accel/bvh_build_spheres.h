// Memory-lean binned-SAH builder of the 8-wide BVH for sphere-only geometry; runs on the loading
// thread (optionally fanning subtrees out through AccelConfig::parallel_for).
#pragma once
#include <cstdint>
#include <vector>

#include "core/accel/accel_types.h"
#include "core/accel/bvh_build.h"
#include "core/geometry/geometry.h"

namespace frameless {

// Builds the same node format as build_bvh8 (every leaf a sphere leaf: info = count |
// kSphereLeafBit, child = index of its first sphere) but in place: a sphere is its own bounds
// (centre +- |radius|; a non-finite one gets a point box at the origin, as in Accel::build), so
// no per-primitive reference array is made. `spheres` and, when it has the same size,
// `materials` are permuted together into leaf order. Extra memory: the nodes being built (in
// 4 MiB blocks that are released while the result is assembled, so the peak is about one BVH
// plus a block) and a few KiB of bins per running split. Requires spheres.size() < 2^32.
//
// Binned SAH as in build_bvh8 (config.sah_bins bins, node children chosen by splitting the
// largest child first, object medians past 32 node levels, so depth * 7 + 1 stays within the
// traversal stack); leaves hold at most config.max_leaf_size spheres. With config.parallel_for
// and more than 65536 spheres, the top splits bin in parallel chunks and the subtrees below them
// are built as independent tasks; the result does not depend on the executor or its order.
Bvh8 build_bvh8_spheres(std::vector<Sphere>& spheres, std::vector<uint16_t>& materials,
                        const AccelConfig& config);

}  // namespace frameless
