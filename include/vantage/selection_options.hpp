#pragma once
/// The selection options a caller gives (issue 42), declared once: `SelectionRequest` holds them,
/// and `kSelectionOptions` names each of them for every reader and writer: its CLI flag and help,
/// its Python keyword, its key in report.json's `inputs`, and the SelectOptions field that
/// SelectOptions::Validate blames. The CLI's flags, the Python module's reading of the keywords,
/// the run's recorded inputs (written and read back) and the pipeline's naming of the option at
/// fault are built from the table, so an option is added here (a member and its row) and where it
/// takes effect.
#include <array>
#include <cstdint>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <variant>

#include "vantage/select_states.hpp"
#include "vantage/settings.hpp"

namespace vantage {

/// Installation constraints of a run (docs/constraints.md), from the command line.
struct ConstraintOptions {
  /// --interference true|false: projecting sensors (ProjectsLight) may not light up more than
  /// `interference_overlap` of each other's observed cells. Unset: on wherever it applies (the
  /// coverage objective without states, kept sensors or refinement), off elsewhere.
  std::optional<bool> interference;
  std::optional<double> interference_overlap;  ///< --interference-overlap, fraction; default 0.1
  /// --calibration-overlap C: the chosen sensors' overlap graph (an edge: at least C common
  /// cells of R) must be connected.
  std::optional<uint64_t> calibration_overlap;
  /// --calibration-overlap-frac f: an edge needs a share f of the smaller of the two sets.
  std::optional<double> calibration_overlap_frac;
  double Overlap() const { return interference_overlap.value_or(0.1); }
  /// InputError naming the option: an overlap outside [0, 1], C < 1, f outside (0, 1], or both
  /// calibration options. (Defined in the pipeline, which checks it.)
  void Validate() const;
};

/// Selection settings given by the caller; unset: the scene's (SelectionSettings). Any of goal,
/// k and budget given replaces the scene's objective altogether (so --k 2 over a scene's goal
/// works). Each member but `constraints` has its row in SelectionOptionTable().
struct SelectionRequest {
  std::optional<int> n;                        ///< -n
  std::optional<Method> method;                ///< --method
  std::optional<int> ransac_iterations;        ///< --iterations
  std::optional<double> ransac_stop_coverage;  ///< --stop, fraction
  std::optional<double> time_limit;            ///< --time-limit [s], default 60
  std::optional<double> goal;                  ///< --goal, fraction
  bool cheapest = false;                       ///< --cheapest: the goal minimises cost
  std::optional<int> k;                        ///< --k
  std::optional<double> budget;                ///< --budget
  /// --min-points: a cell counts once the chosen sensors put this many pixels' hits in it
  /// (SelectOptions::min_points; docs/constraints.md, "Point density").
  std::optional<int64_t> min_points;
  /// --min-density [points per cm²]: min_points = ceil(D · F² in cm²), F the cell edge.
  std::optional<double> min_density;
  std::optional<OverStates> over_states;       ///< --over-states, for a scene with states
  /// --over-parts: maximise the mean or the worst of the target parts' coverages
  /// (Reference::part_of), each part weighted alike, instead of the coverage of all cells.
  std::optional<OverStates> over_parts;
  /// --keep-existing: every answer holds the explicitly declared sensors (candidates of no
  /// population: a world's cameras, a YAML scene's `sensors:`), SelectOptions::fixed.
  bool keep_existing = false;
  ConstraintOptions constraints;  ///< installation constraints
};

/// One option of SelectionRequest as every reader and writer names it.
struct SelectionOption {
  /// The request's member: its type says how each reader parses it (a whole number, a number,
  /// a flag, a method or an aggregation's name).
  using Member = std::variant<std::optional<int> SelectionRequest::*,
                              std::optional<int64_t> SelectionRequest::*,
                              std::optional<double> SelectionRequest::*, bool SelectionRequest::*,
                              std::optional<Method> SelectionRequest::*,
                              std::optional<OverStates> SelectionRequest::*>;
  std::string_view cli_names;  ///< CLI11's names, e.g. "-n,--sensors"
  std::string_view flag;       ///< the flag an error names, e.g. "-n"
  std::string_view keyword;    ///< the Python keyword
  std::string_view input;      ///< the key in report.json's `inputs`
  /// The SelectOptions field that SelectOptions::Validate names when this option is at fault
  /// (FieldError::fields), also the key of SelectionSettings::lines.
  std::string_view field;
  std::string_view help;  ///< the CLI's help
  Member member;
  /// The SelectOptions field the option's value goes to as it is (ResolveSelection copies every
  /// given option by its row); monostate for those the pipeline converts (min_points and
  /// min_density with the cell size, keep_existing into the kept candidates) or reads itself
  /// (over_states, over_parts).
  using Target = std::variant<std::monostate, int SelectOptions::*, double SelectOptions::*,
                              std::optional<double> SelectOptions::*, bool SelectOptions::*,
                              Method SelectOptions::*>;
  Target target;
  /// Part of the model's objective: given, it replaces the scene's objective settings (goal, k,
  /// budget) altogether, so --k 2 over a scene's goal works.
  bool objective = false;
  /// An objective's line in the run's summary (after "objective"), when given; null for the
  /// options the summary describes by their results (goal, k, budget, min_points).
  std::string (*summary)(const SelectionRequest& request) = nullptr;
  /// An objective whose coverage aggregates groups of R's cells (as selection over states does):
  /// its report leaves out what re-counts all cells as one set (Report::CountsGroups), and
  /// optimize refuses it beside --refine, --by-type and an arm's tour (beside the scene's
  /// states it aggregates every state's groups).
  bool aggregates_groups = false;

