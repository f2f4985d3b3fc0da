#pragma once
/// Refined poses (issue 9): after selection, new candidates are searched around each chosen sensor
/// (small moves and turns inside its population's region, re-aiming at the observation point and
/// at what the constellation does not see yet), only they are traced, and selection reruns over
/// old and new candidates; rounds repeat while coverage improves.
#include <cstdint>
#include <functional>
#include <span>
#include <string>
#include <vector>

#include "vantage/candidates.hpp"
#include "vantage/constraints.hpp"
#include "vantage/observe.hpp"
#include "vantage/population.hpp"
#include "vantage/reference.hpp"
#include "vantage/select.hpp"
#include "vantage/select_states.hpp"

namespace vantage {

/// The rounds a run may ask for (--refine-rounds, optimize's refine): each traces the new poses
/// and selects again, so more would run for hours; a run asking for refinement asks for one.
inline constexpr int kMaxRefineRounds = 100;

/// One more state of the scene for Refine (RefineOptions::states); `rays` and `reference` must
/// outlive the call. States that share them (the same geometry) are traced once.
struct RefineState {
  std::string name;
  const RayScene* rays = nullptr;
  const Reference* reference = nullptr;
  std::vector<Observation> observations;
};

struct RefineOptions {
  int max_rounds = 4;   ///< rounds of search + trace + re-selection, >= 0 (0: no refinement)
  double move = 0.05;   ///< first position step [m], > 0
  double turn_deg = 5;  ///< first turn step [degrees], > 0
  int per_sensor = 12;  ///< new poses per chosen sensor per round, >= 1
  /// A round without improvement halves the move and turn steps and the search goes on; after
  /// this many halvings in a row without improvement it stops. 0: stop at the first such round.
  int max_halvings = 1;
  uint64_t seed = 1;  ///< which poses of the pool are drawn when it holds more than per_sensor
  /// How the new poses are traced: the culling and quality filter the given observations were
  /// made with, so that old and new candidates are scored alike.
  ObserveOptions observe;
  /// How the new poses are traced (observe.hpp): empty, by Observe in this process; an MPI job's
  /// spreads them over its ranks (distribute.hpp).
  TraceFunction trace;
  /// Installation constraints (docs/constraints.md) the refined constellation obeys, as the
  /// start selection did: whether a new camera body pose may be mounted (outside the keep-out
  /// boxes; empty: every pose), and the constraints over the given and new candidates together,
  /// recomputed after each round's tracing (separation, interference, calibration; empty: none).
  std::function<bool(const Pose& world_from_body)> may_mount;
  std::function<InstallConstraints(std::span<const Candidate>, std::span<const Observation>)>
      constraints;
  /// Scene states (docs/scene-format.md, States): the states after the first, in state order —
  /// each one's geometry, reference and matrix (one observation per given candidate); the first
  /// state's are Refine's `rays`, `reference` and `observations`. Empty: one scene. New poses are
  /// then traced in every state, and re-selection and scoring use the aggregate `over`.
  std::vector<RefineState> states;
  OverStates over = OverStates::kMean;

  /// Throws InputError naming the field when a value is out of range or not finite.
  void Validate() const;
};

struct RefineResult {
  /// The given candidates and observations first (unchanged, same order), then the new ones in
  /// the order they were made; new candidates are named "<original>_r<round>_<i>" and keep the
  /// original's sensor type and population.
  std::vector<Candidate> candidates;
  std::vector<Observation> observations;
  /// With RefineOptions::states: each of those states' observations, grown the same way.
  std::vector<std::vector<Observation>> state_observations;
  /// The refined constellation (indices into `candidates`); never worse than `start` under the
  /// objective of the SelectOptions. Its `seconds` are the refinement's (tracing included); no
  /// upper_bound (the bound of the original candidates does not hold for the new ones).
  Selection selection;
  double coverage_before = 0;  ///< coverage of `start` (recomputed from the observations)
  /// Coverage after each round, coverage_before first: non-decreasing.
  std::vector<double> history;
  int rounds = 0;             ///< rounds run (traced), including the last, unimproving one
  size_t new_candidates = 0;  ///< candidates added (= candidates.size() - given ones)
  uint64_t extra_rays = 0;    ///< rays traced for the new candidates
  double seconds = 0;         ///< wall time of Refine
};

/// Whether a sensor model position lies in the region its population samples from (GAZEBO.md,
/// "Sensor populations"): the box after Gazebo's shift (P.pos − size/2, then R_P · [0, size]),
/// the cylinder P.pos + R_P · (ρ ≤ r, 0 ≤ z ≤ l), a grid's lattice rectangle widened by half a
/// step on each side (±|dz|/2 off its plane). Boundaries are inside (1e-9 m tolerance).
bool RegionContains(const Population& population, const Vec3& world_position);

/// Refines `start`, a selection over `candidates` with their `observations` (one each, as from
/// Observe in `rays` with `reference` and options.observe). `populations` are those the candidates were deployed from
/// (matched by Candidate::population; "" is an explicit sensor, which moves freely by the same
/// steps). Poses are re-aimed with LookAt at the model's position and composed with the
/// population's model_from_camera as DeployCandidates does; a population's random roll is kept.
/// Re-selection uses `select` (kAll and kBest run as kLocal; for set cover, which has no local
/// search, as kGreedy) and, for every objective but set cover, also
/// swap local search from the current constellation; the better answer is kept, so
/// coverage never drops. Deterministic for a seed whatever the thread count. Kept sensors
/// (select.fixed, in `start`) stay where they are: no poses around them, every re-selection holds
/// them. With select.min_points the search aims at the cells short of the points and the layout
/// is scored by point coverage (the observations must carry their counts). Over scene states
/// (options.states) each new pose is traced in every state, the search aims at the first state's
/// blind cells, and the layout is scored by the states' aggregate (state_coverage filled).
/// Throws InputError for invalid options, sizes that do not match, an unknown population name,
/// `start` naming a candidate out of range or lacking a kept one, or point counts missing.
RefineResult Refine(const RayScene& rays,
                    const Reference& reference,
                    std::vector<Candidate> candidates,
                    std::vector<Observation> observations,
                    const std::vector<Population>& populations,
                    const Vec3& observation_point,
                    const Selection& start,
                    const SelectOptions& select,
                    const RefineOptions& options = {});

}  // namespace vantage
