#pragma once
/// Outputs of a run (SYSTEM.md, Outputs): report.json (vantage.report/1), candidates.csv,
/// reference.ply, observed.ply; written into a temporary folder and renamed into place.
#include <map>
#include <optional>
#include <set>
#include <string>
#include <vector>

#include "vantage/pose_tolerance.hpp"
#include "vantage/robustness.hpp"
#include "vantage/select.hpp"
#include "vantage/selection_options.hpp"
#include "vantage/tour.hpp"
#include "vantage/visibility_file.hpp"

namespace vantage {

/// Version of vantage, as written in report.json.
const char* Version();

struct Timings {
  double load = 0, reference = 0, observe = 0, select = 0, total = 0;
};

/// `optimize --by-type` (issue 43, docs/sensor-models.md "Which sensor to buy"): one sensor type
/// among the candidates, its best constellations of that type alone.
struct TypeComparison {
  std::string type_id;
  std::string name;      ///< display name (the type's, else its id)
  size_t candidates = 0;  ///< the run's candidates of this type
  double unit_cost = 0;   ///< SensorType::cost
  /// False when its vendor publishes no price (UnitCostGiven): unit_cost and every total cost
  /// with it are then not given.
  bool unit_cost_given = true;
  /// Why the physical model sees this type as the ideal pinhole ("" when it does not:
  /// PhysicalModelGap), stated beside its row when the run was physical.
  std::string physical_gap;
  /// Per n from 1 (k with k-coverage) to the run's n, at most the type's candidates: the best
  /// answer over this type's candidates alone, chosen by the run's selection (same method,
  /// objective and constraints). `chosen` indexes the run's candidates; `upper_bound` is the
  /// least bound any method proved at that n, `proven_optimal` whether one proved it optimal;
  /// `cost` the total unit cost.
  std::vector<Selection> best;
};

/// `optimize --by-type`: every type alone and the mix of all of them.
struct TypeComparisonTable {
  std::vector<TypeComparison> types;  ///< in order of the types' first candidates
  /// Per n, the run's own best answer over all candidates (its results and curve), shaped as
  /// TypeComparison::best.
  std::vector<Selection> mix;
  bool physical = false;  ///< observed with the physical sensor model
};

/// What `--refine` did (issue 9): the refined constellation is results[result], grown from
/// results[from_result] by tracing new poses around its sensors.
struct RefinementInfo {
  int from_result = -1;
  int result = -1;
  double coverage_before = 0, coverage_after = 0;
  std::vector<double> history;  ///< coverage after each round, coverage_before first
  int rounds = 0;
  size_t new_candidates = 0;
  uint64_t extra_rays = 0;
  double seconds = 0;
};

/// A scene with states: how results were scored and what each state is.
struct StatesInfo {
  std::string over;  ///< "mean" or "min"
  struct State {
    std::string name;
    size_t reference_voxels = 0;
    int same_as = -1;  ///< an earlier state with the same geometry, whose rays it reuses
  };
  std::vector<State> states;
};

/// What shaped a run, as report.json's `inputs` block records it (docs/outputs.md), so that
/// `render`, `evaluate` and a rerun reproduce the run from its output folder alone. Paths are
/// absolute; unset options were not given (the scene's own values applied).
struct RunInputs {
  std::string command;  ///< optimize, select or evaluate
  std::string scene;    ///< the scene file
  std::vector<std::string> model_paths;     ///< --model-path
  std::vector<std::string> resource_paths;  ///< --resource-path
  std::vector<std::string> package_paths;   ///< --package-path (written only when given)
  std::vector<std::string> targets;         ///< --target
  std::optional<double> cell_size;          ///< --cell-size
  std::optional<uint64_t> seed;             ///< --seed
  std::optional<Vec3> observation_point;    ///< --observation-point
  std::optional<bool> random_roll;          ///< --random-roll
  bool exposed_only = false;                ///< --exposed-only
  bool cull = true;                         ///< false: --no-cull
  /// The sensor model the run used (--ideal, --physical or the scene's default): written as
  /// `sensor_model: "physical"` when physical, left out when ideal (reports as before issue 43).
  bool physical = false;
  QualityFilter quality;                    ///< --max-incidence, --max-depth-noise
  /// -n, --method, ..., --keep-existing and the installation constraints, as given (each
  /// option's `inputs` key: SelectionOptionTable()).
  SelectionRequest selection;
  bool refine = false;                      ///< --refine
  std::optional<int> refine_rounds;         ///< --refine-rounds
  std::optional<double> fov_tolerance_deg;  ///< --fov-tolerance
  std::optional<double> pose_tolerance_m;   ///< --pose-tolerance, its position [m]
  std::optional<double> pose_tolerance_deg;  ///< --pose-tolerance, its angle [deg]
  std::optional<int> pose_samples;          ///< --pose-samples
  std::optional<double> alternatives_within;  ///< --alternatives-within, coverage points
  std::string visibility_file;              ///< select: the .vis file
  std::string constellation;                ///< evaluate: the constellation file
};

/// One chosen sensor of the primary result, in the order chosen.
struct ChosenSensor {
  uint32_t index = 0;        ///< candidate index
  double marginal_gain = 0;  ///< share of R it adds to those chosen before it
  double cumulative = 0;     ///< share of R of it and those before it
};

/// One target part of R (a target object by name; Reference::part_names), as report.json's
/// `ceiling.parts` and the summary's parts table show it.
struct TargetPart {
  std::string name;
  size_t cells = 0;      ///< its cells in R
  size_t unexposed = 0;  ///< of them, no viewpoint can see (Reference::exposed; 0 when unknown)
  size_t left_out = 0;   ///< --exposed-only: its unexposed cells, left out of R
  double ceiling = 0;    ///< the share of its cells that all candidates reach together
};

/// Everything one report holds. The writers (ReportJson, HtmlReport, ...) only serialise it: the
/// values derived from the results are computed once, by DeriveReport, before any writer runs.
/// The installation constraints of a run (docs/constraints.md): what selection had to satisfy, or
/// (evaluate) what the layout is checked against.
struct ConstraintsInfo {
  InstallConstraints constraints;              ///< conflicting pairs, calibration rule
  std::optional<double> interference_overlap;  ///< set when interference is on
  size_t projecting = 0;                       ///< candidates whose type projects light
  std::optional<double> min_separation;        ///< [m], the scene's, when set
  /// The scene's keep-out boxes (report.json `constraints.keep_out`, report.html's 3D view).
  std::vector<KeepOutBox> keep_out_boxes;
  size_t keep_out_excluded = 0;  ///< candidates the boxes excluded before observing
  /// Candidates inside a keep-out box (evaluate: given sensors; optimize: none, all excluded).
  std::vector<uint32_t> keep_out_violations;
  bool is_applied = true;  ///< selection obeyed them (false: evaluate only checks them)
};

/// The waypoints of a move planned around a collision (its ends excluded), straight between
/// them, each with when the arm reaches it [s after the move starts].
struct ArmVia {
  std::vector<std::vector<double>> waypoints;
  std::vector<double> seconds;
  bool empty() const { return waypoints.empty(); }
};

/// One camera on an arm (issue 45): the tour of a result's views, home to home (docs/arm.md).
struct ArmTour {
  std::string robot;
  std::string population;
  std::vector<std::string> joint_names;  ///< the layout of every configuration
  std::vector<double> home;
  std::vector<uint32_t> views;           ///< candidate indices, in tour order
  std::vector<std::vector<double>> configurations;  ///< per view, in tour order
  std::vector<double> move_seconds;      ///< per view: the move that reaches it
  /// Per view: the waypoints between the previous stop and it when the straight move collides
  /// and the planner went around; empty for a straight move.
  std::vector<ArmVia> move_via;
  ArmVia return_via;  ///< the same for the move back to home
  std::vector<double> acquisition_seconds;  ///< per view: frames / fps
  double return_seconds = 0;             ///< the last view back to home
  Tour tour;                             ///< method, exactness, totals
  double resolution = 0;                 ///< [rad or m] of the straight moves' collision check
  size_t unconnected_pairs = 0;  ///< checked moves that collide and the planner did not connect
  size_t planned_pairs = 0;      ///< checked moves that collide and the planner went around
  /// --track: per view, the state it is taken in (views then in state order, a view repeated
  /// when the arm stays); empty for a tour.
  std::vector<std::string> states;
  /// --track --state-interval [s]: the states' spacing; each view's acquisition starts at the
  /// first's plus its state's index times this (the arm waits there when it arrives early).
  std::optional<double> state_interval;
};

/// `optimize --track` (issue 45, docs/arm.md): one camera on an arm follows the scene's states,
/// one view per state, the exact best of Σ coverage − move_penalty · Σ move seconds.
struct TrackInfo {
  double move_penalty = 0;               ///< coverage (fraction) per second of motion
  std::optional<double> state_interval;  ///< [s]
  double value = 0;                      ///< the objective of the answer
  double coverage_sum = 0;               ///< Σ over the states of the view's coverage
  double move_seconds = 0;               ///< Σ of the moves into the states (home's first)
  struct State {
    std::string name;
    uint32_t view = 0;          ///< candidate index
    double coverage = 0;        ///< the view's coverage of this state's R
    double move_seconds = 0;    ///< the move that reaches it (from home, or the last state's)
    bool planned = false;       ///< that move goes around a collision (OMPL)
    size_t views_free = 0;      ///< the arm's views collision-free in this state
  };
  std::vector<State> states;
  size_t views = 0;          ///< the arm's views considered
  size_t checked_moves = 0;  ///< moves collision-checked (only those an answer used)
  size_t solves = 0;         ///< dynamic programmes solved (again after a move got slower)
};

/// A camera on an arm as a run folder's views.yaml gives it (render draws the arm at a view).
struct ArmViewsFile {
  std::string robot;
  std::vector<std::string> joint_names;
  std::vector<std::string> views;                 ///< candidate names, in tour (or state) order
  std::vector<std::vector<double>> positions;     ///< per view, one per joint name
  std::vector<int> lines;                         ///< per view, its line in the file
};
/// Reads views.yaml (detail: src/report/arm_export.cpp). InputError at the file's line when it is
/// not one vantage writes.
ArmViewsFile ReadArmViews(const std::string& path);

struct Report {
  std::string scene;
  uint64_t seed = 1;
  const VisibilityFile* data = nullptr;  ///< reference, candidates, observations (not owned)
  std::vector<Selection> results;
  /// The coverage-versus-n curve's extra answers (CoverageCurve; report.json `curve`): results at
  /// the n that `results` lacks. Never primary.
  std::vector<Selection> curve;
  Timings timings;
  std::vector<std::string> notes;
  /// Read-outs for one result (usually the primary), when computed (issue 9).
  std::optional<Robustness> robustness;
  /// --pose-tolerance: every result's coverage over perturbed layouts (report.json
  /// `pose_tolerance`).
  std::optional<PoseTolerance> pose_tolerance;
  std::optional<RefinementInfo> refinement;
  /// Set for a scene with states; `data` then holds the first state's reference and sets.
  std::optional<StatesInfo> states;
  /// Whether the results' coverage aggregates groups of cells: over the scene's states, or by
  /// an objective of the inputs whose row says so (SelectionOption::aggregates_groups). What
  /// re-counts the cells of `data` as one set (plain and ideal coverage per result, robustness,
  /// pose tolerance) is then not comparable with it, and is left out.
  bool CountsGroups() const;
  /// What shaped the run (report.json `inputs`); absent for reports built by hand.
  std::optional<RunInputs> inputs;
  /// Set when any installation constraint is on (report.json `constraints`, per result too).
  std::optional<ConstraintsInfo> constraints;
  /// A camera on an arm: per result (the index of `results`), its tour; empty when no result's
  /// views are on an arm.
  std::vector<std::optional<ArmTour>> tours;
  /// The same for `curve`'s answers (none where a tour cannot be connected).
  std::vector<std::optional<ArmTour>> curve_tours;
  /// --cycle-time [s], when given: `results` holds the most coverage found within it.
  std::optional<double> cycle_time;
  /// --track: the view per state (report.json `track`); results[0] holds its distinct views.
  std::optional<TrackInfo> track;
  /// `optimize --by-type`: the best constellation of each sensor type alone, per n (report.json
  /// `by_type`).
  std::optional<TypeComparisonTable> by_type;