  /// Whether `request` gives this option (a value, or the flag set).
  bool GivenIn(const SelectionRequest& request) const;
  /// Copies the option's value, when `request` gives it, into its SelectOptions field (target);
  /// nothing for a row without a target.
  void ApplyTo(const SelectionRequest& request, SelectOptions* options) const;
};

/// Every option of SelectionRequest but the constraints, in the order of `--help` (and of
/// report.json's `inputs`): cli_names, flag, keyword, input, field, help, member, target,
/// objective, summary, aggregates_groups.
inline constexpr std::array<SelectionOption, 14> kSelectionOptions = {{
    {"-n,--sensors", "-n", "n", "n", "n", "number of sensors wanted (default: the scene's)",
     &SelectionRequest::n, &SelectOptions::n},
    {"--method", "--method", "method", "method", "method",
     "best | ransac | greedy | local | exact | all (default: the scene's, else all: every "
     "method, compared)",
     &SelectionRequest::method, &SelectOptions::method},
    {"--iterations", "--iterations", "iterations", "ransac_iterations", "ransac_iterations",
     "RANSAC iteration cap (default: the scene's); --method all runs it at the N asked and "
     "shares 5e5 drawn sensors among the smaller N's",
     &SelectionRequest::ransac_iterations, &SelectOptions::ransac_iterations},
    {"--stop", "--stop", "stop", "ransac_stop_coverage", "ransac_stop_coverage",
     "RANSAC stops at this coverage, fraction 0..1 (default: the scene's)",
     &SelectionRequest::ransac_stop_coverage,
     &SelectOptions::ransac_stop_coverage},
    {"--time-limit", "--time-limit", "time_limit", "time_limit", "time_limit",
     "seconds for the exact method, the greedy and local search it starts from included "
     "(default: 60); --method all runs its N's on up to 2 threads at once, each thread's N's "
     "sharing the smaller of it and 9 s of wall time, each N an equal part of what that thread "
     "has left for the N's it still expects",
     &SelectionRequest::time_limit, &SelectOptions::time_limit},
    {"--goal", "--goal", "goal", "goal", "goal",
     "objective: the fewest sensors whose coverage reaches this fraction 0..1 (set cover)",
     &SelectionRequest::goal, &SelectOptions::goal, true},
    {"--cheapest", "--cheapest", "cheapest", "cheapest", "minimize_cost",
     "with --goal: the cheapest sensors (their types' cost) reaching it, not the fewest",
     &SelectionRequest::cheapest, &SelectOptions::minimize_cost},
    {"--k", "--k", "k", "k", "k",
     "objective: k-coverage, a cell counts once k chosen sensors see it (k >= 2); with --goal "
     "or --budget: the goal or the budget's coverage counts cells seen k times",
     &SelectionRequest::k, &SelectOptions::k, true},
    {"--budget", "--budget", "budget", "budget", "budget",
     "objective: the most coverage for a total sensor cost within this budget (counted k times "
     "with --k, in points with --min-points)",
     &SelectionRequest::budget, &SelectOptions::budget, true},
    {"--min-points", "--min-points", "min_points", "min_points", "min_points",
     "point density: a cell counts once the chosen sensors together put at least this many "
     "pixels' hits in it (1..65535; docs/constraints.md)",
     &SelectionRequest::min_points, {}, true},
    {"--min-density", "--min-density", "min_density", "min_density", "min_points",
     "point density in points per cm² of a cell's face (F²), converted to --min-points = "
     "ceil(D * F²)",
     &SelectionRequest::min_density, {}, true},
    {"--over-states", "--over-states", "over_states", "over_states", "over_states",
     kOverStatesHelp, &SelectionRequest::over_states, {}},
    {"--over-parts", "--over-parts", "over_parts", "over_parts", "over_parts",
     "objective: maximise the mean or the worst (min) of the target parts' coverages, each part "
     "alike (with states: of every state's parts, as --over-states if given, which must match; "
     "not with --refine, --by-type or an arm's tour)",
     &SelectionRequest::over_parts,
     {},
     false,
     [](const SelectionRequest& request) {
       return "the " + std::string(AggregationOf(*request.over_parts).phrase) +
              " of the target parts' coverages (coverages below are that; each part's follows)";
     },
     true},
    {"--keep-existing", "--keep-existing", "keep_existing", "keep_existing", "fixed",
     "every answer keeps the sensors the scene declares (a gz-sim world's cameras, a YAML "
     "scene's `sensors:`) and adds to them; -n counts them",
     &SelectionRequest::keep_existing, {}},
}};

/// kSelectionOptions.
std::span<const SelectionOption> SelectionOptionTable();
/// `request` with the scene's setting (scene_settings.hpp) of each option it leaves unset,
/// matched by field; none of the scene's objective settings (goal, k, budget) when the request
/// gives an objective option (SelectionOption::objective).
SelectionRequest RequestOverScene(const SelectionRequest& request,
                                  const SelectionSettings& scene);
/// The row whose Python keyword is `keyword`; InternalError when none is.
const SelectionOption& SelectionOptionOfKeyword(std::string_view keyword);

}  // namespace vantage
