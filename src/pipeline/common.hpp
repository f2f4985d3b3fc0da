#pragma once
/// Pieces the pipeline's commands share: clocks, checks of overrides, the memory checks before
/// R and observe, the selection of a run, the inputs block and the output files.
#include <chrono>
#include <functional>
#include <string>

#include "vantage/gazebo_export.hpp"
#include "vantage/pipeline.hpp"

namespace vantage::detail {

/// `observe` with its sensor model decided (issue 43): as given (--ideal, --physical), else
/// ideal for a Gazebo world of the original system and physical for any other scene.
ObserveOptions WithSensorModel(ObserveOptions observe, const std::string& scene_path);

/// Whether any of `candidates` has a second aperture or a flying-pixel filter (HasPhysicalModel):
/// without one the physical model sees what the ideal pinhole sees, and a run is recorded as ideal.
bool AnyApertureIn(std::span<const Candidate> candidates);

/// `optimize --by-type` (by_type.cpp): per sensor type among data's candidates, the run's
/// selection `options` over that type's candidates alone (conflicts renumbered), best per n; and
/// the run's own best per n from its `results` and `curve`.
TypeComparisonTable CompareTypes(const VisibilityFile& data, const SelectOptions& options,
                                 const std::vector<Selection>& results,
                                 const std::vector<Selection>& curve);

/// Seconds since `start` on the steady clock.
double SecondsSince(std::chrono::steady_clock::time_point start);

/// InputError naming `option` unless WorldPointProblem finds nothing (kMaxWorldCoordinate: what
/// the voxel grid and Embree's float rays can represent with room to spare).
void CheckWorldPoint(const Vec3& point, const std::string& option);

/// CheckCandidate on each candidate, named in messages by `where(i)`.
void CheckCandidates(std::span<const Candidate> candidates,
                     const std::function<std::string(size_t)>& where);
/// CheckCandidates on the deployed candidates of `problem`, each named by the file and line of
/// its population or sensor.
void CheckDeployedCandidates(std::span<const Candidate> candidates, const Problem& problem);

inline constexpr double kMiB = 1024.0 * 1024.0;
/// Bytes of `scene`'s meshes (vertices and triangles) in memory.
uint64_t MeshBytes(const Scene& scene);
/// --max-memory, or 75 % of the machine's RAM when it is not given (0).
double MemoryLimitMiB(double limit_mib);

/// Refuses a cell size too fine for the memory before R is built, and a run whose observe and
/// selection estimate exceeds the limit before any ray is cast (issue #8).
void CheckReferenceMemory(const PreparedScene& prepared, double limit_mib);
/// `state_scenes`: the scene's states (empty without), each holding its own visibility lists and
/// bitsets and a copy of the meshes, and while one is traced its ray caster's scene beside the
/// first state's.
void CheckObserveMemory(const Scene& scene, size_t reference_size,
                        std::span<const Candidate> candidates, double limit_mib,
                        const std::string& source, std::span<const Scene> state_scenes = {});

/// Logs the estimated time (EstimateObserveSeconds of the rays after culling, plus
/// EstimateSceneSeconds of the scene's triangles) and refuses a run above `limit_seconds` (0: no
/// limit) before any ray is cast. `state_scenes`: the scene's states (empty without); each may be
/// traced again, its scene built again, so the estimate of the rays is the first state's times
/// their number (at most: a state of unchanged geometry is not traced).
void CheckObserveTime(const Reference& reference, std::span<const Candidate> candidates,
                      const ObserveOptions& observe, double limit_seconds, const Scene& scene,
                      std::span<const Scene> state_scenes, const std::string& source);

/// Select, its refusal of a goal above what all candidates reach completed with the share of R
/// no viewpoint can see (Reference::exposed), when known.
std::vector<Selection> SelectExplained(std::span<const Observation> observations,
                                       const Reference& reference, const SelectOptions& options);

/// --pose-tolerance (`options` set): every result of `report` over perturbed layouts, traced in
/// `rays` with the run's seed, recorded in report.json `inputs`. Skipped with a note over scene
/// states (the results count over states, `data` holds the first) or without `rays`.
void AddPoseTolerance(const std::optional<PoseToleranceOptions>& options, const RayScene* rays,
                      const ObserveOptions& observe, Report* report);

/// R of `scene` (options: its cell size, --exposed-only), errors named after `source`; `before_build` (may be empty) runs
/// once the targets are known to fit the grid (the memory check).
Reference BuildRunReference(const Scene& scene, const ReferenceOptions& options, const std::string& source,
                            const std::function<void()>& before_build = {});

/// Every candidate of `evaluator` as one "given" selection, with its coverage (evaluate, render).
Selection GivenSelection(const CoverageEvaluator& evaluator);

/// Conflicting pairs (separation, interference) selection can hold (each is a row
/// x_i + x_j <= 1; 5 M take about 200 MB with the methods' neighbour lists).
constexpr size_t kMaxConflictPairs = 5'000'000;

/// The pairs of candidates whose optical centres are closer than `min_separation` [m]
/// (ConflictKind::kSeparation, value: the distance), sorted by (a, b). Stops once it holds more
/// than `max_pairs` (then it returns max_pairs + 1 of them, unsorted).
std::vector<Conflict> SeparationConflicts(std::span<const Candidate> candidates,
                                          double min_separation,
                                          size_t max_pairs = kMaxConflictPairs);

/// Exit 2 at the scene's min_separation line when it puts more than kMaxConflictPairs pairs
/// in conflict: checked in Prepare, before any ray, so that a separation that holds most pairs
/// of a large population is refused instead of filling the memory with its pairs.
void CheckSeparationPairs(std::span<const Candidate> candidates, const MountingRules& mounting);

/// Per candidate, whether its type projects light (ProjectsLight, by its catalog id).
std::vector<bool> ProjectingCandidates(std::span<const Candidate> candidates);

/// The constraints selection must satisfy, from the request over the observed candidates:
/// interference (when asked for, with at least two projecting candidates),
/// calibration and the scene's mounting rules (separation pairs; the keep-out boxes, the
/// `kept_out` candidates they excluded and the candidates inside one, which evaluate reports).
/// With scene `states` (the first of which is `observations`), a pair interferes when it does in
/// any state. nullopt when none is on. InputError for an invalid request, kept sensors that
/// conflict or that no chain joins (or whose chain -n, the budget or method best leaves no room
/// for), and more than kMaxConflictPairs interference pairs.
std::optional<ConstraintsInfo> ResolveConstraints(const ConstraintOptions& request,
                                                  const SelectOptions& options,
                                                  std::span<const Candidate> candidates,
                                                  std::span<const Observation> observations,
                                                  const MountingRules& mounting = {},
                                                  size_t kept_out = 0,
                                                  std::span<const ObservedState> states = {});

/// The constraints of `info` (a run's, from ResolveConstraints) over a grown candidate set, the
/// run's first: interference and separation pairs recomputed over all of them, the calibration
/// rule kept. For refinement, whose new poses join the given candidates.
InstallConstraints ConstraintsOverGrown(const ConstraintsInfo& info,
                                        std::span<const Candidate> candidates,
                                        std::span<const Observation> observations);

/// report->robustness: AssessRobustness of the primary result with what its selection (`select`)
/// obeyed: kept sensors never replaced, the budget or --cheapest's prices, and the installation
/// rules (report->constraints: alternatives that break them are dropped).
void AddRobustness(const VisibilityFile& data, const SelectOptions& select,
                   RobustnessOptions robustness, const RayScene* rays,
                   const ObserveOptions& observe, Report* report);

/// The points a cell needs from --min-points, or from --min-density on cells of edge `cell_size`
/// (MinPointsOfDensity); unset when neither is given. InputError naming the option for a value
/// out of range or both given; `origin`, when set, names where both came from instead (an edited
/// report.json: "run/report.json: inputs.min_points"), with the key appended.
std::optional<uint32_t> ResolveMinPoints(std::optional<int64_t> min_points,
                                         std::optional<double> min_density, double cell_size,
                                         const std::string& origin = "");

/// Logs the estimated time of RANSAC's iterations (issue 15: `--iterations 2000000000` over 400
/// candidates ran for hours after a "selecting takes at most 0.8 s" estimate) and refuses it,
/// naming --iterations, when it is above `limit_seconds` (> 0). Before any selection method runs.
void CheckSelectionTime(std::span<const Observation> observations, const SelectOptions& options,
                        size_t state_count, double limit_seconds, const std::string& source);

/// InputError naming the first objective over groups of cells (aggregates_groups, e.g.
/// --over-parts) that `request` gives beside `conflict` (--refine, --cycle-time, ...: what chooses
/// or re-scores by the coverage of all cells together); nothing when `conflict` is null.
void RefuseGroupObjectiveBeside(const SelectionRequest& request, const char* conflict);

/// Selection on one matrix (optimize without states, `select FILE`): `report`'s results and the
/// coverage curve beside them. The one place a request's objective meets the matrix.
void SelectOnMatrix(const VisibilityFile& data, const SelectionRequest& request,
                    const SelectOptions& options, Report* report);

/// Runs selection: over the states (SelectOverStates) when the scene has them, else
/// SelectOnMatrix.
/// Fills `report`'s results and states block. With report->constraints set, selection obeys them.
void SelectResults(const ObservedScene& observed, const SelectionRequest& request,
                   const SelectOptions& options, Report* report);

/// What shaped the coverage of a run observed into `data` with `inputs` (for the command that
/// scores constellation.sdf again).
ScoringOptions ScoringOf(const VisibilityFile& data, const RunInputs& inputs);

/// `path` absolute and lexically normal (as given where the current folder cannot be read).
std::string AbsoluteText(const std::string& path);
/// `load` with its model, resource and package folders absolute.
LoadOptions AbsoluteFolders(LoadOptions load);
/// An inputs block's scene: its path and how it is read (`load`'s folders, targets, cell size),
/// as given, so that `render` and `evaluate` of the run's folder reload it.
void SetSceneInputs(const std::string& scene, const LoadOptions& load, RunInputs* inputs);

/// The run's inputs block: the scene input with absolute paths and the observe options.
RunInputs InputsOf(const std::string& command, const SceneInput& scene,
                   const ObserveOptions& observe);
/// Adds the selection request to an inputs block.
void AddSelectionInputs(const SelectionRequest& request, RunInputs* inputs);

/// The constellation exports of `chosen` sensors in the scene at `scene_path`: a Gazebo world
/// gives constellation.world and constellation.sdf (its own text edited: `populations` and
/// `sensors` are the world's), another scene constellation.yaml and a generated
/// constellation.sdf of `scene`'s objects. What could not be carried over goes to `notes`.
std::map<std::string, std::string> ConstellationFiles(const std::string& scene_path,
                                                      const Scene& scene,
                                                      const std::vector<Candidate>& chosen,
                                                      const std::vector<Population>& populations,
                                                      const std::vector<ExplicitSensor>& sensors,
                                                      const ScoringOptions& scoring,
                                                      std::vector<std::string>* notes);

/// Serialises every output of a derived report: report.json, candidates.csv, the PLY clouds,
/// report.html (with `scene`'s meshes) and static_transforms.yaml, plus `extra`.
void FinishRun(const Scene& scene, std::map<std::string, std::string> extra, RunResult* run);

/// Cameras on arms (issue 45, src/pipeline/arm_tour.cpp): InputError naming --joint-speed when a
/// moved joint has no <limit velocity> and no --joint-speed is given, or a tour option; at the
/// population when an arm's home collides or no view can be reached from it (the planner seeded
/// by `seed`).
void CheckArmTourInputs(const std::vector<Candidate>& candidates,
                        const std::vector<ArmSetup>& arms, const ArmTourOptions& options,
                        uint64_t seed);
/// What --track and --cycle-time (each one criterion of its own: one view per state, the most
/// coverage within a tour time) would leave unmet: the first objective or constraint that
/// `select` (the scene's settings included) or `request` gives — "a coverage goal", "a budget",
/// "k-coverage", "a point density", "an installation constraint", "--keep-existing"; null when
/// none. Both refuse it before any ray, where --cycle-time had answered without it.
const char* ObjectiveBesideArmSelection(const SelectOptions& select,
                                        const SelectionRequest& request);
/// InputError naming the first tour option `options` gives (--cycle-time, --joint-speed, or
/// --frames, --motion-resolution, --plan-time other than their defaults) in a run without a camera
/// on an arm, where it could change nothing: "{flag}: {why} — {flag} {what it does}; {fix}".
void RefuseTourOptionsWithoutArm(const ArmTourOptions& options, const std::string& why,
                                 const std::string& fix);
/// InputError naming --cycle-time and ObjectiveBesideArmSelection's conflict, if any.
void RefuseObjectiveBesideCycleTime(const SelectOptions& select, const SelectionRequest& request);
/// report->tours: per result, the tour of its views on one arm (the first arm it uses); moves
/// whose straight segment collides are planned around with report->seed. InputError at the
/// arm's population, naming the move, when a tour cannot be connected (before any output).
void AddArmTours(const std::vector<Candidate>& candidates, const std::vector<ArmSetup>& arms,
                 const ArmTourOptions& options, Report* report);
/// --cycle-time: the greedy most coverage whose checked tour fits (method "cycle-time").
Selection CycleTimeSelection(const VisibilityFile& data, const std::vector<ArmSetup>& arms,
                             const ArmTourOptions& options, uint64_t seed);
/// `render` of a run of a camera on an arm (src/pipeline/arm_tour.cpp): its views.yaml, checked
/// before the scene is read (InputError naming --arm-view or the file's place).
class ArmAtViews {
 public:
  ArmAtViews(ArmViewsFile views, std::string path, std::optional<int> view);
  /// The scene without the robot's links (they move with each view), and each chosen sensor
  /// named in views.yaml given the arm as it stands there (its links occlude it, as optimize
  /// observed it). InputError at views.yaml when the scene lacks the robot or its joints.
  void Apply(Problem* problem, std::vector<Candidate>* sensors);
  /// `scene` (Apply's) with the robot's links at the chosen view, occluders named ROBOT::LINK;
  /// `frame` gets their bounds' corners, for the picture's framing.
  Scene SceneAtView(const Scene& scene, std::vector<Vec3>* frame) const;

