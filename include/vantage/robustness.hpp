#pragma once
/// Robustness read-outs of a chosen constellation (issue 9): a sensor failing, the fields of view
/// shrunk by a datasheet tolerance, and near-optimal alternatives to pick from for mounting.
#include <cstdint>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "vantage/candidates.hpp"
#include "vantage/observe.hpp"
#include "vantage/select.hpp"
#include "vantage/visibility_file.hpp"

namespace vantage {

/// The constellation's coverage when one of its sensors fails.
struct SensorFailure {
  uint32_t sensor = 0;  ///< candidate index of the failed sensor
  double coverage = 0;  ///< coverage (or k-coverage) of the others
};

/// A constellation differing from the chosen one in one sensor.
struct Alternative {
  std::vector<uint32_t> chosen;  ///< candidate indices, the chosen order with one replaced
  uint32_t replaced = 0;         ///< the chosen sensor it drops
  uint32_t replacement = 0;      ///< the candidate it takes instead
  double coverage = 0;
  /// Its total cost, where the result's objective prices the sensors (a budget, --cheapest).
  std::optional<double> cost;
};

/// Everything report.json, the summary and report.html show about one result.
struct Robustness {
  int result = -1;                          ///< index into the run's results
  std::vector<SensorFailure> failures;      ///< one per chosen sensor, in chosen order
  std::optional<SensorFailure> worst;       ///< the failure that loses the most coverage
  std::optional<double> fov_tolerance_deg;  ///< set when the shrunk-FOV read-out was computed
  std::optional<double> fov_shrunk_coverage;
  /// Why the shrunk-FOV read-out was skipped (a chosen sensor's field of view is not wider than
  /// the tolerance, e.g. a 2.5 deg camera and the default 3 deg); empty when it was computed or
  /// not asked for.
  std::string fov_note;
  double alternatives_within = 0.01;        ///< coverage points (fraction) an alternative may lose
  std::vector<Alternative> alternatives;    ///< best first
};

/// Coverage without each chosen sensor (k-coverage when k >= 2; with `min_points`, the cells
/// with that many points), in chosen order.
std::vector<SensorFailure> SensorFailures(const CoverageEvaluator& evaluator,
                                          std::span<const uint32_t> chosen, int k = 1,
                                          std::optional<uint32_t> min_points = std::nullopt);

/// What a one-sensor replacement must keep, and how the replacements of a slot are ranked.
struct AlternativeRules {
  int k = 1;                           ///< coverage counts cells seen k times
  std::optional<uint32_t> min_points;  ///< or cells with this many points
  double within = 0.01;                ///< coverage (fraction) an alternative may lose
  std::optional<double> at_least;      ///< set cover's goal: the coverage it must still reach
  std::span<const uint32_t> kept;      ///< installed: never replaced
  /// Per candidate, where the objective prices the sensors; empty: unpriced.
  std::span<const double> costs;
  std::optional<double> budget;  ///< with `costs`: the total an alternative must stay within
  /// With `costs` (--cheapest): a slot's best replacement is the cheapest one that keeps the
  /// rules (then the most coverage), instead of the one with the most coverage.
  bool cheapest = false;
};

/// The best single-sensor replacement for each chosen sensor that keeps `rules`: coverage at
/// least coverage(chosen) - within, the goal, the budget; best first (most coverage, or with
/// `cheapest` least cost), ties by the replaced sensor's position. Coverage counts as in
/// SensorFailures. Deterministic.
std::vector<Alternative> NearOptimalAlternatives(const CoverageEvaluator& evaluator,
                                                 std::span<const uint32_t> chosen,
                                                 const AlternativeRules& rules);

/// The candidates with both fields of view narrowed by `tolerance_deg` (resolution and principal
/// point kept, focal lengths grown), as a unit whose optics are at the datasheet's low end.
/// InputError when the tolerance is not in [0, the smaller field of view).
std::vector<Candidate> ShrinkFov(std::span<const Candidate> candidates, double tolerance_deg);

/// What AssessRobustness computes beyond the failures.
struct RobustnessOptions {
  double fov_tolerance_deg = 3;  ///< fields of view narrowed by this [deg], >= 0
  double within = 0.01;          ///< coverage (fraction) an alternative may lose, in [0, 1]
  /// Candidates already installed (--keep-existing): no alternative replaces them.
  std::vector<uint32_t> kept;
  /// Per candidate: the prices a budget or --cheapest result was selected with (empty: none), so
  /// its alternatives keep the budget, or rank by cost, and say what they cost.
  std::vector<double> costs;
  /// InputError naming the option (--fov-tolerance, --alternatives-within).
  void Validate() const;
};

/// The read-outs for `results[index]` of a run over `data`: failures, alternatives within
/// options.within (fraction) that keep set cover's goal, and, when `rays` is given (the RayScene
/// of the scene `data` was observed in), the coverage with every chosen sensor's field of view
/// shrunk by options.fov_tolerance_deg, those sensors re-traced with `observe` (the run's culling
/// and the data's quality filter); skipped with `fov_note` when a chosen sensor's field of view is
/// not wider than the tolerance (never an error: the tolerance is a read-out, not an input). Budget results get no alternatives (a swap may break the
/// budget).
Robustness AssessRobustness(const VisibilityFile& data, const std::vector<Selection>& results,
                            int index, const RayScene* rays, const ObserveOptions& observe,
                            const RobustnessOptions& options);

}  // namespace vantage
