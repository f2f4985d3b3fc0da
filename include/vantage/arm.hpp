#pragma once
/// A camera on a robot arm (issue 45, docs/arm.md): the arm's kinematics (Orocos KDL), its views
/// from joint space or from a region through inverse kinematics, collision checks of the arm
/// against the cell and itself (FCL), and the motion time between two views. Only the candidates
/// stage links KDL and FCL (cmake/Layering.cmake).
#include <cstdint>
#include <limits>
#include <memory>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "vantage/candidates.hpp"
#include "vantage/problem.hpp"
#include "vantage/robot.hpp"

namespace vantage {

/// The joints that move a robot's link: forward kinematics of the whole robot (vantage's
/// LinkPoses) and of the chain to the link, its Jacobian (KDL), and inverse kinematics.
class ArmKinematics {
 public:
  /// The chain from `robot`'s root to `tip_link`. `moved` names the joints that IK and sampling
  /// change (a subset of the chain's settable joints); the robot's other joints stay at
  /// robot.joints. InternalError for an unknown link (the reader checks it).
  ArmKinematics(const PlacedRobot& robot, const std::string& tip_link,
                const std::vector<std::string>& moved);
  ~ArmKinematics();
  ArmKinematics(ArmKinematics&&) noexcept;
  ArmKinematics& operator=(ArmKinematics&&) noexcept;

  /// Every settable joint of the robot, tree order: the layout of a full configuration.
  const std::vector<std::string>& joint_names() const { return joint_names_; }
  /// Indices into joint_names() of the moved joints.
  const std::vector<size_t>& moved() const { return moved_; }
  /// The robot's `joints:` positions as a full configuration (others 0).
  std::vector<double> Rest() const;
  /// Limits of every joint of joint_names() (±inf where it has none) [rad or m].
  const std::vector<std::pair<double, double>>& limits() const { return limits_; }

  /// world_from_link of `link` (the tip when empty) at a full configuration (KDL's chain).
  Pose TipPose(const std::vector<double>& configuration) const;
  /// world_from_link of every link (LinkPoses), mimic joints following.
  std::map<std::string, Pose> LinkPosesAt(const std::vector<double>& configuration) const;

  /// What inverse kinematics matches: the whole pose, or the position and the camera's optical
  /// axis (body x; the roll about it free: the paper's 4-DoF reduction), or the position only.
  enum class Match { kPose, kDirection, kPosition };
  /// A full configuration, within the limits, whose tip · tip_from_camera puts the camera at
  /// `world_from_camera` within the tolerances, or nullopt. Damped least squares on KDL's
  /// Jacobian from `start`, then from `restarts` - 1 configurations drawn in the limits from
  /// Rng(seed, kArmIk, stream, restart): the same answer for the same seed.
  std::optional<std::vector<double>> SolveIk(const Pose& world_from_camera,
                                             const Pose& tip_from_camera, Match match,
                                             double position_tolerance, double angle_tolerance,
                                             const std::vector<double>& start, int restarts,
                                             uint64_t seed, uint64_t stream) const;

 private:
  struct Impl;
  // Made and deleted in the arm module (issue 47: KDL, FCL and OMPL are loaded only by a run with
  // an arm), hence its deleter with it.
  std::unique_ptr<Impl, void (*)(Impl*)> impl_{nullptr, nullptr};
  std::vector<std::string> joint_names_;
  std::vector<size_t> moved_;
  std::vector<std::pair<double, double>> limits_;
};

/// Which test a configuration failed first (ArmCollisions::Check).
enum class ArmCollision { kNone, kKeepOut, kScene, kSelf };

/// The arm against the cell (the scene's objects but the robot's own links; keep-out boxes) and
/// against itself, with FCL: primitives as FCL shapes, meshes as OBBRSS BVHs, built once.
/// Adjacent links (a joint between them), links that no joint of `moving` moves (fixed to the
/// base: their contact with the cell is the mounting, not a view's) and the allowed pairs are
/// exempt.
class ArmCollisions {
 public:
  ArmCollisions(const PlacedRobot& robot, const Scene& scene,
                const std::vector<KeepOutBox>& keep_out,
                const std::vector<std::string>& moving_joints,
                const std::vector<std::pair<std::string, std::string>>& allowed_pairs);
  ~ArmCollisions();
  ArmCollisions(ArmCollisions&&) noexcept;
  ArmCollisions& operator=(ArmCollisions&&) noexcept;

  /// The first failing test at the links' poses; `what` (may be null) gets the pair, e.g.
  /// "link 'wrist_3' and object 'bin'". Thread-safe.
  ArmCollision Check(const std::map<std::string, Pose>& world_from_link,
                     std::string* what = nullptr) const;

