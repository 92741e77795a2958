#include "display/atomic_file.h"

#include <unistd.h>

#include <atomic>
#include <cerrno>
#include <cstdio>
#include <cstring>
#include <filesystem>

namespace frameless {

std::string temporary_path_for(const std::string& final_path) {
  static std::atomic<unsigned> counter{0};
  return final_path + ".tmp" + std::to_string(getpid()) + "_" + std::to_string(counter++);
}

bool commit_temporary(const std::string& tmp, const std::string& final_path, std::string& error) {
  if (std::rename(tmp.c_str(), final_path.c_str()) != 0) {
    error = final_path + ": cannot rename temporary file: " + std::strerror(errno);
    std::remove(tmp.c_str());
    return false;
  }
  return true;
}

bool directory_writable(const std::string& dir, std::string& error) {
  const std::string d = dir.empty() ? "." : dir;
  std::error_code ec;
  if (!std::filesystem::is_directory(d, ec)) {
    error = d + ": not a directory";
    return false;
  }
  if (access(d.c_str(), W_OK | X_OK) != 0) {
    error = d + ": directory is not writable: " + std::strerror(errno);
    return false;
  }
  return true;
}

}  // namespace frameless
