#include "frameless/output_commit.h"

namespace frameless {

std::mutex& output_commit_mutex() {
  static std::mutex m;
  return m;
}

std::unique_lock<std::mutex> freeze_output_commits() {
  return std::unique_lock<std::mutex>(output_commit_mutex());
}

}  // namespace frameless
