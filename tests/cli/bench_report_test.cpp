// Benchmark report helpers: a run's name becomes a gnuplot title whatever it holds (a quote once
// cut the motion plot's script short, and the PNG was skipped), and a CSV cell stays one cell
// whatever it holds (a scene's path may have commas).
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

TEST(BenchReport, CsvCellsWithCommasQuotesOrBreaksAreQuoted) {
  CsvTable t;
  t.header = {"scene", "value"};
  t.rows = {{"bunny", "1"}, {"a,b.obj", "2"}, {"say \"hi\"", "3"}, {"two\nlines", "4"}};
  EXPECT_EQ(t.text(), "scene,value\nbunny,1\n\"a,b.obj\",2\n\"say \"\"hi\"\"\",3\n\"two\nlines\",4\n");
}

}  // namespace
}  // namespace frameless::bench
