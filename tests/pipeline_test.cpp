// The pipeline as every command runs it (issue 13): each command applies the options it accepts
// through the same code, so a layout scores the same wherever it is measured, and a run's folder
// alone reproduces it (report.json `inputs`).
#include <gtest/gtest.h>

#include <filesystem>
#include <nlohmann/json.hpp>

#include "test_util.hpp"
#include "vantage/error.hpp"
#include "vantage/pipeline.hpp"

namespace vantage {
namespace {

using nlohmann::json;
using test::RunVantage;

std::string Example() {
  return std::string(VANTAGE_SOURCE_DIR) + "/examples/scenes/bin_picking_cell.yaml";
}

json ReadJson(const std::string& path) { return json::parse(test::ReadText(path)); }

// Coverage of the primary result of a report.json.
double PrimaryCoverage(const json& report) {
  return report["results"][report["primary_result"].get<size_t>()]["coverage"].get<double>();
}

// `vantage evaluate` of a constellation, with extra flags: the union's coverage.
double Evaluated(const test::TempDir& dir, const std::string& constellation,
                 const std::string& flags, const std::string& name) {
  const auto run = RunVantage("-q evaluate " + flags + " --constellation " + constellation +
                              " --out " + dir.File(name));
  EXPECT_EQ(run.exit_code, 0) << run.err;
  return ReadJson(dir.File(name + "/report.json"))["results"][0]["coverage"].get<double>();
}

// Bug of issue 13: `evaluate --max-incidence` changed nothing. The filter shrinks what a layout
// sees (a narrower cone of accepted incidence can only drop pixels), and evaluate must measure a
// layout exactly as optimize measured it under the same filter.
TEST(Pipeline, EvaluateAppliesTheQualityFilterAsOptimizeDoes) {
  test::TempDir dir;
  const auto optimize = RunVantage("-q optimize " + Example() +
                                   " -n 2 --method greedy --max-incidence 20 --out " +
                                   dir.File("run20"));
  ASSERT_EQ(optimize.exit_code, 0) << optimize.err;
  const json report = ReadJson(dir.File("run20/report.json"));
  const std::string constellation = dir.File("run20/report.json");
  const double optimized = PrimaryCoverage(report);
  const double plain = report["results"][0]["plain_coverage"].get<double>();
  ASSERT_LT(optimized, plain);  // the filter removes pixels on this scene

  const double given20 = Evaluated(dir, constellation, Example() + " --max-incidence 20", "e20");
  const double inherited = Evaluated(dir, constellation, "", "inherited");
  const double given60 = Evaluated(dir, constellation, Example() + " --max-incidence 60", "e60");
  EXPECT_DOUBLE_EQ(given20, optimized);
  EXPECT_DOUBLE_EQ(inherited, optimized);  // the run's filter, from its inputs
  EXPECT_GT(given60, given20);
  EXPECT_LE(given60, plain);
}

// Bug of issue 13: --refine traced the new poses without the run's quality filter, so refined
// candidates were scored unfiltered against filtered ones. The refined layout's reported coverage
// must be what the filter gives when the same sensors are observed again.
TEST(Pipeline, RefineScoresNewPosesWithTheRunsQualityFilter) {
  test::TempDir dir;
  const auto optimize =
      RunVantage("-q optimize " + Example() +
                 " -n 2 --method greedy --refine --max-incidence 60 --out " + dir.File("run"));
  ASSERT_EQ(optimize.exit_code, 0) << optimize.err;
  const json report = ReadJson(dir.File("run/report.json"));
  ASSERT_TRUE(report.contains("refinement"));
  const json& refined = report["results"][report["refinement"]["result"].get<size_t>()];
  EXPECT_EQ(refined["method"], "refined");
  EXPECT_EQ(report["primary_result"], report["refinement"]["result"]);
  const double again = Evaluated(dir, dir.File("run/report.json"), "", "again");
  EXPECT_DOUBLE_EQ(refined["coverage"].get<double>(), again);
  EXPECT_LE(refined["coverage"].get<double>(), refined["plain_coverage"].get<double>());
  // Never worse than what it refines, under the same filter.
  EXPECT_GE(refined["coverage"].get<double>(), report["results"][0]["coverage"].get<double>());
}

// report.json `inputs`: the options as given, paths absolute, so that the folder reproduces the
// run from anywhere.
TEST(Pipeline, ReportRecordsTheRunsInputs) {
  test::TempDir dir;
  const auto optimize =
      RunVantage("-q optimize " + Example() +
                 " -n 2 --method local --cell-size 0.006 --max-depth-noise 3 --seed 5 --out " +
                 dir.File("run"));
  ASSERT_EQ(optimize.exit_code, 0) << optimize.err;
  const json inputs = ReadJson(dir.File("run/report.json"))["inputs"];
  EXPECT_EQ(inputs["command"], "optimize");
  EXPECT_TRUE(std::filesystem::path(inputs["scene"].get<std::string>()).is_absolute());
  EXPECT_TRUE(std::filesystem::equivalent(inputs["scene"].get<std::string>(), Example()));
  EXPECT_EQ(inputs["cell_size"], 0.006);
  EXPECT_EQ(inputs["seed"], 5);
  EXPECT_EQ(inputs["n"], 2);
  EXPECT_EQ(inputs["method"], "local");
  EXPECT_DOUBLE_EQ(inputs["max_depth_noise_mm"].get<double>(), 3.0);
  EXPECT_FALSE(inputs.contains("max_incidence_deg"));
  EXPECT_EQ(inputs["cull"], true);

  // Evaluated from the folder alone, with the run's cell size and filter: the run's own number.
  const double again = Evaluated(dir, dir.File("run/report.json"), "", "again");
  EXPECT_DOUBLE_EQ(again, PrimaryCoverage(ReadJson(dir.File("run/report.json"))));
  EXPECT_EQ(ReadJson(dir.File("again/report.json"))["cell_size"], 0.006);
}

// Selection problems are found before any ray is cast and blamed on the option given, or on the
// scene when its own settings are at fault: one validation, no re-merging.
TEST(Pipeline, ResolveSelectionBlamesTheOptionGivenElseTheScene) {
  std::vector<Candidate> candidates(3);
  SelectionSettings scene;
  scene.n = 2;
  SelectionRequest request;
  request.k = 3;  // n = 2 from the scene is below k = 3: --k is what was given
  try {
    ResolveSelection(scene, request, 1, candidates, "cell.yaml");
    FAIL() << "k above n accepted";
  } catch (const InputError& e) {
    EXPECT_EQ(std::string(e.what()).rfind("--k: n = 2 is below k = 3", 0), 0u) << e.what();
  }
  scene.n = 5;  // the scene's own n is out of range, and no flag touches it
  try {
    ResolveSelection(scene, {}, 1, candidates, "cell.yaml");
    FAIL() << "n above the candidates accepted";
  } catch (const InputError& e) {
    EXPECT_EQ(std::string(e.what()).rfind("cell.yaml: n = 5 is out of range", 0), 0u) << e.what();
  }
  request = {};
  request.n = 3;  // the request replaces the scene's n and is valid
  const SelectOptions options = ResolveSelection(scene, request, 9, candidates, "cell.yaml");
  EXPECT_EQ(options.n, 3);
  EXPECT_EQ(options.seed, 9u);
  EXPECT_EQ(options.method, Method::kAll);
}

}  // namespace
}  // namespace vantage
