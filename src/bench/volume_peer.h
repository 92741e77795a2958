// OpenVDB's own ray tracer (`vdb_render` from Debian's libopenvdb-tools) as the bench-only peer:
// a signed distance field written as an OpenVDB level set (by Debian's python3-openvdb), read by
// frameless from that file and from a raw copy, primary hits only on both sides (vdb_render's
// position shader; frameless's isosurface intersection); and a fog volume through both volume
// shaders (emission-absorption, unlit). Skipped with a message when either tool is absent.
// Control thread only.
#pragma once
#include <string>

#include <nlohmann/json.hpp>

namespace frameless::bench {

// A sphere distance field of n^3 voxels rendered at w x h on `threads` by both: each one's time
// for the frame, rays per second, and how far apart their hit points are (voxels); "skipped"
// says why when the peer cannot run. work_dir receives the files.
nlohmann::json compare_with_vdb_render(int n, int w, int h, int threads, const std::string& work_dir);

// A fog volume of n^3 voxels, extinction 0.1 per voxel at density 1, steps of one voxel: each
// one's time, frameless's volume samples per second (and vdb_render's for the same count), and
// how far apart the two alpha images are.
nlohmann::json compare_fog_with_vdb_render(int n, int w, int h, int threads, const std::string& work_dir);

}  // namespace frameless::bench