  // Derived by DeriveReport.
  bool is_derived = false;
  /// Index into `results` of the result that stands for the run (PrimaryResult); -1: none.
  int primary = -1;
  /// With a quality filter and no states: per result its coverage counting every pixel (under
  /// its k); empty otherwise.
  std::vector<double> result_plain_coverage;
  /// With a quality filter: per candidate its coverage counting every pixel; empty otherwise.
  std::vector<double> candidate_plain_coverage;
  /// Observed with the physical sensor model and no states: per result the coverage its
  /// sensors would have under the paper's ideal pinhole (same filter, its k); empty otherwise.
  std::vector<double> result_ideal_coverage;
  /// Observed with the physical sensor model: per candidate its ideal-pinhole coverage.
  std::vector<double> candidate_ideal_coverage;
  /// The primary result's sensors with their marginal gains; empty without a primary.
  std::vector<ChosenSensor> primary_sensors;
  /// The candidate that sees the most of R alone (ties: the first); -1 without candidates.
  int best_single = -1;
  /// The ceiling: the coverage all candidates reach together, counted as the results count it
  /// (their k or min_points; plain coverage without results). Unset with states (the results
  /// count over states; `data` holds the first only) or without candidates.
  std::optional<double> ceiling;
  /// R's target parts, each with its ceiling; empty when R does not know its parts (an old
  /// visibility file) or with states.
  std::vector<TargetPart> parts;
  /// Per result, per part (as `parts`): the share of the part's cells the result covers. Empty
  /// when `parts` is.
  std::vector<std::vector<double>> result_part_coverage;
  /// Whether R's exposure is known (Reference::exposed), and how many of its cells are
  /// unexposed (with --exposed-only: how many were left out of R).
  bool exposure_known = false;
  size_t unexposed = 0;

