// File helpers every reader shares (loading thread).
#pragma once
#include <string>

#include "core/base/error.h"

namespace frameless {

// Reads a whole file as bytes; the error names the file and the reason.
Result<std::string> read_file_bytes(const std::string& path);

// Lower-case extension including the dot (".obj"), or "" when there is none.
std::string file_extension(const std::string& path);

}  // namespace frameless
