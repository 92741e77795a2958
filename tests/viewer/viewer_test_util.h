// Helpers of the viewer's tests: a scratch folder, running the viewer under Xvfb with a script,
// and comparing window screenshots (EXR files holding the window's sRGB values).
#pragma once
#include <gtest/gtest.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <initializer_list>
#include <iterator>
#include <set>
#include <string>
#include <vector>

#include "display/exr_io.h"

#if defined(__has_feature)
#if __has_feature(address_sanitizer)  // clang's spelling (the test stage builds with clang)
#define FRAMELESS_TEST_ASAN 1
#endif
#endif
#if defined(__SANITIZE_ADDRESS__) || defined(FRAMELESS_TEST_ASAN)
// Under ASan the viewer child's only leaks are in Mesa's DRI driver, which is unloaded at exit
// so LeakSanitizer cannot name it (our own allocations are checked by every other test).
inline constexpr const char* kChildLeakCheck = "ASAN_OPTIONS=detect_leaks=0 ";
#else
inline constexpr const char* kChildLeakCheck = "";
#endif

namespace frameless {
namespace fs = std::filesystem;

inline fs::path scratch() {
  const fs::path p = fs::temp_directory_path() / ("frameless_viewer_test_" + std::to_string(getpid()));
  fs::create_directories(p);
  return p;
}

inline std::string slurp(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  return std::string(std::istreambuf_iterator<char>(in), {});
}

inline bool have(const char* tool) {
  return std::system((std::string("command -v ") + tool + " >/dev/null 2>&1").c_str()) == 0;
}

// Runs `frameless view ARGS --script SCRIPT` under Xvfb; the exit status, the log in *log.
inline int run_viewer_script(const std::string& args, const std::string& script, const fs::path& dir,
                             std::string* log) {
  std::ofstream(dir / "script.txt") << script;
  const std::string cmd = std::string(kChildLeakCheck) + "xvfb-run -a -s '-screen 0 800x600x24' " +
                          std::string(FRAMELESS_BINARY) + " view " + args + " --script " +
                          (dir / "script.txt").string() + " > " + (dir / "log.txt").string() + " 2>&1";
  const int status = std::system(cmd.c_str());
  *log = slurp(dir / "log.txt");
  return status;
}

// Distinct colours of a window screenshot.
inline size_t distinct_colours(const ExrImage& img) {
  std::set<uint32_t> colours;
  for (size_t i = 0; i < img.channels.at("R").size(); ++i)
    colours.insert(uint32_t(img.channels.at("R")[i] * 255) << 16 |
                   uint32_t(img.channels.at("G")[i] * 255) << 8 | uint32_t(img.channels.at("B")[i] * 255));
  return colours.size();
}

// Mean absolute difference of two screenshots over columns [x0, x1) (all columns by default).
inline double mean_difference(const ExrImage& a, const ExrImage& b, int x0 = 0, int x1 = 1 << 30) {
  double sum = 0;
  size_t n = 0;
  x1 = std::min(x1, a.width);
  for (const char* c : {"R", "G", "B"})
    for (int y = 0; y < a.height; ++y)
      for (int x = x0; x < x1; ++x, ++n) {
        const size_t i = size_t(y) * size_t(a.width) + size_t(x);
        sum += std::abs(a.channels.at(c)[i] - b.channels.at(c)[i]);
      }
  return n ? sum / double(n) : 0.0;
}

// Mean of one channel over columns [x0, x1).
inline double channel_mean(const ExrImage& a, const char* c, int x0, int x1) {
  double sum = 0;
  size_t n = 0;
  for (int y = 0; y < a.height; ++y)
    for (int x = x0; x < std::min(x1, a.width); ++x, ++n) sum += a.channels.at(c)[size_t(y) * size_t(a.width) + size_t(x)];
  return n ? sum / double(n) : 0.0;
}

// The averages of `channels` (summed) over `block`-pixel squares, whole squares only, row by row.
inline std::vector<double> block_means(const ExrImage& e, int block, std::initializer_list<const char*> channels) {
  std::vector<double> out;
  for (int by = 0; by + block <= e.height; by += block)
    for (int bx = 0; bx + block <= e.width; bx += block) {
      double sum = 0;
      for (const char* c : channels)
        for (int y = by; y < by + block; ++y)
          for (int x = bx; x < bx + block; ++x) sum += e.channels.at(c)[size_t(y) * size_t(e.width) + size_t(x)];
      out.push_back(sum / double(block * block));
    }
  return out;
}

// Mean absolute difference of the two screenshots' block averages, channel by channel: a path
// tracer's per-pixel noise shrinks by the block's side, while a change of scene, view or lighting
// moves the averages as it moves the pixels.
inline double block_difference(const ExrImage& a, const ExrImage& b, int block) {
  double sum = 0;
  size_t n = 0;
  for (const char* c : {"R", "G", "B"}) {
    const std::vector<double> va = block_means(a, block, {c}), vb = block_means(b, block, {c});
    for (size_t i = 0; i < va.size(); ++i, ++n) sum += std::abs(va[i] - vb[i]);
  }
  return n ? sum / double(n) : 0.0;
}

// Pearson correlation of the two screenshots' block averages of R + G + B: near 1 for the same
// view whatever its brightness or noise, lower when the content moved.
inline double block_correlation(const ExrImage& a, const ExrImage& b, int block) {
  const std::vector<double> va = block_means(a, block, {"R", "G", "B"}), vb = block_means(b, block, {"R", "G", "B"});
  const double n = double(va.size());
  double ma = 0, mb = 0;
  for (size_t i = 0; i < va.size(); ++i) ma += va[i] / n, mb += vb[i] / n;
  double sab = 0, saa = 0, sbb = 0;
  for (size_t i = 0; i < va.size(); ++i)
    sab += (va[i] - ma) * (vb[i] - mb), saa += (va[i] - ma) * (va[i] - ma), sbb += (vb[i] - mb) * (vb[i] - mb);
  return saa > 0 && sbb > 0 ? sab / std::sqrt(saa * sbb) : 0.0;
}

struct ScratchCleanup : ::testing::Environment {
  void TearDown() override { fs::remove_all(scratch()); }
};

}  // namespace frameless