 private:
  ArmViewsFile views_;
  std::string path_;
  size_t view_ = 0;
  std::shared_ptr<const ArmBody> body_;
  std::shared_ptr<const ArmKinematics> kinematics_;
};

/// `select FILE` of cameras on arms (src/pipeline/arm_select.cpp): the arms of `problem` (the
/// reloaded scene) that `data`'s stored arm views are on, each such candidate given its ArmPose
/// at its stored joints, and those robots taken out of problem->scene (as Prepare does).
/// InputError naming `visibility_file`, before any work, when a view does not fit the scene:
/// its population has no arm, another robot or other joints, or its joints put the camera
/// elsewhere than where it was observed (the scene was edited since observe).
std::vector<ArmSetup> RebuildArmViews(Problem* problem, const std::string& visibility_file,
                                      VisibilityFile* data);

/// --track (before any ray): InputError naming --track without states or without an arm, at a
/// state's line when no view of the arm is collision-free in it, naming --state-interval when no
/// sequence fits it even at the straight moves' times; sets the arms' per-state collisions.
void PrepareArmTrack(PreparedScene* prepared, const ArmTourOptions& options);
/// --track: the exact best view per state (SolveTrack over the checked moves) as the only
/// result, its path as the tour, report->track and report->states.
void TrackSelection(const ObservedScene& observed, const ArmTourOptions& options, uint64_t seed,
                    Report* report);

}  // namespace vantage::detail
