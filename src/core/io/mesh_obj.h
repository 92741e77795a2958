// Wavefront OBJ pieces shared by the plain mesh reader (mesh_obj.cpp) and the OBJ+MTL reader
// (mesh_obj_mtl.cpp); loading thread only.
#pragma once
#include <cstdint>
#include <string>
#include <vector>

#include "core/base/error.h"
#include "core/io/mesh_readers.h"

namespace frameless {

inline constexpr uint16_t kNoObjMaterial = 0xffff;  // face_material of faces before any usemtl

// An OBJ after our line scan. `text` is what tinyobjloader gets: the same number of lines, only
// v, vn, vt and f statements rebuilt from their checked tokens, and "o m<K>" where the file said
// "usemtl" of material K; every other statement (vw, vp, l, p, curv, cstype, g, s, ...) becomes a
// blank line, so tinyobjloader never parses what we do not use.
struct ObjScan {
  struct Library {
    size_t line = 0;
    std::string names;  // the rest of the mtllib line, trimmed
  };
  std::string text;
  std::vector<std::string> materials;  // usemtl names, in order of first use (K above)
  std::vector<Library> libraries;
};

// Checks what tinyobjloader lets through (non-finite numbers, out-of-range v/vt/vn indices,
// NUL bytes); errors are one line, "PATH:LINE: what".
Result<ObjScan> scan_obj(const std::string& text, const std::string& path);

// Parses a scanned OBJ with tinyobjloader (triangulated). Plain: one vertex per position with the
// first normal a face gives it, no uvs. with_materials: one vertex per distinct (v, vt, vn) triple
// so that uvs and normals are per vertex, and face_material indexes scan.materials
// (kNoObjMaterial for faces before any usemtl); materials and textures stay empty.
Result<MeshData> build_obj_mesh(const ObjScan& scan, const std::string& path, bool with_materials);

// OBJ text with its MTL libraries (read from disk relative to path's folder); a file without
// mtllib gives the plain mesh of parse_obj.
Result<MeshData> parse_obj_with_materials(const std::string& text, const std::string& path,
                                          ImageCache& images);

}  // namespace frameless
