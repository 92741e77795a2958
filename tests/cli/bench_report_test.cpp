// Benchmark report helpers: a run's name becomes a gnuplot title whatever it holds (a quote once
// cut the motion plot's script short, and the PNG was skipped).
#include "bench/bench_report.h"

#include <gtest/gtest.h>

namespace frameless::bench {
namespace {

TEST(BenchReport, GnuplotTextDoublesQuotes) {
  EXPECT_EQ(gnuplot_text("frameless a=0.5 p=1%"), "frameless a=0.5 p=1%");
  EXPECT_EQ(gnuplot_text("conventional's samples"), "conventional''s samples");
  EXPECT_EQ(gnuplot_text("''"), "''''");
  EXPECT_EQ(gnuplot_text(""), "");
  EXPECT_EQ(gnuplot_tic_text("a=0.5 p=1%"), "a=0.5 p=1%%");
}

}  // namespace
}  // namespace frameless::bench
