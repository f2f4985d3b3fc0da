// Aggregations over scene states end to end (issue 42): `--over-states sum` on the example's
// states scene and on the same scene with a state that brings a second target (states of
// different sizes), `--over-parts sum` refused; `--over-parts` with states, one aggregation over
// every (state, part) group when both flags ask the same one, two different ones refused.
#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "test_util.hpp"

namespace vantage {
namespace {

using nlohmann::json;
using test::RunVantage;

std::string StatesScene() {
  return std::string(VANTAGE_SOURCE_DIR) + "/examples/scenes/bin_picking_states.yaml";
}

json Report(const std::string& out_dir) {
  return json::parse(test::ReadText(out_dir + "/report.json"));
}

// The example's states scene with a fourth state that adds a second target part beside the
// motor: states of different sizes (1332, 1332, 1332, 2226 cells), the last of two parts.
std::string SceneWithASpareState(const test::TempDir& dir) {
  std::string text = test::ReadText(StatesScene());
  const std::string mesh = "../meshes/";
  text.replace(text.find(mesh), mesh.size(), std::string(VANTAGE_SOURCE_DIR) + "/examples/meshes/");
  text += "  - name: spare                  # a second part beside the motor\n"
          "    add:\n"
          "      - {name: spare, role: target, box: {size: [0.08, 0.06, 0.05]}, "
          "pose: {xyz: [0.11, -0.07, 0.775]}}\n";
  const std::string scene = dir.File("states.yaml");
  test::WriteText(scene, text);
  return scene;
}

// The sum from the report's own per-state coverages and state sizes: Σ f_s |R_s| / Σ |R_s|.
double SumOfStates(const json& report, const json& result) {
  double cells = 0, all = 0;
  const json& states = report["states"]["states"];
  for (size_t s = 0; s < states.size(); ++s) {
    const auto r = states[s]["reference_voxels"].get<double>();
    cells += result["state_coverage"][s].get<double>() * r;
    all += r;
  }
  return cells / all;
}

// The example's states are all 1332 cells: the sum is the mean, result for result.
TEST(StatesSumCli, ExampleStatesOfEqualSizeGiveTheMeansResults) {
  test::TempDir dir;
  const auto sum = RunVantage("optimize " + StatesScene() + " --over-states sum --out " +
                              dir.File("sum"));
  ASSERT_EQ(sum.exit_code, 0) << sum.err;
  EXPECT_NE(sum.out.find("sum over 3 states"), std::string::npos) << sum.out;
  const auto mean = RunVantage("optimize " + StatesScene() + " --out " + dir.File("mean"));
  ASSERT_EQ(mean.exit_code, 0) << mean.err;
  const json s = Report(dir.File("sum"));
  const json m = Report(dir.File("mean"));
  EXPECT_EQ(s["states"]["over"], "sum");
  EXPECT_EQ(s["inputs"]["over_states"], "sum");
  ASSERT_EQ(s["results"].size(), m["results"].size());
  for (size_t i = 0; i < s["results"].size(); ++i) {
    const json& a = s["results"][i];
    const json& b = m["results"][i];
    SCOPED_TRACE(a["method"].get<std::string>() + " n " + std::to_string(a["n"].get<int>()));
    EXPECT_EQ(a["method"], b["method"]);
    EXPECT_EQ(a["sensors"], b["sensors"]);
    EXPECT_NEAR(a["coverage"].get<double>(), b["coverage"].get<double>(), 1e-12);
    EXPECT_NEAR(a["coverage"].get<double>(), SumOfStates(s, a), 1e-12);
  }
}

// A state that brings a second target part: the states differ in size, and exact's answer for
// the sum is at least as good, counted as the sum, as exact's for the mean (and the reverse).
TEST(StatesSumCli, StatesOfDifferentSizesCountEveryCellAlike) {
  test::TempDir dir;
  const std::string scene = SceneWithASpareState(dir);
  json reports[2];
  const char* overs[2] = {"sum", "mean"};
  for (int o = 0; o < 2; ++o) {
    const std::string out = dir.File(overs[o]);
    const auto run = RunVantage("optimize " + scene + " -n 2 --method exact --over-states " +
                                overs[o] + " --out " + out);
    ASSERT_EQ(run.exit_code, 0) << run.err;
    reports[o] = Report(out);
  }
  const json& states = reports[0]["states"]["states"];
  ASSERT_EQ(states.size(), 4u);
  EXPECT_GT(states[3]["reference_voxels"].get<int>(), states[0]["reference_voxels"].get<int>());
  const json& sum = reports[0]["results"].back();
  const json& mean = reports[1]["results"].back();
  EXPECT_EQ(sum["method"], "exact");
  EXPECT_EQ(sum["optimal"], true);
  EXPECT_NEAR(sum["coverage"].get<double>(), SumOfStates(reports[0], sum), 1e-12);
  EXPECT_GE(sum["upper_bound"].get<double>() + 1e-12, sum["coverage"].get<double>());
  // Each optimum is at least the other's answer counted its way.
  EXPECT_GE(sum["coverage"].get<double>() + 1e-12, SumOfStates(reports[1], mean));
  double sum_as_mean = 0;
  for (const json& f : sum["state_coverage"]) sum_as_mean += f.get<double>();
  sum_as_mean /= static_cast<double>(states.size());
  EXPECT_GE(mean["coverage"].get<double>() + 1e-12, sum_as_mean);
}

TEST(StatesSumCli, OverPartsSumIsRefusedAsPlainCoverage) {
  test::TempDir dir;
  const std::string scene =
      std::string(VANTAGE_SOURCE_DIR) + "/examples/scenes/bin_picking_cell.yaml";
  const auto run = RunVantage("optimize " + scene + " --over-parts sum --out " + dir.File("o"));
  EXPECT_EQ(run.exit_code, 2);
  EXPECT_NE(run.err.find("--over-parts"), std::string::npos) << run.err;
  EXPECT_NE(run.err.find("drop --over-parts"), std::string::npos) << run.err;
}

// The example's states hold one target part each: every group is a whole state, so the parts'
// aggregation over the states is the states' own, result for result.
TEST(OverPartsStatesCli, OnePartPerStateIsTheStatesAggregation) {
  test::TempDir dir;
  for (const std::string over : {"min", "mean"}) {
    SCOPED_TRACE(over);
    const auto parts = RunVantage("optimize " + StatesScene() + " -n 2 --over-parts " + over +
                                  " --out " + dir.File("parts_" + over));
    ASSERT_EQ(parts.exit_code, 0) << parts.err;
    EXPECT_NE(parts.out.find("of every state's target parts' coverages"), std::string::npos)
        << parts.out;
    const auto states = RunVantage("optimize " + StatesScene() + " -n 2 --over-states " + over +
                                   " --out " + dir.File("states_" + over));
    ASSERT_EQ(states.exit_code, 0) << states.err;
    const json p = Report(dir.File("parts_" + over));
    const json s = Report(dir.File("states_" + over));
    EXPECT_EQ(p["states"]["over"], over);
    EXPECT_EQ(p["inputs"]["over_parts"], over);
    ASSERT_EQ(p["results"].size(), s["results"].size());
    for (size_t i = 0; i < p["results"].size(); ++i) {
      const json& a = p["results"][i];
      const json& b = s["results"][i];
      SCOPED_TRACE(a["method"].get<std::string>() + " n " + std::to_string(a["n"].get<int>()));
      EXPECT_EQ(a["sensors"], b["sensors"]);
      EXPECT_NEAR(a["coverage"].get<double>(), b["coverage"].get<double>(), 1e-12);
      EXPECT_EQ(a["state_coverage"], b["state_coverage"]);
    }
  }
}

// A state that brings a second part: five groups (the four states' motor, the spare). The worst
// group is at most every state's coverage (a state's is its parts' cell-weighted mean), and the
// states' own optimum (--over-states min alone) is at least this layout's worst state.
TEST(OverPartsStatesCli, SeveralPartsPerStateRunOverEveryGroup) {
  test::TempDir dir;
  const std::string scene = SceneWithASpareState(dir);
  const auto run = RunVantage("optimize " + scene + " -n 3 --method exact --over-states min " +
                              "--over-parts min --out " + dir.File("o"));
  ASSERT_EQ(run.exit_code, 0) << run.err;
  const json report = Report(dir.File("o"));
  const json& exact = report["results"].back();
  EXPECT_EQ(exact["method"], "exact");
  ASSERT_EQ(exact["state_coverage"].size(), 4u);
  const auto per_state = exact["state_coverage"].get<std::vector<double>>();
  EXPECT_LE(exact["coverage"].get<double>(),
            *std::min_element(per_state.begin(), per_state.end()) + 1e-12);
  EXPECT_GE(exact["upper_bound"].get<double>() + 1e-12, exact["coverage"].get<double>());
  const auto states = RunVantage("optimize " + scene + " -n 3 --method exact --over-states min " +
                                 "--out " + dir.File("s"));
  ASSERT_EQ(states.exit_code, 0) << states.err;
  const json states_report = Report(dir.File("s"));
  const json& by_state = states_report["results"].back();
  EXPECT_EQ(by_state["optimal"], true);
  EXPECT_GE(by_state["coverage"].get<double>() + 1e-12,
            *std::min_element(per_state.begin(), per_state.end()));
}

TEST(OverPartsStatesCli, TwoDifferentAggregationsAreRefused) {
  test::TempDir dir;
  const auto run = RunVantage("optimize " + StatesScene() + " --over-states mean --over-parts min" +
                              " --out " + dir.File("o"));
  EXPECT_EQ(run.exit_code, 2);
  EXPECT_NE(run.err.find("--over-parts: min with --over-states mean is a two-level objective"),
            std::string::npos)
      << run.err;
  EXPECT_NE(run.err.find("both mean or both min"), std::string::npos) << run.err;
  EXPECT_FALSE(std::filesystem::exists(dir.File("o")));
}

}  // namespace
}  // namespace vantage
