// `--over-parts` on a scene with states (issue 42): one aggregation over every (state, part)
// group, when both flags ask the same one; two different ones refused, naming both flags.
#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <nlohmann/json.hpp>
#include <string>

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
  std::string text = test::ReadText(StatesScene());
  const std::string mesh = "../meshes/";
  text.replace(text.find(mesh), mesh.size(), std::string(VANTAGE_SOURCE_DIR) + "/examples/meshes/");
  text += "  - name: spare                  # a second part beside the motor\n"
          "    add:\n"
          "      - {name: spare, role: target, box: {size: [0.08, 0.06, 0.05]}, "
          "pose: {xyz: [0.11, -0.07, 0.775]}}\n";
  const std::string scene = dir.File("states.yaml");
  test::WriteText(scene, text);
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
