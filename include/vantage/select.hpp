#pragma once
/// Selection of the constellation from the visibility matrix (SYSTEM.md, stage 5).
#include <cstdint>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "vantage/constraints.hpp"
#include "vantage/settings.hpp"
#include "vantage/visibility.hpp"

namespace vantage {

/// What selection optimises (SYSTEM.md, Select: further objectives). At most one of the
/// non-default objectives is active; SelectOptions::objective() says which.
enum class Objective {
  kCoverage,   ///< maximum coverage with n sensors (the default)
  kSetCover,   ///< the fewest sensors whose coverage reaches SelectOptions::goal
  kKCoverage,  ///< maximum k-coverage with n sensors: a cell counts once k chosen sensors see it
  kBudget,     ///< maximum coverage with a total sensor cost within SelectOptions::budget
  kMinPoints,  ///< maximum coverage with n sensors, a cell counting once it holds min_points points
};

/// "coverage", "set-cover", "k-coverage", "budget", "min-points" (the `objective` key of
/// report.json).
std::string ObjectiveName(Objective objective);

/// The longest exact run a request may ask for [s]: a deadline this far ahead still fits the
/// steady clock's int64 nanoseconds many times over.
constexpr double kMaxTimeLimit = 1e6;
/// The shortest [s]: below a millisecond CBC and the clock reads cannot honour it, and the
/// warnings would quote limits like 1e-301 s (issue 15).
constexpr double kMinTimeLimit = 1e-3;

struct SelectOptions {
  int n = 1;  ///< sensors wanted, 1 <= n <= candidates (ignored by set-cover and budget)
  Method method = Method::kAll;
  int ransac_iterations = 1000;       ///< I of Algorithm 2
  double ransac_stop_coverage = 1.0;  ///< C of Algorithm 2, fraction
  uint64_t seed = 1;
  double time_limit = 60;  ///< seconds, for exact, in [kMinTimeLimit, kMaxTimeLimit]
  /// Set cover: choose the fewest sensors whose coverage reaches this fraction, in (0, 1].
  /// Methods greedy, exact, all. Above what all candidates reach together: InputError from Select.
  /// With k >= 2 (or min_points) the coverage counted is the k-coverage (the min-points one):
  /// the fewest sensors such that that share of R is seen k times (holds the points).
  std::optional<double> goal;
  /// With a goal: the cheapest answer (sum of `costs`) reaching it, instead of the fewest sensors
  /// (`--minimize cost`); needs `costs`. A cycle-time or other per-candidate price enters here
  /// the same way.
  bool minimize_cost = false;
  /// Where the goal was given, for that InputError: "--goal", or the scene's "file:line".
  std::string goal_source = "--goal";
  /// What SelectOverStates' groups of cells are, for its messages: "states", or "target parts"
  /// (--over-parts, whose groups are parts, or each state's parts).
  std::string groups = "states";
  /// k-coverage when >= 2: a cell counts only when at least k chosen sensors see it (stereo,
  /// redundancy); needs n >= k. Methods ransac, greedy, local, exact, all. 1 = plain coverage.
  int k = 1;
  /// Cost budget: the most coverage for a total cost (sum of `costs` of the chosen) <= budget;
  /// n is ignored. Methods greedy, local, exact, all. Needs `costs`.
  std::optional<double> budget;
  /// Unit cost of every candidate (SensorType::cost), in candidate order, each >= 0; used only
  /// with `budget`, which must afford the cheapest candidate, and with `minimize_cost`.
  std::vector<double> costs;
  /// Candidates every answer contains (`--keep-existing`: the sensors already in the cell), by
  /// index, distinct. Every method then chooses the best additions to them, exactly as it would
  /// on the residual problem (the cells they see counted already): n counts them too (n >= their
  /// number), a goal and a budget include them; with k, min_points and over scene states too.
  std::vector<uint32_t> fixed;
  /// Installation constraints (docs/constraints.md): conflicting pairs and calibration
  /// connectivity. Not empty: every method chooses only sets that satisfy them (the coverage
  /// objective only, without `fixed`).
  InstallConstraints constraints;
  /// Point density (docs/constraints.md): a cell counts only once the chosen sensors together put
  /// at least this many pixels' hits in it (Observation::reference_hits, which every observation
  /// must then have). Methods ransac, greedy, local, exact, all; not with another objective,
  /// `fixed` or `constraints`. 1 is plain coverage, counted the same way.
  std::optional<uint32_t> min_points;

