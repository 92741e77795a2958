// Runs `mpirun` jobs of the frameless binary for the cluster tests (localhost, oversubscribed,
// allowed as root), and skips a test with a message where MPI cannot start here.
#pragma once
#include <gtest/gtest.h>

#include <string>

#include "../cli/cli_test_util.h"

namespace frameless::test {

inline const std::string kMpiEnv =
    "OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1 OMPI_MCA_rmaps_base_oversubscribe=1";
inline const std::string kMpirun = kMpiEnv + " timeout 120 mpirun --oversubscribe";

inline CommandResult run_shell(const std::string& cmd) {
  CommandResult r;
  FILE* p = popen((cmd + " 2>&1").c_str(), "r");
  if (!p) return r;
  char buf[4096];
  size_t n;
  while ((n = fread(buf, 1, sizeof buf, p)) > 0) r.output.append(buf, n);
  const int status = pclose(p);
  r.exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status);
  return r;
}

// `mpirun -np N frameless ARGS`.
inline CommandResult run_cluster(int ranks, const std::string& args) {
  return run_shell(std::string(kMpirun) + " -np " + std::to_string(ranks) + " " + FRAMELESS_BINARY +
                   " " + args);
}

// Whether a trivial two-rank job starts (the reason when not).
inline bool mpi_works(std::string& why) {
  static int state = -1;
  static std::string reason;
  if (state < 0) {
    const CommandResult r = run_shell(std::string(kMpirun) + " -np 2 true");
    state = r.exit_code == 0;
    reason = "mpirun cannot start a 2-rank job here (exit " + std::to_string(r.exit_code) + "): " +
             r.output.substr(0, 300);
  }
  why = reason;
  return state == 1;
}

#define FRAMELESS_REQUIRE_MPI()              \
  do {                                       \
    std::string why_;                        \
    if (!::frameless::test::mpi_works(why_)) \
      GTEST_SKIP() << why_;                  \
  } while (0)

}  // namespace frameless::test
