#pragma once
/// The subcommands of the `vantage` binary: each registers its options on the CLI11 app and
/// runs through the library. Only main.cpp maps errors to exit codes.
#include <CLI/CLI.hpp>

#include <optional>
#include <string>
#include <vector>

#include "vantage/scene_states.hpp"
#include "vantage/select_states.hpp"
#include "vantage/vantage.hpp"
#include "vantage/visualize.hpp"

namespace vantage::cli {

/// Options shared by every command that loads a scene.
struct SceneOptions {
  std::string scene;
  std::vector<std::string> model_paths;
  std::vector<std::string> resource_paths;
  std::vector<std::string> targets;
  std::optional<double> cell_size;
  std::optional<uint64_t> seed;
  std::vector<double> observation_point;  ///< x y z, or empty = the scene's
  std::optional<bool> random_roll;        ///< unset = the scene's
  bool no_cull = false;
  std::optional<double> max_incidence_deg;   ///< --max-incidence: quality filter [deg]
  std::optional<double> max_depth_noise_mm;  ///< --max-depth-noise: quality filter [mm]
  double max_memory_mib = 0;  ///< 0 = 75 % of the machine's RAM
};

/// Options of selection, given on the command line (unset = the scene's value).
struct SelectionOptions {
  std::optional<int> n;
  std::optional<std::string> method;
  std::optional<int> iterations;
  std::optional<double> stop_coverage;
  double time_limit = 60;
  /// Objectives: any of these given replaces the scene's goal/k/budget altogether.
  std::optional<double> goal;    ///< --goal: fewest sensors reaching this coverage
  std::optional<int> k;          ///< --k: k-coverage
  std::optional<double> budget;  ///< --budget: total sensor cost cap
  /// Robustness read-outs of the primary result (issue 9).
  double fov_tolerance_deg = 3;     ///< --fov-tolerance
  double alternatives_within = 1;   ///< --alternatives-within, coverage points
  /// --over-states mean|min: how a scene with states is scored (default mean).
  std::optional<std::string> over_states;
};

/// Refuses a negative --seed (CLI11 would wrap "-1" to 2^64 - 1); main.cpp puts it on every
/// command's --seed.
CLI::Validator SeedValidator();

void AddSceneOptions(CLI::App* app, SceneOptions* options, bool with_positional = true);
void AddSelectionOptions(CLI::App* app, SelectionOptions* options);

/// The quality filter of --max-incidence / --max-depth-noise; InputError naming the option.
QualityFilter QualityOf(const SceneOptions& options);

/// Loads the scene with the command-line overrides applied.
Problem LoadScene(const SceneOptions& options);

/// One state of a changing scene, observed.
struct ObservedState {
  std::string name;
  Reference reference;
  std::vector<Observation> observations;
  int same_as = -1;  ///< index of an earlier state with the same geometry (not traced again)
};

/// Result of the first half of the pipeline.
struct ObservedScene {
  VisibilityFile data;
  Timings timings;
  std::vector<std::string> notes;
  Scene scene;  ///< the loaded geometry, for report.html
  /// Where the candidates came from, for constellation.world.
  std::vector<Population> populations;
  std::vector<ExplicitSensor> sensors;
  Vec3 observation_point = Vec3::Zero();  ///< what the candidates look at (for --refine)
  /// A scene with states: each state's reference and observations, in state order (`data`
  /// holds the first state's too); empty for a scene without states.
  std::vector<ObservedState> states;
};
/// Load -> reference -> candidates -> observe, logging each stage.
ObservedScene ObserveScene(const SceneOptions& options, const SelectionOptions* selection);

/// Selection options resolved from the file's defaults and the command line.
SelectOptions ResolveSelectOptions(const VisibilityFile& data, const SelectionOptions& cli,
                                   std::optional<uint64_t> seed, const std::string& method_default);
/// Prints the human summary of a run to stdout: its results, states, refinement and robustness.
void PrintSummary(const Report& report, const std::string& out_dir);

/// Runs selection: over the states (SelectOverStates) when the scene has them, else Select.
/// Fills `report`'s results and states block.
void SelectResults(const ObservedScene& observed, const SelectionOptions& cli, const SelectOptions& options,
                   Report* report);

void SetupOptimize(CLI::App* parent);
void SetupObserve(CLI::App* parent);
void SetupSelect(CLI::App* parent);
void SetupEvaluate(CLI::App* parent);
void SetupSensors(CLI::App* parent);
void SetupRender(CLI::App* parent);

/// Every candidate of `evaluator` as one "given" selection, with its coverage (evaluate, render).
Selection WholeConstellation(const CoverageEvaluator& evaluator);

/// Seconds since `start` on the steady clock.
double SecondsSince(std::chrono::steady_clock::time_point start);

}  // namespace vantage::cli