 private:
  struct Impl;
  std::unique_ptr<Impl, void (*)(Impl*)> impl_{nullptr, nullptr};  // as ArmKinematics'
};

/// One population's arm, kept for the tour (motion times, collision of the moves).
struct ArmSetup {
  std::string population;
  std::string robot;
  std::string file;  ///< where the population's arm is declared, for messages
  int line = 0;
  std::shared_ptr<const ArmKinematics> kinematics;
  std::shared_ptr<const ArmCollisions> collisions;
  std::shared_ptr<const ArmBody> body;  ///< the robot's link meshes, shared by its views
  std::vector<double> home;  ///< the tour's start and end: `home:`, else the robot's joints
  /// Each joint's <limit velocity> [rad/s or m/s] (0 where the URDF gives none).
  std::vector<double> speeds;
  /// --track over the scene's states (the pipeline's, before any ray): per state, the arm
  /// against that state's cell (`state_collisions`, its views) and against the cells of that
  /// state and the one before it together (`move_collisions`: a move into the state; state 0's
  /// is its own); `state_free[s][i]` whether candidate i is collision-free in state s. Empty
  /// otherwise.
  std::vector<std::shared_ptr<const ArmCollisions>> state_collisions;
  std::vector<std::shared_ptr<const ArmCollisions>> move_collisions;
  std::vector<std::vector<bool>> state_free;
};

/// The checks of `arm` (of `problem`'s population and robot: its keep-out boxes, moved joints
/// and allowed pairs) against another cell, e.g. a state's scene.
std::shared_ptr<const ArmCollisions> ArmCollisionsIn(const Problem& problem, const ArmSetup& arm,
                                                     const Scene& scene);

/// The candidates once the arms are applied, and what each test removed (all populations).
struct ArmViews {
  std::vector<Candidate> candidates;
  std::vector<ArmSetup> arms;   ///< one per population with an arm, in population order
  size_t drawn = 0;             ///< configurations drawn (joint space) or poses (reach)
  size_t unreachable = 0;       ///< reach: no IK solution within the tolerances
  size_t camera_kept_out = 0;   ///< the camera's optical centre in a keep-out box
  size_t arm_kept_out = 0;      ///< a link in a keep-out box
  size_t scene_collisions = 0;  ///< a link hits the cell
  size_t self_collisions = 0;   ///< two links hit each other
  std::vector<std::string> notes;  ///< one line per population, for the log and report
};

/// Halton's point `index` (from 1) in `dimensions` dimensions, in [0, 1) (bases 2, 3, 5, ...).
std::vector<double> HaltonPoint(uint64_t index, size_t dimensions);

/// The configurations a kind-`arm` population draws, full (ArmKinematics::joint_names()):
/// the moved joints within their limits (random: Rng(seed, kArm, population_index, i); Halton:
/// point i + 1; grid: floor(count^(1/d)) values per joint, ends included), the others at rest;
/// or its list. InputError at the population's line for a list entry outside the limits.
std::vector<std::vector<double>> DrawConfigurations(const Population& population,
                                                    const ArmKinematics& kinematics,
                                                    uint64_t seed, uint32_t population_index);

/// Each population's arm (its kinematics, collisions with `problem`'s cell, body, home and
/// speeds) in population order, as ApplyArms builds it, without drawing or reaching any view:
/// what `vantage select` rebuilds the arm views of a visibility file with (issue 45).
std::vector<ArmSetup> ArmSetupsOf(const Problem& problem);

/// `deployed` (DeployCandidates: the regions' poses, kind-`arm` populations left out) with the
/// arms applied: each `reach:` population's poses kept where IK puts the camera there (its pose
/// becomes the reached one), then every kind-`arm` population's views appended
/// ("<population>_<i>", draw order), each kept only when collision-free. InputError at the
/// population's place when none is left (naming what removed most), before any ray is cast.
ArmViews ApplyArms(const Problem& problem, std::vector<Candidate> deployed, uint64_t seed);

/// Whether the arm moves straight in joint space from `from` to `to` without collision, checked
/// at every joint step of at most `resolution` [rad or m] (both ends included). `what` (may be
/// null) gets the first colliding pair (ArmCollisions::Check's words) when it is not.
bool StraightMotionIsFree(const ArmKinematics& kinematics, const ArmCollisions& collisions,
                          const std::vector<double>& from, const std::vector<double>& to,
                          double resolution, std::string* what = nullptr);

/// The time of the straight joint-space move: the slowest joint at its speed,
/// max_i |to_i - from_i| / speed_i [s].
double MotionSeconds(const std::vector<double>& from, const std::vector<double>& to,
                     const std::vector<double>& speeds);

/// A move around what the straight segment hits: full configurations from `from` to `to` (both
/// included), each segment between them straight and collision-free at the resolution.
struct PlannedMotion {
  bool found = false;
  std::vector<std::vector<double>> waypoints;  ///< empty when not found
  /// Sum over the segments of MotionSeconds (the arm stops at each waypoint) [s], +inf when not
  /// found; never less than the straight move's time (MotionSeconds is a norm).
  double seconds = std::numeric_limits<double>::infinity();
  bool stopped_by_time = false;  ///< the time limit, not the sample budget, ended the search
};

/// How PlanMotion searches.
struct MotionPlanOptions {
  double resolution = 0.01;   ///< [rad or m]: every segment checked at this joint step
  double time_limit = 2.0;    ///< [s] per move: a safety net; the sample budget ends a search
  size_t max_samples = 4000;  ///< RRT-Connect iterations: the deterministic end of a search
  uint64_t seed = 1;          ///< with `stream`: Rng(seed, kArmPlan, stream) seeds the sampler
  uint64_t stream = 0;
};

/// A collision-free path from `from` to `to` in joint space (the moved joints and any joint
/// that differs between the two, within the URDF limits); not found when the search fails or
/// an end collides. OMPL's RRT-Connect with the FCL checks (ArmCollisions) as its state
/// validity, its sampler seeded from `options`' seed and stream and its nearest neighbours
/// searched exactly, so the same call gives the same path; then shortened greedily (from each
/// waypoint, straight to the farthest later one that is free). Deterministic unless the time
/// limit, rather than the sample budget, ends a search.
PlannedMotion PlanMotion(const ArmKinematics& kinematics, const ArmCollisions& collisions,
                         const std::vector<double>& from, const std::vector<double>& to,
                         const std::vector<double>& speeds, const MotionPlanOptions& options);

}  // namespace vantage