  /// The primary result's chosen candidates (empty without one). Requires is_derived.
  const std::vector<uint32_t>& PrimaryChosen() const;
};

/// Fills the derived fields of `report` from its data and results (once, before the writers).
/// Requires report->data.
void DeriveReport(Report* report);

/// The result whose optimality proves results[index] optimal: itself when proven, else a proven
/// optimal result of the same objective and n whose coverage it equals (exact proved that no
/// layout of n does better, so this one is optimal too). -1 when none.
int ProvenBy(const std::vector<Selection>& results, int index);

/// How results[index] is named wherever a method is named: "greedy n=3", "exact n=3 (proven
/// optimal)", "greedy n=3 (proven optimal by exact)".
std::string ResultLabel(const std::vector<Selection>& results, int index);

/// The result that stands for the run: among those with the largest n, the highest coverage
/// (ties: the first). -1 when there is no result.
int PrimaryResult(const std::vector<Selection>& results);

/// The report.json text (pretty-printed, keys of SYSTEM.md plus extras).
std::string ReportJson(const Report& report);
/// report.json's "ceiling", each result's "part_coverage" (null where it has none) and
/// "pose_tolerance" (null where absent), as the JSON text of one object with those three keys
/// (report.html shows the same, without making all of report.json).
std::string ReportAnswersJsonText(const Report& report);
/// report.json's "robustness" object alone, as JSON text (report.html shows the same).
std::string RobustnessJsonText(const Robustness& robustness, const VisibilityFile& data);
/// candidates.csv text: one row per candidate.
std::string CandidatesCsv(const Report& report);
/// Binary little-endian PLY of voxel centres (x y z float).
std::string VoxelPly(const std::vector<uint64_t>& keys, double cell_size);
/// Packed keys that the union of `chosen` observes (in R and outside it), sorted.
std::vector<uint64_t> ObservedKeys(const VisibilityFile& data, const std::vector<uint32_t>& chosen);

/// report.json, candidates.csv, reference.ply and observed.ply (the primary result's voxels), by
/// file name. Requires a derived report.
std::map<std::string, std::string> ReportFiles(const Report& report);

/// Every file name a vantage command may write into a run folder. A rerun into the same folder
/// replaces or drops these; any other file there is the user's and is kept.
const std::set<std::string>& RunFolderFileNames();

/// Writes every output into `out_dir` atomically: a temporary sibling folder, renamed over the
/// old one only once complete (the user's own files in it are kept, see RunFolderFileNames).
/// `extra_files` (name -> content) are written beside the others.
void WriteOutputs(const std::string& out_dir, const Report& report,
                  const std::map<std::string, std::string>& extra_files = {});

/// A constellation to evaluate: the candidates of a report.json (and, when present, the
/// sensors named by its first `results` entry; otherwise every candidate), with the run's
/// `inputs` when the file has them.
struct Constellation {
  std::vector<Candidate> sensors;
  std::optional<RunInputs> inputs;
  double cell_size = 0;                 ///< report.json `cell_size`; 0 when absent
  std::string scene;                    ///< report.json `scene`; "" when absent
  std::optional<double> coverage;       ///< of the result whose sensors were taken
};
/// Reads report.json-shaped input; InputError naming file and problem when malformed.
Constellation LoadConstellation(const std::string& path);

}  // namespace vantage