  /// The objective these options select: goal -> set cover, k >= 2 -> k-coverage, budget ->
  /// budget, min_points -> min-points, none -> coverage.
  Objective objective() const;
  /// Throws InputError naming the field: out-of-range values, more than one objective, or a
  /// method that does not apply to the objective.
  void Validate(size_t candidate_count) const;
};

struct Selection {
  std::string method;
  int n = 0;
  std::vector<uint32_t> chosen;  ///< candidate indices, in the order chosen
  /// |∪O ∩ R| / |R|; for k-coverage the share of R seen by at least k of the chosen.
  double coverage = 0;
  /// |∪O| / |R|; for k-coverage the cells in R and keys outside R seen at least k times.
  double paper_coverage = 0;
  /// Proven bound on the best `coverage` under the same objective and constraint (n, or budget).
  std::optional<double> upper_bound;
  /// Proven optimal: coverage == upper_bound, or (set cover) n == n_lower_bound.
  bool proven_optimal = false;
  double seconds = 0;
  std::string objective = "coverage";  ///< ObjectiveName of what was optimised
  std::optional<double> goal;          ///< set cover: the coverage goal, fraction
  int k = 1;                           ///< k of k-coverage (1 otherwise)
  std::optional<uint32_t> min_points;  ///< min-points: the points a cell needs
  std::optional<double> budget;        ///< budget: the budget
  std::optional<double> cost;          ///< budget: total cost of the chosen sensors
  std::optional<int> n_lower_bound;    ///< set cover: proven least number of sensors
  /// Set cover minimising cost: proven least cost of any answer reaching the goal.
  std::optional<double> cost_lower_bound;
  /// A scene with states (select_states.hpp): the coverage of each state; `coverage` is then their
  /// mean or minimum. Empty otherwise.
  std::vector<double> state_coverage;
};

/// Coverage of unions of observation sets.
class CoverageEvaluator {
 public:
  CoverageEvaluator(std::span<const Observation> observations, size_t reference_size);
  /// Number of reference cells seen by the union of `chosen` (k = 1), or by at least k of them
  /// (k-coverage; a candidate listed twice counts twice).
  size_t CoveredCount(std::span<const uint32_t> chosen, int k = 1) const;
  double Coverage(std::span<const uint32_t> chosen, int k = 1) const;
  /// Cells of R plus distinct keys outside R seen by at least k of `chosen`, over |R|.
  double PaperCoverage(std::span<const uint32_t> chosen, int k = 1) const;
  /// Cells of R in which `chosen` together put at least `min_points` pixels' hits
  /// (reference_hits; InternalError when an observation has none).
  size_t PointCoveredCount(std::span<const uint32_t> chosen, uint32_t min_points) const;
  double PointCoverage(std::span<const uint32_t> chosen, uint32_t min_points) const;
  /// PointCoverage with `min_points`, else Coverage with k: the coverage a result reports.
  double CoverageUnder(std::span<const uint32_t> chosen, int k,
                       std::optional<uint32_t> min_points) const {
    return min_points ? PointCoverage(chosen, *min_points) : Coverage(chosen, k);
  }
  size_t reference_size() const { return reference_size_; }
  /// The observation sets it evaluates (one per candidate, in candidate order).
  std::span<const Observation> observations() const { return observations_; }

 private:
  std::span<const Observation> observations_;
  size_t reference_size_;
};

/// Runs `options.method` for `options.objective()`. kAll gives, for coverage: best (n = 1), then
/// ransac, greedy, local, exact for every n from 1 to options.n; for k-coverage: ransac, greedy,
/// local, exact for every n from k to options.n; for set cover: greedy, exact; for budget:
/// greedy, local, exact. Deterministic for a seed. InputError for invalid options and for a goal
/// above what all candidates reach together (the message names that maximum).
std::vector<Selection> Select(std::span<const Observation> observations,
                              size_t reference_size,
                              const SelectOptions& options);

/// The coverage-versus-n curve always reaches at least this n (issue 16).
inline constexpr int kCurveMinN = 6;

/// The coverage-versus-n curve beside a run's `results` (issue 16): greedy and local (cheap, for
/// any size) at every n from 1 (k for k-coverage) to max(up_to, the largest n of `results`),
/// capped at the number of candidates, where `results` has no answer of that method and n; each
/// scored as Select scores its answers. Exact is not run for the curve (its bounds are those of
/// `results`, where it ran). Empty for set cover and budget (they do not choose n). Deterministic.
std::vector<Selection> CoverageCurve(std::span<const Observation> observations,
                                     size_t reference_size, const SelectOptions& options,
                                     const std::vector<Selection>& results,
                                     int up_to = kCurveMinN);

/// `chosen` named `method`, scored under the objective of `options` exactly as Select scores its
/// answers (coverage or k-coverage, goal, budget and cost filled in); seconds 0, no bound.
Selection ScoreChosen(const CoverageEvaluator& evaluator, std::vector<uint32_t> chosen,
                      const std::string& method, const SelectOptions& options);

/// Swap local search (as method local runs it) from `start`, under the objective of `options`:
/// k-coverage for k >= 2, the budget with options.costs; never worse than `start`. For the
/// refinement of a constellation over grown candidate sets; with options.constraints, only swaps
/// that keep them (`start` must obey them); with options.fixed (in `start`), the kept sensors
/// first and never swapped out. InternalError for set cover.
std::vector<uint32_t> ImproveBySwaps(std::span<const Observation> observations,
                                     size_t reference_size, std::vector<uint32_t> start,
                                     const SelectOptions& options);

/// Single methods, each for exactly options.n sensors.
Selection SelectBest(const CoverageEvaluator& evaluator);
Selection SelectRansac(const CoverageEvaluator& evaluator, const SelectOptions& options);
Selection SelectGreedy(const CoverageEvaluator& evaluator, int n);

}  // namespace vantage
