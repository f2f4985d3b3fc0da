// The further objectives of selection from the command line and the scene file (SYSTEM.md,
// Select): --goal (set cover), --k (k-coverage), --budget, their settings: keys, how they travel
// through the visibility file, the report.json keys they add and the infeasible goal's exit 2.
#include <fmt/format.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <filesystem>
#include <iterator>
#include <nlohmann/json.hpp>
#include <optional>
#include <sstream>
#include <set>
#include <string>
#include <tuple>
#include <vector>

#include "test_util.hpp"

namespace vantage {
namespace {

using nlohmann::json;
using test::RunVantage;

std::string Scene() { return test::DataPath("cli/cube_cell.yaml"); }

// cube_cell.yaml with `extra` spliced in: settings lines go under `settings:`, and with
// `cost` the custom camera costs that much.
std::string SceneWith(const test::TempDir& dir,
                      const std::string& settings,
                      const std::string& cost = "") {
  std::string text = test::ReadText(Scene());
  const std::string settings_key = "settings:\n";
  text.replace(text.find(settings_key), settings_key.size(), settings_key + settings);
  if (!cost.empty()) {
    const std::string range = "    range: [0.1, 3.0]\n";
    text.replace(text.find(range), range.size(), range + "    cost: " + cost + "\n");
  }
  const std::string path = dir.File("scene.yaml");
  test::WriteText(path, text);
  return path;
}

json Report(const std::string& out_dir) {
  return json::parse(test::ReadText(out_dir + "/report.json"));
}

// The fixed keys of report.schema.json's results entries, which every objective keeps.
void ExpectSchemaKeys(const json& r) {
  for (const char* key : {"method", "n", "sensors", "coverage", "paper_coverage", "seconds"})
    EXPECT_TRUE(r.contains(key)) << key;
  ASSERT_TRUE(r["n"].is_number_integer());
  EXPECT_GE(r["n"].get<int>(), 1);
  EXPECT_EQ(r["sensors"].size(), r["n"].get<size_t>());
  EXPECT_GE(r["coverage"].get<double>(), 0.0);
  EXPECT_LE(r["coverage"].get<double>(), 1.0);
  if (r.contains("upper_bound")) {
    EXPECT_GE(r["upper_bound"].get<double>() + 1e-12, r["coverage"].get<double>());
  }
}

TEST(ObjectivesCli, GoalGivesTheFewestSensorsReachingIt) {
  test::TempDir dir;
  const auto run = RunVantage("optimize " + Scene() + " --goal 0.5 --out " + dir.File("o"));
  ASSERT_EQ(run.exit_code, 0) << run.err;
  const json report = Report(dir.File("o"));
  ASSERT_EQ(report["results"].size(), 2u);  // "all": greedy and exact
  EXPECT_EQ(report["results"][0]["method"], "greedy");
  EXPECT_EQ(report["results"][1]["method"], "exact");
  for (const json& r : report["results"]) {
    ExpectSchemaKeys(r);
    EXPECT_EQ(r["objective"], "set-cover");
    EXPECT_DOUBLE_EQ(r["goal"].get<double>(), 0.5);
    EXPECT_GE(r["coverage"].get<double>(), 0.5);
  }
  const json& exact = report["results"][1];
  EXPECT_LE(exact["n"].get<int>(), report["results"][0]["n"].get<int>());
  ASSERT_TRUE(exact.contains("n_lower_bound"));
  EXPECT_LE(exact["n_lower_bound"].get<int>(), exact["n"].get<int>());
  EXPECT_EQ(exact["optimal"].get<bool>(), exact["n_lower_bound"] == exact["n"]);
  // The fewest sensors stand for the run.
  EXPECT_EQ(report["results"][report["primary_result"].get<size_t>()]["n"], exact["n"]);
  EXPECT_NE(run.out.find("set cover: the fewest sensors reaching 50.00 % coverage"),
            std::string::npos)
      << run.out;
}

TEST(ObjectivesCli, InfeasibleGoalExitsTwoNamingTheReachableMaximum) {
  test::TempDir dir;
  // What all 16 candidates see together: greedy with n = 16 takes them all.
  ASSERT_EQ(RunVantage("optimize " + Scene() + " -n 16 --method greedy --out " + dir.File("all"))
                .exit_code,
            0);
  const double reachable = Report(dir.File("all"))["results"][0]["coverage"].get<double>();
  ASSERT_LT(reachable, 0.999);
  const auto run = RunVantage("optimize " + Scene() + " --goal 0.999 --out " + dir.File("o"));
  EXPECT_EQ(run.exit_code, 2);
  EXPECT_NE(run.err.find(fmt::format("goal 0.999 is above the {:.4f} that all 16 candidates reach "
                                     "together — lower --goal",
                                     reachable)),
            std::string::npos)
      << run.err;
  EXPECT_FALSE(std::filesystem::exists(dir.File("o")));
  // The scene's own goal is named at its line (the one right after `settings:`).
  const std::string scene = SceneWith(dir, "  goal: 0.999\n");
  const int settings_line = [&] {
    const std::string text = test::ReadText(scene);
    return 1 + static_cast<int>(std::count(text.begin(), text.begin() + text.find("settings:\n"), '\n'));
  }();
  const auto own = RunVantage("optimize " + scene + " --out " + dir.File("s"));
  EXPECT_EQ(own.exit_code, 2);
  EXPECT_NE(own.err.find(fmt::format("{}:{}: goal 0.999 is above the {:.4f}", scene,
                                     settings_line + 1, reachable)),
            std::string::npos)
      << own.err;
  EXPECT_FALSE(std::filesystem::exists(dir.File("s")));
}

TEST(ObjectivesCli, KCoverageReportsTheKMetricPerN) {
  test::TempDir dir;
  const auto run = RunVantage("optimize " + Scene() + " --k 2 -n 3 --out " + dir.File("o"));
  ASSERT_EQ(run.exit_code, 0) << run.err;
  const json report = Report(dir.File("o"));
  std::set<std::pair<std::string, int>> seen;
  for (const json& r : report["results"]) {
    ExpectSchemaKeys(r);
    EXPECT_EQ(r["objective"], "k-coverage");
    EXPECT_EQ(r["k"], 2);
    seen.insert({r["method"].get<std::string>(), r["n"].get<int>()});
  }
  // n = k..N: 2 and 3, each with ransac, greedy, local and exact.
  EXPECT_EQ(seen.size(), 8u);
  for (const char* m : {"ransac", "greedy", "local", "exact"}) {
    EXPECT_TRUE(seen.count({m, 2})) << m;
    EXPECT_TRUE(seen.count({m, 3})) << m;
  }
  EXPECT_NE(run.out.find("coverage by n (2-coverage, %)"), std::string::npos) << run.out;
  // Fewer sensors than k: exit 2, saying what to do.
  const auto too_few = RunVantage("optimize " + Scene() + " --k 3 -n 2 --out " + dir.File("x"));
  EXPECT_EQ(too_few.exit_code, 2);
  EXPECT_NE(too_few.err.find("raise -n to at least 3"), std::string::npos) << too_few.err;
}

TEST(ObjectivesCli, BudgetUsesTheScenesCostsAndIsNeverExceeded) {
  test::TempDir dir;
  // Every camera costs 250: a budget of 600 affords two.
  const std::string scene = SceneWith(dir, "", "250");
  const auto run = RunVantage("optimize " + scene +
                              " --budget 600 --alternatives-within 100 --out " + dir.File("o"));
  ASSERT_EQ(run.exit_code, 0) << run.err;
  const json report = Report(dir.File("o"));
  // Its one-sensor alternatives (any within 100 points) keep the budget and say what they cost:
  // two cameras, 500.
  const json& alternatives = report["robustness"]["alternatives"];
  EXPECT_EQ(alternatives.size(), 2u);
  for (const json& a : alternatives) EXPECT_DOUBLE_EQ(a["cost"].get<double>(), 500);
  EXPECT_NE(run.out.find(", cost 500 (+0)"), std::string::npos) << run.out;
  ASSERT_EQ(report["results"].size(), 3u);  // greedy, local, exact
  for (const json& r : report["results"]) {
    ExpectSchemaKeys(r);
    EXPECT_EQ(r["objective"], "budget");
    EXPECT_DOUBLE_EQ(r["budget"].get<double>(), 600);
    EXPECT_LE(r["cost"].get<double>(), 600);
    EXPECT_DOUBLE_EQ(r["cost"].get<double>(), 250.0 * r["n"].get<int>());
    EXPECT_EQ(r["n"], 2);
  }
  // The exact answer with a budget for two is the optimum of n = 2.
  const auto two = RunVantage("optimize " + scene + " -n 2 --method exact --out " + dir.File("n2"));
  ASSERT_EQ(two.exit_code, 0) << two.err;
  EXPECT_DOUBLE_EQ(report["results"][2]["coverage"].get<double>(),
                   Report(dir.File("n2"))["results"][0]["coverage"].get<double>());
  // Below the cheapest camera: exit 2.
  const auto broke = RunVantage("optimize " + scene + " --budget 100 --out " + dir.File("x"));
  EXPECT_EQ(broke.exit_code, 2);
  EXPECT_NE(broke.err.find("budget 100 is below the cheapest candidate's cost 250"),
            std::string::npos)
      << broke.err;
}

TEST(ObjectivesCli, SceneSettingsTravelThroughTheVisibilityFile) {
  test::TempDir dir;
  const std::string scene = SceneWith(dir, "  goal: 0.5\n");
  ASSERT_EQ(RunVantage("observe " + scene + " --out " + dir.File("m.vis")).exit_code, 0);
  const auto select = RunVantage("select " + dir.File("m.vis") + " --out " + dir.File("s"));
  ASSERT_EQ(select.exit_code, 0) << select.err;
  const json selected = Report(dir.File("s"));
  ASSERT_EQ(selected["results"].size(), 2u);
  EXPECT_EQ(selected["results"][1]["objective"], "set-cover");
  // The same as optimizing the scene directly.
  ASSERT_EQ(RunVantage("optimize " + scene + " --out " + dir.File("o")).exit_code, 0);
  EXPECT_EQ(Report(dir.File("o"))["results"][1]["sensors"], selected["results"][1]["sensors"]);
  // An objective on the command line replaces the scene's.
  const auto k = RunVantage("select " + dir.File("m.vis") + " --k 2 -n 2 --method greedy --out " +
                            dir.File("k"));
  ASSERT_EQ(k.exit_code, 0) << k.err;
  const json k_report = Report(dir.File("k"));
  ASSERT_EQ(k_report["results"].size(), 1u);
  EXPECT_EQ(k_report["results"][0]["objective"], "k-coverage");
  EXPECT_FALSE(k_report["results"][0].contains("goal"));

  // settings.k and settings.budget likewise.
  const std::string k_scene = SceneWith(dir, "  k: 2\n  method: exact\n");
  ASSERT_EQ(RunVantage("optimize " + k_scene + " --out " + dir.File("ko")).exit_code, 0);
  const json ko = Report(dir.File("ko"));
  ASSERT_EQ(ko["results"].size(), 1u);  // settings.method applies too
  EXPECT_EQ(ko["results"][0]["method"], "exact");
  EXPECT_EQ(ko["results"][0]["k"], 2);
  const std::string b_scene = SceneWith(dir, "  budget: 2\n");
  ASSERT_EQ(RunVantage("optimize " + b_scene + " --out " + dir.File("bo")).exit_code, 0);
  const json bo = Report(dir.File("bo"));  // a named value: the loop must not outlive it
  for (const json& r : bo["results"]) EXPECT_LE(r["cost"].get<double>(), 2);
}

TEST(ObjectivesCli, BadObjectiveSettingsExitTwoWithFileAndLine) {
  test::TempDir dir;
  struct Case {
    std::string settings;
    int line;
    std::string message;
  };
  // Settings start at line 3 of cube_cell.yaml (after two comment lines and `settings:`).
  const Case cases[] = {
      {"  goal: 1.5\n", 4, "settings.goal = 1.5 is a coverage fraction"},
      {"  k: 0\n", 4, "settings.k = 0 is too small"},
      {"  budget: -3\n", 4, "settings.budget = -3 must be >= 0"},
      {"  goal: 0.5\n  budget: 10\n", 5, "separate objectives"},
  };
  for (const Case& c : cases) {
    const std::string scene = SceneWith(dir, c.settings);
    const auto run = RunVantage("optimize " + scene + " --out " + dir.File("o"));
    EXPECT_EQ(run.exit_code, 2) << c.settings;
    EXPECT_NE(run.err.find(fmt::format("scene.yaml:{}: ", c.line)), std::string::npos)
        << c.settings << run.err;
    EXPECT_NE(run.err.find(c.message), std::string::npos) << c.settings << run.err;
  }
  // Two objectives on the command line, or a method that does not apply: exit 2.
  EXPECT_EQ(
      RunVantage("optimize " + Scene() + " --goal 0.5 --budget 2 --out " + dir.File("o")).exit_code,
      2);
  const auto method =
      RunVantage("optimize " + Scene() + " --goal 0.5 --method local --out " + dir.File("o"));
  EXPECT_EQ(method.exit_code, 2);
  EXPECT_NE(method.err.find("method 'local' does not apply to the set-cover objective"),
            std::string::npos)
      << method.err;
}

TEST(ObjectivesCli, AllPrintsTheCoverageByNTable) {
  test::TempDir dir;
  const auto run = RunVantage("optimize " + Scene() + " -n 3 --out " + dir.File("o"));
  ASSERT_EQ(run.exit_code, 0) << run.err;
  EXPECT_NE(run.out.find("coverage by n (%)"), std::string::npos) << run.out;
  // The header row, then one row per n: n, five percentages (or "-") and the bound.
  std::vector<std::vector<std::string>> rows;
  std::istringstream lines(run.out);
  for (std::string line; std::getline(lines, line);) {
    std::istringstream words(line);
    rows.emplace_back(std::istream_iterator<std::string>(words), std::istream_iterator<std::string>());
  }
  const std::vector<std::string> header = {"n", "best", "ransac", "greedy", "local", "exact", "bound"};
  const auto at = std::find(rows.begin(), rows.end(), header);
  ASSERT_NE(at, rows.end()) << run.out;
  // "47.30": digits, a point and two decimals.
  const auto is_percent = [](std::string word) {
    const size_t point = word.find('.');
    return point != std::string::npos && point > 0 && word.size() == point + 3 &&
           std::all_of(word.begin(), word.end(),
                       [](char c) { return c == '.' || std::isdigit(static_cast<unsigned char>(c)); });
  };
  for (int n = 1; n <= 3; ++n) {
    ASSERT_LT(at + n, rows.end()) << run.out;
    const std::vector<std::string>& row = at[n];
    ASSERT_EQ(row.size(), 7u) << n << "\n" << run.out;
    EXPECT_EQ(row[0], std::to_string(n));
    for (size_t column = 1; column <= 5; ++column)
      EXPECT_TRUE(row[column] == "-" || is_percent(row[column])) << row[column];
    std::string bound = row[6];
    if (!bound.empty() && bound.back() == '*') bound.pop_back();
    EXPECT_TRUE(is_percent(bound)) << row[6];
  }
}


// ----- installation constraints (issue 20, docs/constraints.md) ------------------------------

// A 10 cm cube (cells of 1 cm) and explicit sensors at its mid-height, each looking at its
// centre: `sensors` is the YAML list.
std::string CubeWithSensors(const test::TempDir& dir, const std::string& sensors) {
  const std::string text = "settings:\n  cell_size: 0.01\n  n: 2\n"
                           "  observation_point: [0, 0, 0.05]\n"
                           "sensor_types:\n"
                           "  - id: fine_cam\n    resolution: [640, 480]\n    hfov: 1.0\n"
                           "    range: [0.1, 3.0]\n"
                           "objects:\n"
                           "  - name: cube\n    role: target\n    box: {size: [0.1, 0.1, 0.1]}\n"
                           "    pose: {xyz: [0, 0, 0.05]}\n"
                           "sensors:\n" + sensors;
  const std::string path = dir.File("cube.yaml");
  test::WriteText(path, text);
  return path;
}

// `vantage ARGS --out OUT` exits 2 with `message` in its stderr and writes nothing.
void ExpectRefused(const std::string& args, const std::string& out, const std::string& message) {
  const auto run = RunVantage(args + " --out " + out);
  EXPECT_EQ(run.exit_code, 2) << args;
  EXPECT_NE(run.err.find(message), std::string::npos) << args << ": " << run.err;
  EXPECT_FALSE(std::filesystem::exists(out)) << args;
}

std::set<std::string> Names(const json& sensors) {
  std::set<std::string> names;
  for (const json& s : sensors) names.insert(s.get<std::string>());
  return names;
}

TEST(ConstraintsCli, CalibrationRefusesDisjointViewsAndTakesTheBridge) {
  test::TempDir dir;
  // a sees the +x and +y faces, b the -x and -y faces (they share at most the two corner columns
  // of 11 cells), the bridge sees +x and -y: a whole face with each.
  const std::string scene = CubeWithSensors(
      dir,
      "  - {name: a, type: fine_cam, position: [0.5, 0.5, 0.05]}\n"
      "  - {name: b, type: fine_cam, position: [-0.5, -0.5, 0.05]}\n"
      "  - {name: bridge, type: fine_cam, position: [0.5, -0.5, 0.05]}\n");
  const auto plain = RunVantage("optimize " + scene + " --method exact --out " + dir.File("p"));
  ASSERT_EQ(plain.exit_code, 0) << plain.err;
  const json p = Report(dir.File("p"));
  EXPECT_EQ(Names(p["results"][0]["sensors"]), (std::set<std::string>{"a", "b"}));
  EXPECT_FALSE(p.contains("constraints"));  // tiny cameras project nothing; no rule given

  const auto run = RunVantage("optimize " + scene +
                              " --method exact --calibration-overlap 40 --out " + dir.File("c"));
  ASSERT_EQ(run.exit_code, 0) << run.err;
  const json c = Report(dir.File("c"));
  const json& r = c["results"][0];
  ExpectSchemaKeys(r);
  const std::set<std::string> chosen = Names(r["sensors"]);
  EXPECT_EQ(chosen.size(), 2u);
  EXPECT_TRUE(chosen.count("bridge"));
  EXPECT_LT(r["coverage"].get<double>(), p["results"][0]["coverage"].get<double>());
  EXPECT_TRUE(r["optimal"].get<bool>());
  EXPECT_EQ(c["constraints"]["calibration"]["min_cells"], 40);
  EXPECT_TRUE(r["constraints"]["connected"].get<bool>());
  EXPECT_TRUE(r["constraints"]["satisfied"].get<bool>());
  ASSERT_EQ(r["constraints"]["overlap_graph"].size(), 1u);
  // The shared face: 11 x 11 cells through which it passes (a face on a grid plane), less what
  // the two grazing views miss; at least the face's interior 9 x 9.
  const int shared = r["constraints"]["overlap_graph"][0]["cells"].get<int>();
  EXPECT_GE(shared, 81);
  EXPECT_LE(shared, 121);
  EXPECT_NE(run.out.find("(connected)"), std::string::npos) << run.out;

  // evaluate: the unconstrained layout breaks the rule.
  const auto check = RunVantage("evaluate --constellation " + dir.File("p") +
                                "/report.json --calibration-overlap 40 --out " + dir.File("e"));
  ASSERT_EQ(check.exit_code, 0) << check.err;
  const json e = Report(dir.File("e"));
  EXPECT_FALSE(e["constraints"]["applied"].get<bool>());
  EXPECT_FALSE(e["results"][0]["constraints"]["connected"].get<bool>());
  EXPECT_FALSE(e["results"][0]["constraints"]["satisfied"].get<bool>());
  EXPECT_EQ(e["results"][0]["constraints"]["components"].size(), 2u);
  EXPECT_NE(check.out.find("NOT connected: 2 parts"), std::string::npos) << check.out;
}

TEST(ConstraintsCli, StructuredLightPairConflictsTofWithStereoDoesNot) {
  test::TempDir dir;
  // Two Kinect 360 (structured light) facing the +x face from 3 cm apart see nearly the same
  // cells; an Azure Kinect (time of flight) and a MultiSense S7 (stereo) both face -x: only one
  // of them projects. Opposite faces share no cell.
  const std::string scene = CubeWithSensors(
      dir,
      "  - {name: sl_1, type: kinect_xbox_360, position: [0.8, 0.015, 0.05]}\n"
      "  - {name: sl_2, type: kinect_xbox_360, position: [0.8, -0.015, 0.05]}\n"
      "  - {name: tof, type: azure_kinect_nfov, position: [-0.8, 0.015, 0.05]}\n"
      "  - {name: stereo, type: multisense_s7, position: [-0.8, -0.015, 0.05]}\n");
  const auto run =
      RunVantage("evaluate " + scene + " --interference true --out " + dir.File("e"));
  ASSERT_EQ(run.exit_code, 0) << run.err;
  const json e = Report(dir.File("e"));
  EXPECT_EQ(e["constraints"]["interference"]["projecting_candidates"], 3);
  EXPECT_EQ(e["constraints"]["interference"]["conflicting_pairs"], 1);
  const json& broken = e["results"][0]["constraints"]["conflicts"];
  ASSERT_EQ(broken.size(), 1u);
  EXPECT_EQ(broken[0]["a"], "sl_1");
  EXPECT_EQ(broken[0]["b"], "sl_2");
  EXPECT_GT(broken[0]["shared"].get<double>(), 0.9);
  EXPECT_NE(run.out.find("breaks           sl_1 ~ sl_2 (interference"), std::string::npos)
      << run.out;
  // optimize -n 2 never takes both Kinects; without interference it may.
  const auto opt = RunVantage("optimize " + scene + " --method exact --interference true --out " +
                              dir.File("o"));
  ASSERT_EQ(opt.exit_code, 0) << opt.err;
  const json o = Report(dir.File("o"));
  const std::set<std::string> chosen = Names(o["results"][0]["sensors"]);
  EXPECT_FALSE(chosen.count("sl_1") && chosen.count("sl_2"));
  EXPECT_TRUE(o["results"][0]["constraints"]["satisfied"].get<bool>());
  // Without it (the default) there is no block.
  const auto off = RunVantage("optimize " + scene + " --out " + dir.File("f"));
  ASSERT_EQ(off.exit_code, 0) << off.err;
  EXPECT_FALSE(Report(dir.File("f")).contains("constraints"));
}

TEST(ConstraintsCli, ConstraintOptionsThatCannotApplyExitTwoNamingThem) {
  test::TempDir dir;
  const std::vector<std::pair<std::string, std::string>> cases = {
      {"--interference-overlap 1.5", "--interference-overlap: 1.5 must be a fraction in [0, 1]"},
      {"--calibration-overlap 0", "--calibration-overlap: must be at least 1 common cell"},
      {"--calibration-overlap 3 --calibration-overlap-frac 0.1",
       "--calibration-overlap-frac: give one of"},
  };
  for (const auto& [flags, message] : cases) {
    const auto run = RunVantage("optimize " + Scene() + " " + flags + " --out " + dir.File("x"));
    EXPECT_EQ(run.exit_code, 2) << flags;
    EXPECT_NE(run.err.find(message), std::string::npos) << flags << ": " << run.err;
    EXPECT_FALSE(std::filesystem::exists(dir.File("x")));
  }
}

// Over scene states: the calibration rule joins by the first state's overlaps, the result is
// connected there and scored over both states; interference holds in every method.
TEST(ConstraintsCli, CalibrationAndInterferenceOverSceneStates) {
  test::TempDir dir;
  const std::string states =
      "states:\n"
      "  - name: full\n"
      "  - name: lifted\n"
      "    move: {cube: {xyz: [0, 0, 0.02], rpy: [0, 0, 0]}}\n";
  const std::string scene =
      CubeWithSensors(dir,
                      "  - {name: a, type: fine_cam, position: [0.5, 0.5, 0.05]}\n"
                      "  - {name: b, type: fine_cam, position: [-0.5, -0.5, 0.05]}\n"
                      "  - {name: bridge, type: fine_cam, position: [0.5, -0.5, 0.05]}\n" +
                          states);
  const auto plain = RunVantage("optimize " + scene + " --method exact --out " + dir.File("p"));
  ASSERT_EQ(plain.exit_code, 0) << plain.err;
  const json p = Report(dir.File("p"));
  ASSERT_TRUE(p.contains("states"));
  EXPECT_EQ(Names(p["results"][0]["sensors"]), (std::set<std::string>{"a", "b"}));
  for (const char* method : {"exact", "greedy", "local", "ransac"}) {
    const std::string out = dir.File(std::string("c_") + method);
    const auto run = RunVantage("optimize " + scene + " --method " + method +
                                " --over-states min --calibration-overlap 40 --out " + out);
    ASSERT_EQ(run.exit_code, 0) << method << ": " << run.err;
    const json c = Report(out);
    const json& r = c["results"][0];
    ExpectSchemaKeys(r);
    EXPECT_EQ(c["states"]["over"], "min");
    EXPECT_EQ(r["state_coverage"].size(), 2u);
    const std::set<std::string> chosen = Names(r["sensors"]);
    EXPECT_EQ(chosen.size(), 2u) << method;
    EXPECT_TRUE(chosen.count("bridge")) << method;
    EXPECT_TRUE(r["constraints"]["connected"].get<bool>()) << method;
    EXPECT_TRUE(r["constraints"]["satisfied"].get<bool>()) << method;
    if (std::string(method) == "exact") {
      EXPECT_TRUE(r["optimal"].get<bool>());
      EXPECT_GE(r["upper_bound"].get<double>() + 1e-12, r["coverage"].get<double>());
    }
  }
  // Two Kinects on the same face: never both, in any state.
  const std::string kinects =
      CubeWithSensors(dir,
                      "  - {name: sl_1, type: kinect_xbox_360, position: [0.8, 0.015, 0.05]}\n"
                      "  - {name: sl_2, type: kinect_xbox_360, position: [0.8, -0.015, 0.05]}\n"
                      "  - {name: stereo, type: multisense_s7, position: [-0.8, -0.015, 0.05]}\n" +
                          states);
  const auto opt = RunVantage("optimize " + kinects + " --method all --interference true --out " +
                              dir.File("k"));
  ASSERT_EQ(opt.exit_code, 0) << opt.err;
  const json k = Report(dir.File("k"));
  EXPECT_EQ(k["constraints"]["interference"]["conflicting_pairs"], 1);
  for (const json& r : k["results"]) {
    const std::set<std::string> chosen = Names(r["sensors"]);
    EXPECT_FALSE(chosen.count("sl_1") && chosen.count("sl_2")) << r["method"];
    EXPECT_TRUE(r["constraints"]["satisfied"].get<bool>()) << r["method"];
  }
  // evaluate of the plain layout over the states scene: it breaks the rule.
  const auto check = RunVantage("evaluate --constellation " + dir.File("p") +
                                "/report.json --calibration-overlap 40 --out " + dir.File("e"));
  ASSERT_EQ(check.exit_code, 0) << check.err;
  const json e = Report(dir.File("e"));
  EXPECT_FALSE(e["results"][0]["constraints"]["connected"].get<bool>());
  EXPECT_FALSE(e["results"][0]["constraints"]["satisfied"].get<bool>());
}

// Interference over states in optimize and evaluate: a wall in front of sl_2 in the scene as
// listed (state 'walled') hides the face the two Kinects share; state 'open' removes it, and there
// they conflict.
TEST(ConstraintsCli, InterferenceInAnyStateOptimizeAndEvaluate) {
  test::TempDir dir;
  const std::string base =
      "settings:\n  cell_size: 0.01\n  n: 2\n  observation_point: [0, 0, 0.05]\n"
      "objects:\n  - name: cube\n    role: target\n    box: {size: [0.1, 0.1, 0.1]}\n"
      "    pose: {xyz: [0, 0, 0.05]}\n"
      "  - name: wall\n    role: occluder\n    box: {size: [0.01, 0.02, 0.1]}\n"
      "    pose: {xyz: [0.75, -0.015, 0.05]}\n"
      "sensors:\n"
      "  - {name: sl_1, type: kinect_xbox_360, position: [0.8, 0.015, 0.05]}\n"
      "  - {name: sl_2, type: kinect_xbox_360, position: [0.8, -0.015, 0.05]}\n";
  const std::string flat = dir.File("flat.yaml"), changing = dir.File("states.yaml");
  test::WriteText(flat, base);
  test::WriteText(changing, base +
                                "states:\n  - name: walled\n  - name: open\n"
                                "    remove: [wall]\n");
  const auto walled =
      RunVantage("evaluate " + flat + " --interference true --out " + dir.File("w"));
  ASSERT_EQ(walled.exit_code, 0) << walled.err;
  EXPECT_EQ(Report(dir.File("w"))["constraints"]["interference"]["conflicting_pairs"], 0);
  const auto open =
      RunVantage("evaluate " + changing + " --interference true --out " + dir.File("o"));
  ASSERT_EQ(open.exit_code, 0) << open.err;
  const json o = Report(dir.File("o"));
  EXPECT_EQ(o["constraints"]["interference"]["conflicting_pairs"], 1);
  ASSERT_EQ(o["results"][0]["constraints"]["conflicts"].size(), 1u);
  EXPECT_FALSE(o["results"][0]["constraints"]["satisfied"].get<bool>());
  const auto opt = RunVantage("optimize " + changing +
                              " --method exact --interference true --out " + dir.File("x"));
  ASSERT_EQ(opt.exit_code, 0) << opt.err;
  const json x = Report(dir.File("x"));
  EXPECT_EQ(x["constraints"]["interference"]["conflicting_pairs"], 1);
  EXPECT_EQ(x["results"][0]["sensors"].size(), 1u);
  EXPECT_TRUE(x["results"][0]["constraints"]["satisfied"].get<bool>());
}

// The other objectives under the constraints: k-coverage, a goal, a budget and point density.
// a and b see disjoint pairs of faces (not joined by 40 common cells); the bridge shares a face
// with each, so every connected answer of two holds it. The faces lie on grid planes: each
// sensor sees the 10 x 10 inner cells of its two faces, 200 of the 602 (a face's row and column
// of index 5 are touched by its edges only), and any two joined by the bridge 300 (49.8 %).
TEST(ConstraintsCli, ConstraintsWithTheOtherObjectives) {
  test::TempDir dir;
  const std::string pair =
      "  - {name: a, type: fine_cam, position: [0.5, 0.5, 0.05]}\n"
      "  - {name: b, type: fine_cam, position: [-0.5, -0.5, 0.05]}\n";
  const std::string scene = CubeWithSensors(
      dir, pair + "  - {name: bridge, type: fine_cam, position: [0.5, -0.5, 0.05]}\n");
  const std::vector<std::string> objectives = {"--k 2 -n 2", "--goal 0.45", "--budget 2",
                                               "--min-points 2 -n 2"};
  for (size_t i = 0; i < objectives.size(); ++i) {
    const std::string out = dir.File(fmt::format("o{}", i));
    const auto run = RunVantage("optimize " + scene + " " + objectives[i] +
                                " --method exact --calibration-overlap 40 --out " + out);
    ASSERT_EQ(run.exit_code, 0) << objectives[i] << ": " << run.err;
    const json r = Report(out)["results"][0];
    ExpectSchemaKeys(r);
    // {a, bridge} and {b, bridge} tie (the scene is symmetric): either, never {a, b}.
    const std::set<std::string> names = Names(r["sensors"]);
    EXPECT_EQ(names.size(), 2u) << objectives[i];
    EXPECT_TRUE(names.contains("bridge")) << objectives[i];
    if (objectives[i] != "--k 2 -n 2" && objectives[i] != "--min-points 2 -n 2") {
      EXPECT_NEAR(r["coverage"].get<double>(), 300.0 / 602, 1e-12) << objectives[i];
    }
    EXPECT_TRUE(r["constraints"]["connected"].get<bool>()) << objectives[i];
    EXPECT_TRUE(r["optimal"].get<bool>()) << objectives[i];
  }
  // a + b reach 0.6 with two sensors; connected, all three are needed.
  const auto three =
      RunVantage("optimize " + scene +
                 " --goal 0.6 --method exact --calibration-overlap 40 --out " + dir.File("g3"));
  ASSERT_EQ(three.exit_code, 0) << three.err;
  const json g3 = Report(dir.File("g3"))["results"][0];
  EXPECT_EQ(g3["n"], 3);
  EXPECT_TRUE(g3["optimal"].get<bool>());
  // Without the bridge no two are joined: a goal above one sensor's exits 2 naming the goal.
  const std::string apart = CubeWithSensors(dir, pair);
  const auto run = RunVantage("optimize " + apart + " --goal 0.5 --calibration-overlap 40 --out " +
                              dir.File("g"));
  EXPECT_EQ(run.exit_code, 2) << run.out;
  EXPECT_NE(run.err.find("goal 0.5 cannot be reached: the installation constraints allow at most"),
            std::string::npos)
      << run.err;
  EXPECT_FALSE(std::filesystem::exists(dir.File("g")));
}

// --keep-existing under interference: a candidate that conflicts with a kept sensor is never
// added; kept sensors that conflict with each other exit 2 naming them, before any output.
TEST(ConstraintsCli, KeptSensorsAndInterference) {
  test::TempDir dir;
  const auto scene_with = [&](const std::string& sensors) {
    const std::string text =
        "settings:\n  cell_size: 0.01\n  n: 3\n  observation_point: [0, 0, 0.05]\n"
        "objects:\n  - name: cube\n    role: target\n    box: {size: [0.1, 0.1, 0.1]}\n"
        "    pose: {xyz: [0, 0, 0.05]}\n"
        "sensors:\n" +
        sensors +
        "populations:\n"
        "  - {name: near, type: kinect_xbox_360, distribution: grid, rows: 1, cols: 1,\n"
        "     step: [0.1, 0.1, 0], pose: {xyz: [0.8, -0.015, 0.05]}}\n"
        "  - {name: far, type: kinect_xbox_360, distribution: grid, rows: 1, cols: 1,\n"
        "     step: [0.1, 0.1, 0], pose: {xyz: [-0.8, 0, 0.05]}}\n";
    const std::string path = dir.File("kept.yaml");
    test::WriteText(path, text);
    return path;
  };
  const std::string sl_1 =
      "  - {name: sl_1, type: kinect_xbox_360, position: [0.8, 0.015, 0.05]}\n";
  const std::string scene = scene_with(sl_1);
  const auto plain =
      RunVantage("optimize " + scene + " --keep-existing --method exact --out " + dir.File("p"));
  ASSERT_EQ(plain.exit_code, 0) << plain.err;
  EXPECT_TRUE(Names(Report(dir.File("p"))["results"][0]["sensors"]).count("near_0"));
  const auto run = RunVantage("optimize " + scene + " --keep-existing --interference true --out " +
                              dir.File("k"));
  ASSERT_EQ(run.exit_code, 0) << run.err;
  const json k = Report(dir.File("k"));
  for (const json& r : k["results"]) {
    ASSERT_FALSE(r["sensors"].empty());
    EXPECT_EQ(r["sensors"][0], "sl_1") << r["method"];
    EXPECT_FALSE(Names(r["sensors"]).count("near_0")) << r["method"];
    EXPECT_TRUE(r["constraints"]["satisfied"].get<bool>()) << r["method"];
  }
  const std::string both =
      scene_with(sl_1 + "  - {name: sl_2, type: kinect_xbox_360, position: [0.8, -0.015, 0.05]}\n");
  ExpectRefused("optimize " + both + " --keep-existing --interference true", dir.File("c"),
                "--keep-existing: the kept sensors conflict: 'sl_1' and 'sl_2' (interference");
}

// --keep-existing with kept sensors that the calibration rule leaves apart: a and b share at most
// the corner columns (fewer than 40 cells); ring_2 at (0.5, -0.6) sees +x and -y, a whole face
// with each, so every answer holds a, b and a joining ring sensor. -n 2 leaves no room for it and
// a rule no pair meets has no chain: both exit 2 before any output.
TEST(ConstraintsCli, KeptSensorsApartAreJoinedByABridge) {
  test::TempDir dir;
  const std::string scene = CubeWithSensors(
      dir,
      "  - {name: a, type: fine_cam, position: [0.5, 0.5, 0.05]}\n"
      "  - {name: b, type: fine_cam, position: [-0.5, -0.5, 0.05]}\n"
      "populations:\n"
      "  - {name: ring, type: fine_cam, distribution: grid, rows: 1, cols: 3,\n"
      "     step: [0.5, 0.5, 0], pose: {xyz: [0, -0.6, 0.05]}}\n");
  const auto run = RunVantage("optimize " + scene +
                              " --keep-existing --calibration-overlap 40 -n 3 --out " +
                              dir.File("k"));
  ASSERT_EQ(run.exit_code, 0) << run.err;
  EXPECT_NE(run.err.find("joining the kept sensors' 2 parts ([a] [b]) takes 1 more sensor"),
            std::string::npos)
      << run.err;
  const json k = Report(dir.File("k"));
  ASSERT_FALSE(k["results"].empty());
  for (const json& r : k["results"]) {
    const std::set<std::string> chosen = Names(r["sensors"]);
    EXPECT_EQ(chosen.size(), 3u) << r["method"];
    EXPECT_TRUE(chosen.count("a") && chosen.count("b")) << r["method"];
    EXPECT_TRUE(r["constraints"]["connected"].get<bool>()) << r["method"];
  }
  ExpectRefused("optimize " + scene + " --keep-existing --calibration-overlap 40 -n 2",
                dir.File("n"),
                "-n: joining the kept sensors' 2 parts ([a] [b]) takes 1 more sensor (ring_2) — "
                "give -n 3 or more");
  ExpectRefused("optimize " + scene + " --keep-existing --calibration-overlap 400 -n 3",
                dir.File("c"),
                "--keep-existing: the kept sensors are not connected by the calibration rule (2 "
                "parts: [a] [b]), and no chain of candidates joins them");
}

// --refine under the constraints: the refined constellation obeys interference over old and new
// poses, and a keep-out box around the pose it chose keeps every new pose out of it.
TEST(ConstraintsCli, RefineObeysInterferenceAndKeepOut) {
  test::TempDir dir;
  const std::string text =
      "settings:\n  cell_size: 0.01\n  n: 2\n  observation_point: [0, 0.12, 0.05]\n"
      "sensor_types:\n  - {id: sl_cam, resolution: [320, 240], hfov: 0.6, range: [0.1, 3.0],\n"
      "     interferes: true}\n"
      "objects:\n  - name: cube\n    role: target\n    box: {size: [0.1, 0.1, 0.1]}\n"
      "    pose: {xyz: [0, 0, 0.05]}\n"
      "populations:\n"
      "  - {name: east, type: sl_cam, distribution: grid, rows: 2, cols: 2, step: [0.1, 0.1, 0],\n"
      "     pose: {xyz: [0.8, 0, 0.3]}}\n"
      "  - {name: west, type: sl_cam, distribution: grid, rows: 2, cols: 2, step: [0.1, 0.1, 0],\n"
      "     pose: {xyz: [-0.8, 0, 0.3]}}\n";
  const std::string scene = dir.File("sl.yaml");
  test::WriteText(scene, text);
  const std::string flags = " --refine --method greedy --interference-overlap 0.5 --out ";
  const auto run = RunVantage("optimize " + scene + flags + dir.File("r"));
  ASSERT_EQ(run.exit_code, 0) << run.err;
  const json r = Report(dir.File("r"));
  const auto result = [](const json& report, const std::string& method) {
    for (const json& x : report["results"])
      if (x["method"] == method) return x;
    return json();
  };
  const json refined = result(r, "refined");
  ASSERT_FALSE(refined.is_null());
  EXPECT_TRUE(refined["constraints"]["satisfied"].get<bool>());
  EXPECT_GT(refined["coverage"].get<double>(), result(r, "greedy")["coverage"].get<double>());
  // The interference pairs count the new poses too: more candidates than the 8 given.
  EXPECT_GT(r["candidates"].size(), 8u);
  EXPECT_EQ(r["constraints"]["interference"]["projecting_candidates"], r["candidates"].size());
  // A new pose the refinement chose, and a 1 cm keep-out box around it.
  std::optional<std::vector<double>> chosen_pose;
  for (const json& name : refined["sensors"]) {
    if (name.get<std::string>().find("_r") == std::string::npos) continue;
    for (const json& c : r["candidates"]) {
      if (c["name"] == name) {
        chosen_pose = c["position"].get<std::vector<double>>();
      }
    }
  }
  ASSERT_TRUE(chosen_pose.has_value());
  test::WriteText(scene, text + fmt::format("keep_out:\n  - {{name: pillar, center: [{}, {}, {}], "
                                            "size: [0.01, 0.01, 0.01]}}\n",
                                            (*chosen_pose)[0], (*chosen_pose)[1],
                                            (*chosen_pose)[2]));
  const auto boxed = RunVantage("optimize " + scene + flags + dir.File("b"));
  ASSERT_EQ(boxed.exit_code, 0) << boxed.err;
  const json b = Report(dir.File("b"));
  for (const json& c : b["candidates"]) {
    const std::vector<double> p = c["position"].get<std::vector<double>>();
    double distance = 0;  // along the farthest axis
    for (int axis = 0; axis < 3; ++axis)
      distance = std::max(distance, std::abs(p[axis] - (*chosen_pose)[axis]));
    EXPECT_GT(distance, 0.005) << c["name"];
  }
  const json boxed_refined = result(b, "refined");
  ASSERT_FALSE(boxed_refined.is_null());
  EXPECT_TRUE(boxed_refined["constraints"]["satisfied"].get<bool>());
  EXPECT_GE(boxed_refined["coverage"].get<double>(), result(b, "greedy")["coverage"].get<double>());
}

// ----- mounting rules (docs/constraints.md, Mounting rules) ----------------------------------

// a at (0.5, 0.5) sees the +x and +y faces (two faces), face at (0.5, 0) only +x (one face): a
// is the best single sensor. A keep-out box around a leaves face, with its own coverage.
TEST(MountingCli, KeepOutRemovesTheBestCandidateAndTheNextBestIsChosen) {
  test::TempDir dir;
  const std::string sensors = "  - {name: a, type: fine_cam, position: [0.5, 0.5, 0.05]}\n"
                              "  - {name: face, type: fine_cam, position: [0.5, 0, 0.05]}\n";
  const std::string scene = CubeWithSensors(dir, sensors);
  const auto plain = RunVantage("optimize " + scene + " -n 1 --method exact --out " +
                                dir.File("p"));
  ASSERT_EQ(plain.exit_code, 0) << plain.err;
  const json p = Report(dir.File("p"));
  EXPECT_EQ(Names(p["results"][0]["sensors"]), (std::set<std::string>{"a"}));
  test::WriteText(scene, test::ReadText(scene) +
                             "keep_out:\n  - {name: cabinet, center: [0.5, 0.5, 0.5], "
                             "size: [0.2, 0.2, 1.0]}\n");
  const auto run = RunVantage("optimize " + scene + " -n 1 --method exact --out " +
                              dir.File("k"));
  ASSERT_EQ(run.exit_code, 0) << run.err;
  const json k = Report(dir.File("k"));
  EXPECT_EQ(Names(k["results"][0]["sensors"]), (std::set<std::string>{"face"}));
  EXPECT_EQ(k["candidates"].size(), 1u);
  EXPECT_EQ(k["constraints"]["keep_out"]["boxes"], 1);
  EXPECT_EQ(k["constraints"]["keep_out"]["excluded_candidates"], 1);
  EXPECT_TRUE(k["results"][0]["constraints"]["satisfied"].get<bool>());
  EXPECT_NE(run.out.find("keep-out: 1 box; 1 candidates inside excluded"), std::string::npos)
      << run.out;
  // face sees the +x face whole: 9 x 9 to 11 x 11 cells; a saw two faces.
  const double cells = k["reference_voxels"].get<double>();
  const double seen = k["results"][0]["coverage"].get<double>() * cells;
  EXPECT_GE(seen, 81 - 0.5);
  EXPECT_LE(seen, 121 + 0.5);
  EXPECT_GE(p["results"][0]["coverage"].get<double>() * cells, 2 * 81 - 0.5);
}

// a above one corner sees +x, +y and the top; c below the opposite corner -x, -y and the bottom:
// together every face, the best pair, sqrt(3 * 0.8^2) = 1.386 m apart. b, far beyond c's corner
// above the cube, sees -x, -y and the top (a with b: five faces). With min_separation 1.5 m, a ~ c
// and b ~ c (sqrt(0.6^2 + 0.6^2 + 0.8^2) = 1.166 m) conflict, a ~ b (1.980 m) does not: the only
// feasible pair is a, b.
TEST(MountingCli, MinSeparationKeepsTwoCloseSensorsFromBothBeingChosen) {
  test::TempDir dir;
  const std::string scene = CubeWithSensors(
      dir,
      "  - {name: a, type: fine_cam, position: [0.4, 0.4, 0.45]}\n"
      "  - {name: b, type: fine_cam, position: [-1.0, -1.0, 0.45]}\n"
      "  - {name: c, type: fine_cam, position: [-0.4, -0.4, -0.35]}\n");
  const auto plain = RunVantage("optimize " + scene + " --method exact --out " + dir.File("p"));
  ASSERT_EQ(plain.exit_code, 0) << plain.err;
  EXPECT_EQ(Names(Report(dir.File("p"))["results"][0]["sensors"]),
            (std::set<std::string>{"a", "c"}));

  test::WriteText(scene, test::ReadText(scene) + "min_separation: 1.5\n");
  for (const char* method : {"exact", "greedy", "local", "ransac"}) {
    const std::string out = dir.File(std::string("s_") + method);
    const auto run = RunVantage("optimize " + scene + " --method " + method + " --out " + out);
    ASSERT_EQ(run.exit_code, 0) << method << run.err;
    const json s = Report(out);
    EXPECT_EQ(Names(s["results"][0]["sensors"]), (std::set<std::string>{"a", "b"})) << method;
    EXPECT_TRUE(s["results"][0]["constraints"]["satisfied"].get<bool>()) << method;
    EXPECT_EQ(s["constraints"]["separation"]["min_separation"], 1.5);
    EXPECT_EQ(s["constraints"]["separation"]["conflicting_pairs"], 2);
  }
  // evaluate: the declared layout a, b, c breaks the rule twice.
  const auto check = RunVantage("evaluate " + scene + " --out " + dir.File("e"));
  ASSERT_EQ(check.exit_code, 0) << check.err;
  const json e = Report(dir.File("e"));
  const json& broken = e["results"][0]["constraints"]["conflicts"];
  ASSERT_EQ(broken.size(), 2u);
  EXPECT_EQ(broken[0]["a"], "a");
  EXPECT_EQ(broken[0]["b"], "c");
  EXPECT_EQ(broken[0]["kind"], "separation");
  EXPECT_NEAR(broken[0]["distance"].get<double>(), std::sqrt(3 * 0.64), 1e-9);
  EXPECT_EQ(broken[1]["a"], "b");
  EXPECT_EQ(broken[1]["b"], "c");
  EXPECT_NEAR(broken[1]["distance"].get<double>(), std::sqrt(0.36 + 0.36 + 0.64), 1e-9);
  EXPECT_FALSE(e["results"][0]["constraints"]["satisfied"].get<bool>());
  EXPECT_NE(check.out.find("breaks           a ~ c (separation, 1.386 m)"), std::string::npos)
      << check.out;
}

// The .vis file keeps the scene's min_separation (format 5): `observe` + `select FILE` choose
// what `optimize` on the scene chooses, with the same constraints block (the scene of the test
// above: only a, b is feasible), and refuse what optimize refuses (min_separation with --k).
TEST(MountingCli, SelectFromTheVisibilityFileAppliesMinSeparationAsOptimizeDoes) {
  test::TempDir dir;
  const std::string scene = CubeWithSensors(
      dir,
      "  - {name: a, type: fine_cam, position: [0.4, 0.4, 0.45]}\n"
      "  - {name: b, type: fine_cam, position: [-1.0, -1.0, 0.45]}\n"
      "  - {name: c, type: fine_cam, position: [-0.4, -0.4, -0.35]}\n"
      "min_separation: 1.5\n");
  const auto observe = RunVantage("observe " + scene + " --out " + dir.File("m.vis"));
  ASSERT_EQ(observe.exit_code, 0) << observe.err;
  for (const char* method : {"exact", "greedy", "local", "ransac"}) {
    const std::string flags = std::string(" --method ") + method + " --out ";
    const auto opt = RunVantage("optimize " + scene + flags + dir.File(std::string("o_") + method));
    ASSERT_EQ(opt.exit_code, 0) << method << opt.err;
    const auto sel =
        RunVantage("select " + dir.File("m.vis") + flags + dir.File(std::string("s_") + method));
    ASSERT_EQ(sel.exit_code, 0) << method << sel.err;
    const json o = Report(dir.File(std::string("o_") + method));
    const json s = Report(dir.File(std::string("s_") + method));
    EXPECT_EQ(Names(s["results"][0]["sensors"]), (std::set<std::string>{"a", "b"})) << method;
    EXPECT_EQ(s["results"][0]["sensors"], o["results"][0]["sensors"]) << method;
    EXPECT_EQ(s["results"][0]["coverage"], o["results"][0]["coverage"]) << method;
    EXPECT_EQ(s["results"][0]["constraints"], o["results"][0]["constraints"]) << method;
    EXPECT_EQ(s["constraints"], o["constraints"]) << method;
    EXPECT_EQ(s["constraints"]["separation"]["conflicting_pairs"], 2) << method;
  }
  // With another objective too (issue 20): select and optimize agree, and the answer keeps the
  // separation.
  for (const std::string& command : {"optimize " + scene, "select " + dir.File("m.vis")}) {
    const std::string out = dir.File(command.rfind("select", 0) == 0 ? "k_s" : "k_o");
    const auto run = RunVantage(command + " --k 2 --method exact --out " + out);
    ASSERT_EQ(run.exit_code, 0) << command << ": " << run.err;
    const json r = Report(out)["results"][0];
    EXPECT_EQ(r["objective"], "k-coverage");
    EXPECT_TRUE(r["constraints"]["satisfied"].get<bool>()) << command;
  }
  EXPECT_EQ(Report(dir.File("k_s"))["results"][0]["sensors"],
            Report(dir.File("k_o"))["results"][0]["sensors"]);
}

// A custom type's `interferes:` survives the .vis file (format 5): two stereo-technology
// cameras declared `interferes: true` facing one face conflict in select FILE as in optimize;
// two Kinect 360 (structured light) declared `interferes: false` do not, in either.
TEST(MountingCli, CustomInterferesFlagsTravelThroughTheVisibilityFile) {
  test::TempDir dir;
  std::string scene = CubeWithSensors(
      dir,
      "  - {name: loud_1, type: loud_stereo, position: [0.8, 0.015, 0.05]}\n"
      "  - {name: loud_2, type: loud_stereo, position: [0.8, -0.015, 0.05]}\n"
      "  - {name: quiet_1, type: quiet_kinect, position: [-0.8, 0.015, 0.05]}\n"
      "  - {name: quiet_2, type: quiet_kinect, position: [-0.8, -0.015, 0.05]}\n");
  std::string text = test::ReadText(scene);
  text.replace(text.find("sensor_types:\n"), 14,
               "sensor_types:\n"
               "  - {id: loud_stereo, base: multisense_s7, technology: stereo, interferes: true}\n"
               "  - {id: quiet_kinect, base: kinect_xbox_360, interferes: false}\n");
  test::WriteText(scene, text);
  const auto observe = RunVantage("observe " + scene + " --out " + dir.File("m.vis"));
  ASSERT_EQ(observe.exit_code, 0) << observe.err;
  const std::string flags = " --method exact --interference true -n 3 --out ";
  const auto opt = RunVantage("optimize " + scene + flags + dir.File("o"));
  ASSERT_EQ(opt.exit_code, 0) << opt.err;
  const auto sel = RunVantage("select " + dir.File("m.vis") + flags + dir.File("s"));
  ASSERT_EQ(sel.exit_code, 0) << sel.err;
  for (const char* out : {"o", "s"}) {
    const json r = Report(dir.File(out));
    EXPECT_EQ(r["constraints"]["interference"]["projecting_candidates"], 2) << out;
    EXPECT_EQ(r["constraints"]["interference"]["conflicting_pairs"], 1) << out;
    // Three of four: one loud camera (never both), both quiet ones (they may be both chosen).
    const std::set<std::string> chosen = Names(r["results"][0]["sensors"]);
    EXPECT_EQ(chosen.size(), 3u) << out;
    EXPECT_FALSE(chosen.count("loud_1") && chosen.count("loud_2")) << out;
    EXPECT_TRUE(chosen.count("quiet_1") && chosen.count("quiet_2")) << out;
  }
  EXPECT_EQ(Report(dir.File("s"))["constraints"], Report(dir.File("o"))["constraints"]);
  EXPECT_EQ(Report(dir.File("s"))["results"][0]["sensors"],
            Report(dir.File("o"))["results"][0]["sensors"]);
}

// --keep-existing with a declared sensor inside a keep-out box names the box that holds it,
// not the first one.
TEST(MountingCli, KeepExistingNamesTheKeepOutBoxThatHoldsTheSensor) {
  test::TempDir dir;
  const std::string scene = CubeWithSensors(
      dir,
      "  - {name: a, type: fine_cam, position: [0.5, 0.5, 0.05]}\n"
      "  - {name: c, type: fine_cam, position: [0.5, -0.5, 0.05]}\n"
      "keep_out:\n"
      "  - {name: far_shelf, center: [3, 3, 3], size: [0.1, 0.1, 0.1]}\n"
      "  - {name: rail, center: [0.5, -0.5, 0.05], size: [0.1, 0.1, 0.1]}\n");
  const std::string text = test::ReadText(scene);
  const auto rail = std::count(text.begin(), text.begin() + text.find("name: rail"), '\n') + 1;
  const auto run = RunVantage("optimize " + scene + " --keep-existing -n 1 --out " + dir.File("x"));
  EXPECT_EQ(run.exit_code, 2);
  EXPECT_NE(run.err.find(scene + ":" + std::to_string(rail) +
                         ": the declared sensor 'c' lies inside the keep-out box 'rail'"),
            std::string::npos)
      << run.err;
  EXPECT_FALSE(std::filesystem::exists(dir.File("x")));
}

TEST(MountingCli, EvaluateReportsSensorsInsideAKeepOutBox) {
  test::TempDir dir;
  const std::string scene = CubeWithSensors(
      dir,
      "  - {name: a, type: fine_cam, position: [0.5, 0.5, 0.05]}\n"
      "  - {name: c, type: fine_cam, position: [0.5, -0.5, 0.05]}\n"
      "keep_out:\n"
      "  - {name: rail, min: [-0.1, -0.1, -0.1], max: [0.1, 0.1, 0.1],\n"
      "     pose: {xyz: [0.5, 0.5, 0.05], rpy_deg: [0, 0, 45]}}\n");
  const auto run = RunVantage("evaluate " + scene + " --out " + dir.File("e"));
  ASSERT_EQ(run.exit_code, 0) << run.err;
  const json e = Report(dir.File("e"));
  EXPECT_FALSE(e["constraints"]["applied"].get<bool>());
  EXPECT_EQ(e["constraints"]["keep_out"]["candidates_inside"], 1);
  EXPECT_EQ(e["results"][0]["constraints"]["keep_out_violations"], json::array({"a"}));
  EXPECT_FALSE(e["results"][0]["constraints"]["satisfied"].get<bool>());
  EXPECT_NE(run.out.find("breaks           a lies inside a keep-out box"), std::string::npos)
      << run.out;
}

TEST(MountingCli, BadMountingRulesExitTwoWithFileAndLine) {
  test::TempDir dir;
  const std::string base = CubeWithSensors(
      dir, "  - {name: a, type: fine_cam, position: [0.5, 0.5, 0.05]}\n"
           "  - {name: c, type: fine_cam, position: [0.5, -0.5, 0.05]}\n");
  const std::string base_text = test::ReadText(base);
  const size_t lines = static_cast<size_t>(std::count(base_text.begin(), base_text.end(), '\n'));
  const std::vector<std::tuple<std::string, std::string, std::string>> cases = {
      {"min_separation: -1\n", "", "min_separation = -1 must be positive"},
      // Below a micrometre the neighbour hashing would overflow; beyond the world no mount exists.
      {"min_separation: 1e-300\n", "", "min_separation 1e-300 m is outside [1e-06, 1e+09] m"},
      {"min_separation: 1e300\n", "", "min_separation 1e+300 m is outside [1e-06, 1e+09] m"},
      // 10,000 candidates a millimetre apart: about 5e7 pairs under 0.5 m, refused before any
      // ray instead of filling the memory with them.
      {"min_separation: 0.5\npopulations:\n  - {name: dense, type: fine_cam, distribution: "
       "grid, rows: 1000, cols: 10, step: [0.001, 0.001, 0], pose: {xyz: [0.6, 0, 0.3]}}\n",
       "", "min_separation 0.5 m puts more than 5000000 pairs of the 10002 candidates in conflict"},
      {"keep_out:\n  - {min: [0, 0, 0], max: [1, 0, 1]}\n", "",
       "keep_out 'keep_out[0]': max must exceed min on every axis"},
      {"keep_out:\n  - {center: [0, 0, 0]}\n", "", "keep_out[0] has no 'size'"},
      {"keep_out:\n  - {size: [1, 1, 1], max: [1, 1, 1]}\n", "",
       "needs either `size` (and an optional `center`) or `min` and `max`"},
      {"keep_out:\n  - {size: [2, 2, 2], center: [0, 0, 0]}\n", "",
       "every one of the 2 candidates lies inside a keep_out box"},
  };
  for (const auto& [extra, flags, message] : cases) {
    const std::string scene = dir.File("bad.yaml");
    test::WriteText(scene, base_text + extra);
    const auto run =
        RunVantage("optimize " + scene + flags + " --out " + dir.File("x"));
    EXPECT_EQ(run.exit_code, 2) << extra;
    EXPECT_NE(run.err.find(scene + ":" + std::to_string(lines + (extra.find("keep_out") == 0 ? 2 : 1))),
              std::string::npos)
        << extra << ": " << run.err;
    EXPECT_NE(run.err.find(message), std::string::npos) << extra << ": " << run.err;
    EXPECT_FALSE(std::filesystem::exists(dir.File("x")));
  }
}

}  // namespace
}  // namespace vantage
