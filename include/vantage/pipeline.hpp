#pragma once
/// The pipeline as a library (docs/architecture.md): load → overrides → deploy → checks → states
/// → R → observe → select → assess → report. Every command of the CLI calls these functions (and
/// so will the Python module and the distributed mode); the CLI only maps flags onto these option
/// structs and prints. Option problems are InputErrors naming the option (`-n: ...`), or the
/// scene file when its own settings are at fault; they are found before any ray is cast.
#include <chrono>
#include <cstdint>
#include <functional>
#include <map>
#include <memory>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "vantage/arm.hpp"
#include "vantage/candidates.hpp"
#include "vantage/observe.hpp"
#include "vantage/pose_tolerance.hpp"
#include "vantage/output_guard.hpp"
#include "vantage/problem.hpp"
#include "vantage/ray_scene.hpp"
#include "vantage/reference.hpp"
#include "vantage/refine.hpp"
#include "vantage/render.hpp"
#include "vantage/report.hpp"
#include "vantage/robustness.hpp"
#include "vantage/select.hpp"
#include "vantage/select_states.hpp"
#include "vantage/selection_options.hpp"
#include "vantage/settings.hpp"
#include "vantage/visibility_file.hpp"

namespace vantage {

/// The scene of a run and what overrides its own settings (unset: the scene's).
struct SceneInput {
  std::string path;                       ///< .yaml/.yml scene or .world/.sdf Gazebo world
  LoadOptions load;                       ///< model/resource paths, targets, cell size
  std::optional<uint64_t> seed;           ///< --seed
  std::optional<Vec3> observation_point;  ///< --observation-point [m, world]
  std::optional<bool> random_roll;        ///< --random-roll
  /// --exposed-only: coverage counts only surface some viewpoint could see (docs/outputs.md,
  /// "The ceiling"); unset: the paper's metric (evaluate: the constellation's run's).
  std::optional<bool> exposed_only;
  /// --track: a camera on an arm may follow the scene's `states:` (refused otherwise).
  bool arm_follows_states = false;
  /// InputError naming the option: an observation point that is not finite or beyond what the
  /// voxel grid and Embree can represent.
  void Validate() const;
};

/// What a run may use.
struct RunLimits {
  double max_memory_mib = 0;  ///< refuse runs estimated above this [MiB]; 0: 75 % of the RAM
  /// Refuse runs whose ray casting is estimated above this [s] (EstimateObserveSeconds, before
  /// any ray); 0: no limit (the estimate is still logged).
  double max_seconds = 0;
  void Validate() const;  ///< InputError naming --max-memory or --max-seconds
};

/// A deliberately high estimate of the seconds that observing `candidates` candidates with
/// `rays` rays to trace (after culling: CountRaysToTrace) takes on `threads` threads, selection
/// and outputs included: kSecondsPerRay per ray plus kSecondsPerCandidate per candidate (culling,
/// the sets, selection over them), per thread; about twice the costs measured on the shared
/// 2-core machine (the example: 1.1 M rays in 1.26 s on one thread; a 1000 x 1000 grid: 10^6
/// candidates, 0.23 M rays, 130 s on two).
double EstimateObserveSeconds(uint64_t rays, size_t candidates, size_t threads);
inline constexpr double kSecondsPerRay = 2e-6;
inline constexpr double kSecondsPerCandidate = 3e-4;

/// A deliberately high estimate of the seconds a scene's triangles cost: the ray caster's BVH of
/// each traced state's scene (`built_triangles`: the triangles of all of them), kSecondsPerTriangle
/// per triangle and thread, and writing the outputs of a scene of `scene_triangles` (report.html
/// simplifies one of more than 300 000), kOutputSecondsPerTriangle per triangle on one thread;
/// about twice the costs measured on the shared 2-core machine (4 M triangles: the BVH in about
/// 1 s on two threads, the outputs in 3.6 s).
double EstimateSceneSeconds(uint64_t built_triangles, uint64_t scene_triangles, size_t threads);
inline constexpr double kSecondsPerTriangle = 1e-6;
inline constexpr double kOutputSecondsPerTriangle = 2e-6;

/// The selection options of a run: the request over the scene's settings, costs from the
/// candidates' types. InputError naming the option of the request that makes them invalid, or
/// `source` (the scene or visibility file) when its own settings do. `cell_size` [m] converts
/// --min-density into points per cell (MinPointsOfDensity); 0: not known (refused then).
SelectOptions ResolveSelection(const SelectionSettings& settings, const SelectionRequest& request,
                               uint64_t seed, std::span<const Candidate> candidates,
                               const std::string& source, Method default_method = Method::kAll,
                               double cell_size = 0);

/// Points per cell for a density of `per_cm2` points per cm² on a cell's face, F² (F the cell
/// edge [m]): ceil(per_cm2 · (100 F)²), at least 1.
uint32_t MinPointsOfDensity(double per_cm2, double cell_size);

/// The largest --min-points: each sensor's count per cell saturates there (kMaxPointCount).
inline constexpr int64_t kMaxMinPoints = 65535;

/// Loads the scene and applies the overrides, without deploying candidates (evaluate, render).
Problem LoadScene(const SceneInput& input);

/// A loaded and deployed scene, before any ray is cast.
struct PreparedScene {
  Problem problem;                   ///< overrides applied; `scene` is the first state's
  LoadOptions load;                  ///< the options the scene was read with (kept in the .vis)
  std::vector<Scene> state_scenes;   ///< one per state of problem.states (empty: no states)
  /// One per state when a state moves sensors (SceneState::sensor_poses: sensors on a robot
  /// link), each state's candidates; empty when every state has `candidates`. `candidates` are
  /// then the first state's.
  std::vector<std::vector<Candidate>> state_candidates;
  std::vector<Candidate> candidates; ///< deployed, in order
  Timings timings;                   ///< load
  std::vector<std::string> notes;    ///< non-fatal remarks for the report
  bool cell_size_from_option = false;  ///< the cell size is the override's (for messages)
  bool exposed_only = false;  ///< --exposed-only: R holds only exposed surface
  /// The candidates the scene's keep_out boxes excluded (docs/constraints.md, Mounting rules):
  /// inside a box in the base scene or any state. Not in `candidates`; no ray is cast for them.
  std::vector<Candidate> kept_out;
  /// The arms of the `arm` and `reach:` populations (issue 45): their kinematics, collisions,
  /// home and joint speeds, for the tour. Empty when no camera is on an arm.
  std::vector<ArmSetup> arms;
};

/// Loads the scene, applies the overrides and the states, deploys the candidates. InputError for
/// bad input (file:line) or a bad override (the option).
PreparedScene Prepare(const SceneInput& input);

/// One state of a changing scene, observed.
struct ObservedState {
  std::string name;
  Reference reference;
  std::vector<Observation> observations;
  int same_as = -1;  ///< index of an earlier state with the same geometry (not traced again)
};

/// A scene observed: the visibility matrix and what it was made from.
struct ObservedScene {
  /// The first state's matrix for a scene with states; with the scene's mounting rules and the
  /// count of candidates the keep-out boxes excluded (data.mounting, data.kept_out).
  VisibilityFile data;
  Scene scene;                         ///< the geometry `data` was observed in
  std::unique_ptr<RayScene> rays;      ///< the BVH of `scene`, for the stages that cast rays later
  std::vector<Population> populations; ///< where the candidates came from
  std::vector<ExplicitSensor> sensors;
  Vec3 observation_point = Vec3::Zero();
  /// A scene with states: each state's reference and observations, in state order (`data` holds
  /// the first state's too); empty otherwise.
  std::vector<ObservedState> states;
  /// Each state's geometry, in state order (empty without states): --refine traces new poses in
  /// every state.
  std::vector<Scene> state_scenes;
  Timings timings;                     ///< load, reference, observe
  std::vector<std::string> notes;
  std::vector<ArmSetup> arms;          ///< PreparedScene::arms, for the tour
};

// TraceFunction (observe.hpp): ObservePrepared calls it once per traced geometry, the scene's
// first, then each state of another geometry, in the same order in every process.

/// Memory checks, R, observe (every state): the candidates traced once per distinct geometry,
/// each geometry's BVH built once, through `trace` when it is set. The scene's selection settings
/// go into the visibility file for `vantage select`.
ObservedScene ObservePrepared(PreparedScene prepared, const ObserveOptions& observe,
                              const RunLimits& limits, const TraceFunction& trace = {});

/// A finished run: the data its report points into (owned, so the report stays valid when the
/// result moves) and every output file by name.
struct RunResult {
  std::unique_ptr<VisibilityFile> data;
  Report report;                               ///< derived; report.data == data.get()
  std::map<std::string, std::string> files;    ///< report.json, report.html, ... by file name
  /// What the exports had to leave out ("constellation.sdf: 5 objects are left out"): WriteRun
  /// logs them as warnings, so that a run that writes nothing says nothing (they are in
  /// report.notes too).
  std::vector<std::string> export_warnings;
};

/// Writes result.files into `out_dir` atomically (a sibling folder renamed into place).
void WriteRun(const std::string& out_dir, const RunResult& result);

/// Throws InputError when WriteRun could not write `out_dir` (a file, a non-empty folder
/// without a report.json, a link to nothing). Commands call it before any work: found at the
/// end, the refusal cost the whole ray casting.
void CheckRunFolder(const std::string& out_dir);

/// The same for one output file (a visibility file, a PNG): a device, a pipe, a socket, a
/// folder, or a link to one of them.
void CheckOutputFile(const std::string& path);

/// A camera on an arm (issue 45, docs/arm.md): how its tours are timed.
struct ArmTourOptions {
  /// --cycle-time [s]: the most coverage whose tour fits (greedy; replaces the selection).
  std::optional<double> cycle_time;
  /// --joint-speed [rad/s or m/s]: every joint's speed, instead of the URDF's <limit velocity>.
  std::optional<double> joint_speed;
  int frames = 1;            ///< --frames: frames taken per view (acquisition = frames / fps)
  double resolution = 0.01;  ///< [rad or m]: the straight moves' collision check step
  /// --plan-time [s]: the most one move's planning around a collision may take (OMPL); the
  /// planner's sample budget normally ends it first (deterministic).
  double plan_seconds = 2.0;
  /// --track: with the scene's `states:` in time order, one view per state (TrackInfo, exact
  /// dynamic programme); replaces the selection.
  bool track = false;
  /// --move-penalty P: coverage (a fraction of R) subtracted per second of motion; default 0.
  std::optional<double> move_penalty;
  /// --state-interval T [s]: the states are T apart; acquisition and the move to the next
  /// state's view must fit in it.
  std::optional<double> state_interval;
  /// InputError naming the option.
  void Validate() const;
};

/// `vantage optimize`: the whole pipeline.
struct OptimizeOptions {
  SceneInput scene;
  ObserveOptions observe;
  RunLimits limits;
  SelectionRequest selection;
  RobustnessOptions robustness;
  /// --pose-tolerance: every result's coverage over perturbed layouts (seed: the run's).
  std::optional<PoseToleranceOptions> pose_tolerance;
  /// Set: refine the primary result (--refine); its seed and observe options are the run's.
  std::optional<RefineOptions> refine;
  TraceFunction trace;  ///< how observe traces (ObservePrepared); empty: in this process
  ArmTourOptions arm;   ///< cameras on arms: their tours
  /// --by-type (issue 43): also select over each sensor type's candidates alone, per n
  /// (Report::by_type). For the objectives that choose n (coverage, k-coverage, min-points);
  /// not with states, --keep-existing, --refine or --cycle-time (InputError naming --by-type).
  bool by_type = false;
};
RunResult Optimize(const OptimizeOptions& options);

/// Optimize in its two halves, for the distributed layer, which runs the first in every process
/// and the second in one: every check, Prepare and ObservePrepared (through options.trace); then
/// selection, refinement, assessment and the outputs. Optimize runs one after the other.
struct OptimizeObserved {
  ObservedScene observed;
  SelectOptions select;
  std::chrono::steady_clock::time_point start;  ///< for timings.total
};
OptimizeObserved ObserveForOptimize(const OptimizeOptions& options);
RunResult FinishOptimize(const OptimizeOptions& options, OptimizeObserved observed);

/// `vantage observe`: the visibility file of a scene.
struct ObserveRunOptions {
  SceneInput scene;
  ObserveOptions observe;
  RunLimits limits;
  std::optional<int> n;  ///< -n: the default number of sensors stored with the matrix
  TraceFunction trace;   ///< how observe traces (ObservePrepared); empty: in this process
};
struct ObserveRunResult {
  VisibilityFile data;
  Timings timings;
  std::vector<std::string> state_names;  ///< a scene with states: all of them (data: the first)
};
ObserveRunResult ObserveRun(const ObserveRunOptions& options);

/// `vantage select`: selection from a saved visibility file.
struct SelectFileOptions {
  std::string visibility_file;
  SelectionRequest selection;
  std::optional<uint64_t> seed;  ///< unset: the file's
  RobustnessOptions robustness;
  /// --pose-tolerance, assessed when the file's scene still loads (its geometry re-traces).
  std::optional<PoseToleranceOptions> pose_tolerance;
  /// A camera on an arm (a file of format 11 whose scene still loads): each result's tour and
  /// --cycle-time, as `optimize` gives them (--track needs states, which a file does not hold).
  ArmTourOptions arm;
};
RunResult SelectFromFile(const SelectFileOptions& options);

/// The selection of `vantage select FILE` over an observed matrix (SelectFromFile and the Python
/// module's Visibility.select): the request over the file's settings, its installation
/// constraints resolved over the candidates (docs/constraints.md) and put into `options`.
struct MatrixSelection {
  SelectOptions options;                     ///< with `constraints` set when they apply
  std::optional<ConstraintsInfo> constraints;  ///< report.json's `constraints`; nullopt: none
};
/// InputError naming the option (or `source`, the file, when --min-points needs the pixel
/// counts it lacks), before any selection.
MatrixSelection ResolveMatrixSelection(const VisibilityFile& data, const SelectionRequest& request,
                                       uint64_t seed, Method default_method = Method::kAll,
                                       const std::string& source = "");

/// `vantage evaluate`: the coverage of given sensor poses.
struct EvaluateOptions {
  /// Empty fields (path, model/resource paths, targets, cell size) take the constellation's
  /// report.json `inputs`, so that a run's folder alone reproduces it.
  SceneInput scene;
  /// A report.json; empty: the layout the scene declares itself (its explicit sensors: a gz-sim
  /// world's cameras, a YAML scene's `sensors:`), which needs scene.path.
  std::string constellation;
  /// A quality filter left unset takes the one the constellation's run used.
  ObserveOptions observe;
  RunLimits limits;
  /// The constraints the layout is checked against (report.json results[0].constraints); fields
  /// left unset take the constellation's run's. Interference is checked by default.
  ConstraintOptions constraints;
  /// Point density: the layout's coverage counts only cells with this many points (--min-points,
  /// or --min-density per cm²); both unset take the constellation's run's.
  std::optional<int64_t> min_points;
  std::optional<double> min_density;
  /// --pose-tolerance: the layout's coverage over perturbed layouts (seed: the scene's or --seed).
  std::optional<PoseToleranceOptions> pose_tolerance;
};
struct EvaluateResult {
  RunResult run;                         ///< one result, method "given": every sensor
  std::vector<double> sensor_coverage;   ///< each sensor alone, in order
};
EvaluateResult Evaluate(const EvaluateOptions& options);

/// `vantage render`: a PNG of a finished run.
struct RenderRunOptions {
  std::string run;    ///< an output folder of optimize/select/evaluate, or its report.json
  std::string png;    ///< file to write; empty: <run folder>/view.png
  SceneInput scene;   ///< empty fields take the run's report.json `inputs`
  RenderOptions render;
  /// A run of a camera on an arm (its views.yaml): the view (1-based, views.yaml's order) at
  /// which the arm is drawn; unset: the first. InputError naming --arm-view for a run without
  /// views.yaml or a view it does not have.
  std::optional<int> arm_view;
};
struct RenderRunResult {
  std::string png;
  size_t sensors = 0;
  double coverage = 0;  ///< of the re-observed constellation
};
RenderRunResult RenderRun(const RenderRunOptions& options);

}  // namespace vantage
