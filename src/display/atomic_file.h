// Write-to-temporary-then-rename helper so no reader ever sees a half-written output; any thread.
#pragma once
#include <string>

namespace frameless {

// A temporary name next to `final_path` (same directory, so rename is atomic).
std::string temporary_path_for(const std::string& final_path);
// Renames tmp to final; on failure removes tmp and returns false with errno-based message.
bool commit_temporary(const std::string& tmp, const std::string& final_path, std::string& error);
// Checks that the directory of `path` exists and is writable (before long work starts).
bool directory_writable(const std::string& dir, std::string& error);

}  // namespace frameless
