// The selection options' one declaration (selection_options.hpp, issue 42): the readers and
// writers built from it give what each of them gave when it spelled the options out itself.
#include <gtest/gtest.h>

#include <nlohmann/json.hpp>
#include <string>

#include "report/run_inputs.hpp"
#include "test_util.hpp"
#include "vantage/error.hpp"
#include "vantage/pipeline.hpp"
#include "vantage/selection_options.hpp"

namespace vantage {
namespace {

using nlohmann::json;

SelectionRequest EveryOptionGiven() {
  SelectionRequest request;
  request.n = 3;
  request.method = Method::kLocal;
  request.ransac_iterations = 250;
  request.ransac_stop_coverage = 0.75;
  request.time_limit = 12.5;
  request.goal = 0.6;
  request.cheapest = true;
  request.k = 2;
  request.budget = 1500;
  request.min_points = 40000;
  request.min_density = 2.5;
  request.over_states = OverStates::kMin;
  request.keep_existing = true;
  request.constraints.interference = true;
  request.constraints.interference_overlap = 0.2;
  request.constraints.calibration_overlap = 7;
  request.constraints.calibration_overlap_frac = 0.05;
  return request;
}

// report.json's inputs as they were written before the table (one Put per field, in this order
// but for cheapest, which the table puts beside --goal as --help does).
TEST(SelectionOptions, InputsAreWrittenUnderTheirKeys) {
  RunInputs inputs;
  inputs.selection = EveryOptionGiven();
  const json written = json::parse(detail::RunInputsJson(inputs).dump());
  const json expected = {{"n", 3},
                         {"method", "local"},
                         {"ransac_iterations", 250},
                         {"ransac_stop_coverage", 0.75},
                         {"time_limit", 12.5},
                         {"goal", 0.6},
                         {"cheapest", true},
                         {"k", 2},
                         {"budget", 1500.0},
                         {"min_points", 40000},
                         {"min_density", 2.5},
                         {"over_states", "min"},
                         {"keep_existing", true},
                         {"interference", true},
                         {"interference_overlap", 0.2},
                         {"calibration_overlap", 7},
                         {"calibration_overlap_frac", 0.05}};
  for (const auto& [key, value] : expected.items()) {
    ASSERT_TRUE(written.contains(key)) << key;
    EXPECT_EQ(written[key], value) << key;
  }
  // Nothing given: no key at all (flags written only when set).
  const json empty = json::parse(detail::RunInputsJson(RunInputs{}).dump());
  for (const auto& [key, value] : expected.items()) EXPECT_FALSE(empty.contains(key)) << key;
}

TEST(SelectionOptions, InputsReadBackAsGiven) {
  RunInputs inputs;
  inputs.selection = EveryOptionGiven();
  const json written = json::parse(detail::RunInputsJson(inputs).dump());
  const SelectionRequest read = detail::ParseRunInputs(written, "run/report.json").selection;
  const SelectionRequest given = EveryOptionGiven();
  EXPECT_EQ(read.n, given.n);
  EXPECT_EQ(read.method, given.method);
  EXPECT_EQ(read.ransac_iterations, given.ransac_iterations);
  EXPECT_EQ(read.ransac_stop_coverage, given.ransac_stop_coverage);
  EXPECT_EQ(read.time_limit, given.time_limit);
  EXPECT_EQ(read.goal, given.goal);
  EXPECT_EQ(read.cheapest, given.cheapest);
  EXPECT_EQ(read.k, given.k);
  EXPECT_EQ(read.budget, given.budget);
  EXPECT_EQ(read.min_points, given.min_points);
  EXPECT_EQ(read.min_density, given.min_density);
  EXPECT_EQ(read.over_states, given.over_states);
  EXPECT_EQ(read.keep_existing, given.keep_existing);
  EXPECT_EQ(read.constraints.interference, given.constraints.interference);
  EXPECT_EQ(read.constraints.interference_overlap, given.constraints.interference_overlap);
  EXPECT_EQ(read.constraints.calibration_overlap, given.constraints.calibration_overlap);
  EXPECT_EQ(read.constraints.calibration_overlap_frac,
            given.constraints.calibration_overlap_frac);
}

TEST(SelectionOptions, AWrongInputNamesItsKey) {
  const auto message = [](json inputs) {
    try {
      detail::ParseRunInputs(inputs, "run/report.json");
    } catch (const InputError& e) {
      return std::string(e.what());
    }
    return std::string("accepted");
  };
  EXPECT_EQ(message({{"k", "two"}}),
            "run/report.json: inputs.k must be a whole number — give a report.json written by "
            "vantage");
  EXPECT_EQ(message({{"cheapest", 1}}),
            "run/report.json: inputs.cheapest must be true or false — give a report.json written "
            "by vantage");
  EXPECT_NE(message({{"method", "fastest"}}).find("run/report.json: inputs.method: unknown method "
                                                  "'fastest'"),
            std::string::npos);
  EXPECT_NE(message({{"over_states", "max"}}).find("run/report.json: inputs.over_states:"),
            std::string::npos);
}

// The request's option at fault is named by its flag, in the order the pipeline blamed them
// before the table: min_points before k, k before goal, the goal before the method.
TEST(SelectionOptions, TheFlagAtFaultIsNamed) {
  const std::vector<Candidate> candidates(4);
  const auto blamed = [&](const SelectionRequest& request) {
    try {
      ResolveSelection(SelectionSettings{}, request, 1, candidates, "scene.yaml", Method::kAll);
    } catch (const InputError& e) {
      const std::string message = e.what();
      return message.substr(0, message.find(':'));
    }
    return std::string("accepted");
  };
  SelectionRequest points_and_k;
  points_and_k.k = 2;
  points_and_k.min_points = 3;
  EXPECT_EQ(blamed(points_and_k), "--min-points");
  SelectionRequest cheapest;
  cheapest.cheapest = true;
  EXPECT_EQ(blamed(cheapest), "--cheapest");
  SelectionRequest best_for_goal;
  best_for_goal.method = Method::kBest;
  best_for_goal.goal = 0.5;
  EXPECT_EQ(blamed(best_for_goal), "--goal");
  SelectionRequest k_above_n;  // needs n >= k: both fields at fault, n named first
  k_above_n.n = 1;
  k_above_n.k = 2;
  EXPECT_EQ(blamed(k_above_n), "-n");
  k_above_n.n.reset();  // the scene's n: the flag given is blamed
  EXPECT_EQ(blamed(k_above_n), "--k");
  SelectionRequest too_many;
  too_many.n = 5;
  EXPECT_EQ(blamed(too_many), "-n");
}

// The request's options reach SelectOptions through their rows: each value given lands in its
// field as given, the converted ones (min_points, keep_existing) as the pipeline derives them.
TEST(SelectionOptions, EveryGivenValueReachesItsField) {
  // Every option given, less those this objective (a goal, at the cheapest) cannot take with it.
  SelectionRequest request = EveryOptionGiven();
  request.method = Method::kGreedy;
  request.k.reset();
  request.budget.reset();
  request.min_points.reset();  // min_density gives it: 2.5 per cm² on a 2 cm cell's 4 cm² face: 10
  request.over_states.reset();
  request.constraints = {};
  std::vector<Candidate> candidates(4);
  for (Candidate& candidate : candidates) {
    candidate.sensor.cost = 100;
    candidate.sensor.cost_given = true;
    candidate.type_id = "custom";
    candidate.sensor.id = "custom";
    candidate.population = "grid";
  }
  candidates[2].population.clear();  // declared by the scene
  request.keep_existing = true;
  SelectionSettings scene;
  scene.n = 2;
  scene.ransac_iterations = 9;
  scene.budget = 300;  // an objective given: the scene's is not taken
  const SelectOptions options =
      ResolveSelection(scene, request, 7, candidates, "scene.yaml", Method::kAll, 0.02);
  EXPECT_EQ(options.n, 3);
  EXPECT_EQ(options.method, Method::kGreedy);
  EXPECT_EQ(options.ransac_iterations, 250);
  EXPECT_EQ(options.ransac_stop_coverage, 0.75);
  EXPECT_EQ(options.time_limit, 12.5);
  EXPECT_EQ(options.goal, 0.6);
  EXPECT_EQ(options.goal_source, "--goal");
  EXPECT_TRUE(options.minimize_cost);
  EXPECT_EQ(options.k, 1);
  EXPECT_FALSE(options.budget);
  EXPECT_EQ(options.min_points, 10u);
  EXPECT_EQ(options.fixed, std::vector<uint32_t>{2});
  EXPECT_EQ(options.costs, std::vector<double>(4, 100));
  EXPECT_EQ(options.seed, 7u);
}

// What the request leaves unset comes from the scene: its objective (goal, k, budget) only when
// the request gives none of goal, k, budget, min_points, min_density.
TEST(SelectionOptions, TheSceneFillsWhatTheRequestLeavesUnset) {
  const std::vector<Candidate> candidates(5);
  SelectionSettings scene;
  scene.n = 4;
  scene.method = Method::kLocal;
  scene.ransac_iterations = 9;
  scene.ransac_stop_coverage = 0.5;
  scene.k = 3;
  scene.lines["k"] = 12;
  const SelectOptions from_scene =
      ResolveSelection(scene, SelectionRequest{}, 1, candidates, "scene.yaml", Method::kAll);
  EXPECT_EQ(from_scene.n, 4);
  EXPECT_EQ(from_scene.method, Method::kLocal);
  EXPECT_EQ(from_scene.ransac_iterations, 9);
  EXPECT_EQ(from_scene.ransac_stop_coverage, 0.5);
  EXPECT_EQ(from_scene.k, 3);
  EXPECT_EQ(from_scene.time_limit, 60);
  EXPECT_FALSE(from_scene.goal);
  SelectionRequest points;  // an objective: the scene's k is dropped
  points.min_points = 5;
  const SelectOptions over_points =
      ResolveSelection(scene, points, 1, candidates, "scene.yaml", Method::kAll);
  EXPECT_EQ(over_points.k, 1);
  EXPECT_EQ(over_points.min_points, 5u);
  EXPECT_EQ(over_points.n, 4);
  scene.method.reset();
  scene.k = 1;
  scene.goal = 0.5;
  scene.lines["goal"] = 14;
  SelectionRequest method;  // not an objective: the scene's goal stays, named by its line
  method.method = Method::kGreedy;
  const SelectOptions over_goal =
      ResolveSelection(scene, method, 1, candidates, "scene.yaml", Method::kAll);
  EXPECT_EQ(over_goal.goal, 0.5);
  EXPECT_EQ(over_goal.goal_source, "scene.yaml:14");
  EXPECT_EQ(over_goal.method, Method::kGreedy);
  EXPECT_EQ(ResolveSelection(scene, SelectionRequest{}, 1, candidates, "s", Method::kExact).method,
            Method::kExact);
}

// Every row is a flag of optimize and select, with its help (the CLI is built from the table).
TEST(SelectionOptions, EveryRowIsAFlag) {
  for (const char* command : {"optimize", "select"}) {
    const test::CommandResult help = test::RunVantage(std::string("help ") + command);
    ASSERT_EQ(help.exit_code, 0) << help.err;
    // CLI11 wraps long help: compare with the spaces and line breaks folded.
    std::string folded;
    for (const char c : help.out) {
      const bool space = c == ' ' || c == '\n';
      if (!space || (!folded.empty() && folded.back() != ' ')) folded += space ? ' ' : c;
    }
    for (const SelectionOption& option : SelectionOptionTable()) {
      EXPECT_NE(folded.find(std::string(option.flag)), std::string::npos) << option.flag;
      const std::string help_start(option.help.substr(0, 30));
      EXPECT_NE(folded.find(help_start), std::string::npos) << command << " " << option.flag;
    }
  }
}

}  // namespace
}  // namespace vantage
