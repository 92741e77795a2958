// Render threads step aside for interactive threads (EngineConfig::render_nice): every render
// thread runs at the process's nice value plus render_nice, the thread that started the engine
// keeps its own, and 0 changes nothing. Read from /proc/self/task/*/stat (Linux). Out-of-range
// values are rejected.
#include <gtest/gtest.h>

#include <sys/resource.h>
#include <sys/syscall.h>
#include <unistd.h>

#include <chrono>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

#include "frameless/engine.h"
#include "test_shaders.h"

namespace frameless {
namespace {

const Scene kNoScene{};

// The nice value of every thread of this process but the caller (field 19 of its stat line,
// counted after the command name's closing parenthesis).
std::vector<int> other_threads_nice() {
  std::vector<int> out;
  const std::string self = std::to_string(long(syscall(SYS_gettid)));
  for (const auto& entry : std::filesystem::directory_iterator("/proc/self/task")) {
    if (entry.path().filename() == self) continue;
    std::ifstream in(entry.path() / "stat");
    std::string line;
    if (!std::getline(in, line)) continue;  // the thread ended meanwhile
    std::istringstream rest(line.substr(line.rfind(')') + 2));
    std::string field;
    for (int i = 3; i <= 19 && rest >> field; ++i)
      if (i == 19) out.push_back(std::stoi(field));
  }
  return out;
}

int count(const std::vector<int>& v, int x) {
  int n = 0;
  for (int e : v) n += e == x;
  return n;
}

TEST(RenderPriority, RenderThreadsRunNicerThanTheRest) {
#if !defined(__linux__)
  GTEST_SKIP() << "per-thread nice values are Linux's";
#endif
  const int base = getpriority(PRIO_PROCESS, id_t(syscall(SYS_gettid)));
  if (base > 12) GTEST_SKIP() << "the test runs at nice " << base << ": no room for +7";
  for (const int nice : {7, 0}) {
    SCOPED_TRACE(nice);
    EngineConfig c = testing::test_config(32, 32, 3, testing::noisy_shader);
    c.render_nice = nice;
    Engine e(kNoScene, c, testing::camera_at(0));
    const std::vector<int> before = other_threads_nice();
    e.start();
    std::this_thread::sleep_for(std::chrono::milliseconds(100));  // every thread has started
    const std::vector<int> during = other_threads_nice();
    const int mine = getpriority(PRIO_PROCESS, id_t(syscall(SYS_gettid)));
    e.stop();
    ASSERT_FALSE(e.error());
    EXPECT_EQ(mine, base);  // the caller is left alone
    // Three more threads at base + nice (the render threads), the others where they were.
    EXPECT_EQ(count(during, base + nice) - count(before, base + nice), 3);
  }
}

TEST(RenderPriority, OutOfRangeValuesAreRejected) {
  EngineConfig c;
  c.render_nice = -1;
  EXPECT_EQ(validate(c), "render_nice: must be 0..19");
  c.render_nice = 20;
  EXPECT_EQ(validate(c), "render_nice: must be 0..19");
  c.render_nice = 19;
  EXPECT_EQ(validate(c), "");
}

}  // namespace
}  // namespace frameless
