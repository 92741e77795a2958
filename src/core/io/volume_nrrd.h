// NRRD volumes (.nrrd, .nhdr + data; teem's format, http://teem.sourceforge.net/nrrd/format.html),
// the format most scientific volumes come in: a strict reader of our own (issue 27).
//
// Accepted: magic NRRD0001..NRRD0005; "field: value" lines up to a blank line (or the end of a
// detached header); '#' comments; "key:=value" lines ignored. Required: type (uint8 / uint16 /
// float under their teem names), dimension 3, sizes (3 positive integers), encoding (raw, gzip);
// endian for 16/32-bit voxels. Optional: spacings, or space directions (their vectors' lengths
// are the spacings); data file (relative to the header's folder; LIST and format strings are
// refused); line skip (lines of the file before the data); byte skip (bytes before the data:
// after decompression for gzip; -1 = the data ends the file, raw only). Descriptive fields
// (content, kinds, space origin, ...) are ignored; unknown fields are errors. The data must hold
// exactly the voxels the sizes say. Raw data in a file, in native byte order and starting at a
// multiple of the voxel size (aligned), is memory-mapped; other data is read (gzip inflated
// incrementally) and swapped where needed into owned storage.
// Errors are one line: "FILE:LINE: field: what is wrong" for the header (LINE counts from 1),
// "FILE: what is wrong" for the data.
#pragma once
#include <memory>
#include <string>

#include "core/base/error.h"
#include "core/volume/volume_grid.h"

namespace frameless {

Result<std::shared_ptr<const VolumeGrid>> read_nrrd(const std::string& path);

// The same for a header with attached data held in memory (the fuzzer, tests); `path` names it
// in errors and `base_dir` resolves a relative "data file".
Result<std::shared_ptr<const VolumeGrid>> decode_nrrd(const std::string& bytes, const std::string& path,
                                                      const std::string& base_dir);

}  // namespace frameless
