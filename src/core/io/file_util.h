// File helpers every reader shares (loading thread).
#pragma once
#include <string>

#include "core/base/error.h"

namespace frameless {

// Reads a whole file as bytes; the error names the file and the reason.
Result<std::string> read_file_bytes(const std::string& path);

// Lower-case extension including the dot (".obj"), or "" when there is none.
std::string file_extension(const std::string& path);

// A reader's error: "path: what", kept on one line (header text quoted in it may hold breaks).
inline Error file_error(const std::string& path, const std::string& what) {
  return Error{one_line(path + ": " + what)};
}

}  // namespace frameless
