// `frameless bench rays --json` end to end on small images: the work per ray (8-wide nodes
// entered, primitives tested) is reported for every kind of ray, and the BVH keeps it to a tiny
// fraction of the scene; several scenes make one report; bad arguments are one line each. (No
// timing is asserted.)
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>
#include <vector>

#include "cli_test_util.h"

namespace frameless::test {
namespace {

TEST(BenchRaysCli, JsonReportsTheWorkOfEachKindOfRay) {
  const CommandResult r =
      run_frameless("bench rays spheres:20000 --size 64x64 --reps 1 --threads 1 --json --no-embree");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  const nlohmann::json j = nlohmann::json::parse(r.output, nullptr, false);
  ASSERT_FALSE(j.is_discarded()) << r.output;
  ASSERT_EQ(j["prims"].get<double>(), 20000.0);
  // Build times, serial and parallel (the best of the repetitions' builds).
  EXPECT_GT(j.value("build_ms", 0.0), 0.0) << r.output;
  EXPECT_GT(j.value("build_ms_parallel", 0.0), 0.0) << r.output;
  for (const char* kind : {"primary", "shadow", "bounce", "bounce_shadow"}) {
    ASSERT_TRUE(j["work_per_ray"].contains(kind)) << r.output;
    const double nodes = j["work_per_ray"][kind]["nodes"], prims = j["work_per_ray"][kind]["prims"];
    EXPECT_GE(nodes, 1.0) << kind;  // every ray enters the root
    EXPECT_GT(prims, 0.0) << kind;
    // A tree over 20000 spheres: a ray visits a few dozen nodes and tests a few dozen spheres,
    // not a linear share of them.
    EXPECT_LT(nodes, 60.0) << kind;
    EXPECT_LT(prims, 200.0) << kind;
  }
}

// With Embree in the build, instanced scenes are instanced on Embree's side too (its own instance
// geometry over each mesh's scene), and the two agree on what each primary ray hits: the same
// instance and primitive. A transform handed over in the wrong layout, or an instance numbered
// apart from ours, breaks the agreement.
// A run's JSON (discarded when the run failed, which is reported).
nlohmann::json run_json(const std::string& args) {
  const CommandResult r = run_frameless(args);
  EXPECT_EQ(r.exit_code, 0) << r.output;
  const nlohmann::json j = nlohmann::json::parse(r.output, nullptr, false);
  EXPECT_FALSE(j.is_discarded()) << r.output;
  return j;
}

TEST(BenchRaysCli, EmbreeSeesTheSameInstances) {
  const nlohmann::json j = run_json("bench rays sunflowers:1 --opaque --size 48x48 --reps 1 --threads 1 --json");
  ASSERT_FALSE(j.is_discarded());
  if (!j.contains("embree")) GTEST_SKIP() << "this build has no Embree (tools/install-deps.sh --bench)";
  ASSERT_GT(j["instances"].get<int>(), 1);
  EXPECT_GT(j["primary_hit_fraction"].get<double>(), 0.5);
  // Rays exactly on a shared edge may go to either triangle: allow one in a hundred.
  EXPECT_GE(j["embree"]["primary_agreement"].get<double>(), 0.99);
  EXPECT_GE(j["embree"]["shadow_agreement"].get<double>(), 0.99);
}

// --embree-robust gives Embree's scenes its accurate mode: the run says which mode it measured
// (in the JSON, the report's settings and the table), and the robust Embree agrees with us as the
// fast one does.
TEST(BenchRaysCli, EmbreeRobustModeIsMeasuredAndSaid) {
  const nlohmann::json f = run_json("bench rays bunny --opaque --size 48x48 --reps 1 --threads 1 --json");
  ASSERT_FALSE(f.is_discarded());
  if (!f.contains("embree")) GTEST_SKIP() << "this build has no Embree (tools/install-deps.sh --bench)";
  EXPECT_FALSE(f["embree"]["robust"].get<bool>());
  const nlohmann::json j = run_json("bench rays bunny --opaque --size 48x48 --reps 1 --threads 1 --json --embree-robust");
  ASSERT_FALSE(j.is_discarded());
  EXPECT_TRUE(j["embree"]["robust"].get<bool>());
  EXPECT_GE(j["embree"]["primary_agreement"].get<double>(), 0.99);
  EXPECT_GE(j["embree"]["shadow_agreement"].get<double>(), 0.99);
  EXPECT_GT(j["embree"]["ratio_primary_vs_intersect1_1t"].get<double>(), 0.0);
  const CommandResult table = run_frameless("bench rays bunny --opaque --size 32x32 --reps 1 --threads 1 --embree-robust");
  ASSERT_EQ(table.exit_code, 0) << table.output;
  EXPECT_NE(table.output.find(" robust, medium quality, build"), std::string::npos) << table.output;
  const auto dir = fresh_dir("rays_robust");
  const CommandResult report = run_frameless("bench rays bunny --opaque --size 32x32 --reps 1 --threads 1 --embree-robust --out " +
                                             dir.string());
  ASSERT_EQ(report.exit_code, 0) << report.output;
  std::ifstream in(dir / "rays.json");
  const nlohmann::json saved = nlohmann::json::parse(in, nullptr, false);
  ASSERT_FALSE(saved.is_discarded());
  EXPECT_TRUE(saved["settings"]["embree_robust"].get<bool>());
  std::filesystem::remove_all(dir);
}

// Each figure's worst repetition is reported beside its best (for ours and, with Embree in the
// build, for Embree): never above the best, and the same figure with one repetition.
TEST(BenchRaysCli, TheWorstRepetitionIsReportedBesideTheBest) {
  for (const int reps : {1, 3}) {
    const nlohmann::json j =
        run_json("bench rays spheres:5000 --size 48x48 --threads 1 --json --reps " + std::to_string(reps));
    ASSERT_FALSE(j.is_discarded());
    std::vector<const nlohmann::json*> sides = {&j};
    if (j.contains("embree")) sides.push_back(&j["embree"]);
    for (const nlohmann::json* side : sides) {
      int spread = 0;  // figures whose repetitions differ (three clock readings are never all equal)
      for (const char* kind : {"primary", "shadow", "bounce", "bounce_shadow"}) {
        const std::string best = std::string(kind) + "_mrays_per_s_1t", worst = best + "_worst";
        ASSERT_TRUE(side->contains(best) && side->contains(worst)) << worst;
        const double b = (*side)[best].get<double>(), w = (*side)[worst].get<double>();
        EXPECT_GT(w, 0.0) << worst;
        if (reps == 1)
          EXPECT_EQ(w, b) << worst;
        else
          EXPECT_LE(w, b) << worst;
        spread += w < b;
      }
      if (reps > 1) EXPECT_GT(spread, 0);
    }
  }
  const CommandResult table = run_frameless("bench rays spheres:5000 --size 32x32 --threads 1 --reps 2");
  ASSERT_EQ(table.exit_code, 0) << table.output;
  if (table.output.find("agreement with embree") != std::string::npos)
    EXPECT_NE(table.output.find("spread over 2 repetitions"), std::string::npos) << table.output;
}

// --embree-quality builds Embree's scenes at the quality named, and the run says which: high
// (spatial splits) duplicates some of the bunny's triangle references, so Embree holds more
// memory than at its default medium quality, for the same hits. With the quality not handed to
// Embree the two sizes are equal.
TEST(BenchRaysCli, EmbreeBuildQualityIsMeasuredAndSaid) {
  const std::string args = "bench rays bunny --opaque --size 32x32 --reps 1 --threads 1 --json";
  const nlohmann::json medium = run_json(args);
  ASSERT_FALSE(medium.is_discarded());
  if (!medium.contains("embree")) GTEST_SKIP() << "this build has no Embree (tools/install-deps.sh --bench)";
  EXPECT_EQ(medium["embree"]["build_quality"].get<std::string>(), "medium");
  const nlohmann::json high = run_json(args + " --embree-quality high");
  ASSERT_FALSE(high.is_discarded());
  EXPECT_EQ(high["embree"]["build_quality"].get<std::string>(), "high");
  EXPECT_GT(high["embree"]["bytes"].get<double>(), medium["embree"]["bytes"].get<double>());
  EXPECT_GE(high["embree"]["primary_agreement"].get<double>(), 0.99);
  EXPECT_GE(high["embree"]["shadow_agreement"].get<double>(), 0.99);
  const CommandResult table =
      run_frameless("bench rays bunny --opaque --size 32x32 --reps 1 --threads 1 --embree-robust --embree-quality high");
  ASSERT_EQ(table.exit_code, 0) << table.output;
  EXPECT_NE(table.output.find(" robust, high quality, build"), std::string::npos) << table.output;
  const auto dir = fresh_dir("rays_quality");
  const CommandResult report =
      run_frameless("bench rays bunny spheres:2000 --opaque --size 32x32 --reps 1 --threads 1 --embree-quality low --out " +
                    dir.string());
  ASSERT_EQ(report.exit_code, 0) << report.output;
  EXPECT_NE(report.output.find("ours / Embree (low build quality)"), std::string::npos) << report.output;
  std::ifstream in(dir / "rays.json");
  const nlohmann::json saved = nlohmann::json::parse(in, nullptr, false);
  ASSERT_FALSE(saved.is_discarded());
  EXPECT_EQ(saved["settings"]["embree_quality"].get<std::string>(), "low");
  std::filesystem::remove_all(dir);
}

// The lines of a text file.
std::vector<std::string> file_lines(const std::filesystem::path& path) {
  std::ifstream in(path);
  std::vector<std::string> lines;
  for (std::string line; std::getline(in, line);) lines.push_back(line);
  return lines;
}

std::vector<std::string> split(const std::string& line, char separator) {
  std::vector<std::string> cells;
  std::stringstream in(line);
  for (std::string cell; std::getline(in, cell, separator);) cells.push_back(cell);
  return cells;
}

// Several scenes are measured one after the other into one report: --json gives every run, --out
// writes them as rays.json (with the machine and build), rays.csv (a row per scene and kind of
// ray, with its rays and rates) and the plot's data (a scene and ten figures a line), each scene
// under its own name, and the summary table names every scene.
TEST(BenchRaysCli, SeveralScenesMakeOneReport) {
  const std::string args = "bench rays spheres:2000 soup:500 --size 24x24 --reps 1 --threads 1 --no-embree";
  const CommandResult r = run_frameless(args + " --json");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  const nlohmann::json j = nlohmann::json::parse(r.output, nullptr, false);
  ASSERT_FALSE(j.is_discarded()) << r.output;
  ASSERT_EQ(j["runs"].size(), 2u) << r.output;
  EXPECT_EQ(j["runs"][0]["scene"], "spheres:2000");
  EXPECT_EQ(j["runs"][0]["spheres"].get<int>(), 2000);
  EXPECT_EQ(j["runs"][1]["scene"], "soup:500");
  EXPECT_EQ(j["runs"][1]["triangles"].get<int>(), 500);

  const std::filesystem::path dir = fresh_dir("bench_rays_out");
  const CommandResult w = run_frameless(args + " --out " + dir.string());
  ASSERT_EQ(w.exit_code, 0) << w.output;
  const size_t summary = w.output.find("Mrays/s, 1 thread:");
  ASSERT_NE(summary, std::string::npos) << w.output;
  EXPECT_NE(w.output.find("\nsoup:500 ", summary), std::string::npos) << w.output;
  std::ifstream json_file(dir / "rays.json");
  const nlohmann::json report = nlohmann::json::parse(json_file, nullptr, false);
  ASSERT_FALSE(report.is_discarded());
  ASSERT_EQ(report["runs"].size(), 2u);
  EXPECT_TRUE(report.contains("machine")) << report.dump();
  EXPECT_EQ(report["runs"][1]["scene"], "soup:500");
  EXPECT_FALSE(report["settings"]["embree"].get<bool>());

  const std::vector<std::string> csv = file_lines(dir / "rays.csv");
  ASSERT_EQ(csv.size(), 1u + 2u * 5u);  // the header, five kinds of ray a scene
  EXPECT_EQ(csv[0], "scene,kind,rays,mrays_per_s_1t,mrays_per_s,ratio_to_embree_1t,ratio_to_embree");
  const std::vector<std::string> soup_primary = split(csv[6], ',');
  ASSERT_EQ(soup_primary.size(), 7u) << csv[6];
  EXPECT_EQ(soup_primary[0], "soup:500");
  EXPECT_EQ(soup_primary[1], "primary");
  EXPECT_EQ(soup_primary[2], "576");  // 24 x 24 camera rays
  EXPECT_GT(std::stod(soup_primary[3]), 0.0) << csv[6];
  EXPECT_EQ(soup_primary[5], "nan");  // no Embree, no ratio

  const std::vector<std::string> dat = file_lines(dir / "rays.dat");
  ASSERT_EQ(dat.size(), 3u);  // a comment, then a line a scene
  for (size_t i = 1; i < dat.size(); ++i) EXPECT_EQ(split(dat[i], '\t').size(), 11u) << dat[i];
  EXPECT_EQ(split(dat[2], '\t')[0], "soup:500");
  if (std::filesystem::exists(dir / "rays.png")) EXPECT_GT(std::filesystem::file_size(dir / "rays.png"), 1000u);
  std::filesystem::remove_all(dir);
}

// With Embree in the build, every scene's row has its ratios to Embree, and the report says so.
TEST(BenchRaysCli, WithEmbreeTheReportHasRatios) {
  const std::filesystem::path dir = fresh_dir("bench_rays_embree");
  const CommandResult r =
      run_frameless("bench rays spheres:2000 soup:500 --size 24x24 --reps 1 --threads 1 --out " + dir.string());
  ASSERT_EQ(r.exit_code, 0) << r.output;
  std::ifstream json_file(dir / "rays.json");
  const nlohmann::json report = nlohmann::json::parse(json_file, nullptr, false);
  ASSERT_FALSE(report.is_discarded());
  if (!report["runs"][0].contains("embree")) GTEST_SKIP() << "this build has no Embree (tools/install-deps.sh --bench)";
  EXPECT_TRUE(report["settings"]["embree"].get<bool>());
  EXPECT_NE(r.output.find("ours / Embree, 1 thread:"), std::string::npos) << r.output;
  const std::vector<std::string> csv = file_lines(dir / "rays.csv");
  ASSERT_EQ(csv.size(), 11u);
  for (size_t i = 1; i < csv.size(); ++i) {
    const std::vector<std::string> cells = split(csv[i], ',');
    ASSERT_EQ(cells.size(), 7u) << csv[i];
    if (cells[2] == "0") continue;  // a kind without rays has no ratio
    EXPECT_GT(std::stod(cells[5]), 0.0) << csv[i];
  }
  std::filesystem::remove_all(dir);
}

// A bad scene anywhere in the list, or an output folder that cannot be one, is one line before
// anything is measured, and leaves no report.
TEST(BenchRaysCli, BadScenesAndFoldersAreOneLineAndLeaveNoReport) {
  const std::filesystem::path dir = fresh_dir("bench_rays_bad");
  for (const std::string spec : {"no_such_scene.json", "no_such_model.ply", "no_such_builtin"}) {
    const CommandResult r = run_frameless("bench rays spheres:2000 " + spec +
                                          " --size 16x16 --reps 1 --threads 1 --no-embree --json --out " + dir.string());
    EXPECT_NE(r.exit_code, 0) << spec;
    EXPECT_EQ(count_lines(r.output), 1) << spec << ": " << r.output;
    EXPECT_FALSE(std::filesystem::exists(dir / "rays.json")) << spec;
    EXPECT_FALSE(std::filesystem::exists(dir / "rays.csv")) << spec;
  }
  std::ofstream(dir / "a_file") << "not a folder\n";
  const CommandResult r = run_frameless("bench rays spheres:2000 --size 16x16 --reps 1 --no-embree --out " +
                                        (dir / "a_file").string());
  EXPECT_NE(r.exit_code, 0);
  EXPECT_EQ(count_lines(r.output), 1) << r.output;
  EXPECT_EQ(r.output.find("scene spheres"), std::string::npos) << "measured before the folder was checked";
  std::filesystem::remove_all(dir);
}

TEST(BenchRaysCli, BadArgumentsAreOneLine) {
  for (const char* args : {"bench rays --reps 0", "bench rays --size 0x5", "bench rays --threads -2",
                           "bench rays no_such_scene.json", "bench rays --embree-quality best"}) {
    const CommandResult r = run_frameless(args);
    EXPECT_NE(r.exit_code, 0) << args;
    EXPECT_EQ(count_lines(r.output), 1) << args << ": " << r.output;
  }
}

}  // namespace
}  // namespace frameless::test
