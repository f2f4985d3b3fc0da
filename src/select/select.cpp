// Select: runs the methods on the merged matrix and scores their answers (SYSTEM.md, stage 5).
//
// Every objective but a goal runs the methods on the model (constrained.cpp's ConstrainedMethods:
// the plain greedy, local search, RANSAC and one exact solve where no rule or kept sensor
// restricts it); every goal, and a budget counted k times or in points, runs the states' model
// on one state (over_states.cpp: GoalMethods, with the plain matrix's own set cover where no rule
// or kept sensor restricts it). Each runs in RunMethods' order, and answers are scored under their own metric (k-coverage counts a cell once k chosen
// sensors see it).
//
// Every method works on one detail::CoverageMatrix, built once per Select call: reference cells
// that exactly the same candidates see are merged into one weighted element and cells nobody
// sees are dropped, which keeps coverage exact and shrinks typical instances by orders of
// magnitude. Coverage and paper_coverage of every answer are then recomputed by
// CoverageEvaluator from the observations themselves, never taken from a method's bookkeeping.
#include "vantage/select.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <iterator>
#include <memory>
#include <optional>

#include "select/constrained.hpp"
#include "select/coverage_matrix.hpp"
#include "select/methods.hpp"
#include "select/model.hpp"
#include "vantage/error.hpp"
#include "vantage/select_states.hpp"

namespace vantage {
namespace {

using Clock = std::chrono::steady_clock;


double SecondsSince(Clock::time_point start) {
  return std::chrono::duration<double>(Clock::now() - start).count();
}

}  // namespace

namespace detail {

CoverageMatrix MatrixFor(std::span<const Observation> observations, size_t reference_size,
                         const SelectOptions& options) {
  if (!options.min_points) return CoverageMatrix(observations, reference_size);
  return CoverageMatrix(observations, reference_size, *options.min_points);
}

}  // namespace detail

namespace {

void ValidateN(int n, size_t candidate_count) {
  SelectOptions options;
  options.n = n;
  options.Validate(candidate_count);
}

// Min-points needs every observation's point counts (visibility files before format 4 have none).
void RequirePointCounts(std::span<const Observation> observations) {
  for (const Observation& o : observations) {
    if (!o.has_point_counts()) {
      throw FieldError({"min_points"},
                       "min_points needs the pixel counts per cell, which these observations do "
                       "not carry — observe the scene again with this vantage");
    }
  }
}

}  // namespace

namespace detail {

Selection ScoreSelection(const CoverageEvaluator& evaluator, std::vector<uint32_t> chosen,
                         const std::string& method, const SelectOptions& options) {
  const SelectionKind kind = KindFor(options);
  Selection s;
  s.method = method;
  s.n = static_cast<int>(chosen.size());
  s.chosen = std::move(chosen);
  s.coverage = evaluator.Coverage(s.chosen, kind.k);
  s.paper_coverage = evaluator.PaperCoverage(s.chosen, kind.k);
  if (kind.min_points) {
    // Counts are kept for R's cells only: the keys outside R count as seen (docs/constraints.md).
    const double outside = s.paper_coverage - s.coverage;
    s.coverage = evaluator.PointCoverage(s.chosen, *kind.min_points);
    s.paper_coverage = s.coverage + outside;
    s.min_points = kind.min_points;
  }
  s.objective = ObjectiveName(kind.objective);
  s.k = kind.k;
  if (kind.limit == SelectionKind::Limit::kGoal) {
    s.goal = options.goal;
    if (options.minimize_cost) s.cost = TotalCost(options.costs, s.chosen);
  }
  if (kind.limit == SelectionKind::Limit::kBudget) {
    s.budget = options.budget;
    s.cost = TotalCost(options.costs, s.chosen);
  }
  return s;
}

}  // namespace detail

Selection SelectBest(const CoverageEvaluator& evaluator) {
  const Clock::time_point start = Clock::now();
  const std::span<const Observation> observations = evaluator.observations();
  ValidateN(1, observations.size());
  uint32_t best = 0;
  for (uint32_t i = 1; i < observations.size(); ++i) {
    // Strict: ties keep the lower index. reference_indices are unique indices into R.
    if (observations[i].reference_indices.size() > observations[best].reference_indices.size())
      best = i;
  }
  Selection s;
  s.method = MethodName(Method::kBest);
  s.n = 1;
  s.chosen = {best};
  s.coverage = evaluator.Coverage(s.chosen);
  s.paper_coverage = evaluator.PaperCoverage(s.chosen);
  // The best single candidate is the optimum for n = 1.
  s.upper_bound = s.coverage;
  s.proven_optimal = true;
  s.seconds = SecondsSince(start);
  return s;
}

Selection SelectRansac(const CoverageEvaluator& evaluator, const SelectOptions& options) {
  SelectOptions ransac = options;
  ransac.method = Method::kRansac;
  return Select(evaluator.observations(), evaluator.reference_size(), ransac).front();
}

Selection SelectGreedy(const CoverageEvaluator& evaluator, int n) {
  ValidateN(n, evaluator.observations().size());
  SelectOptions options;
  options.n = n;
  options.method = Method::kGreedy;
  return Select(evaluator.observations(), evaluator.reference_size(), options).front();
}

namespace {

// The questions the methods on the cells (SelectConstrained) do not ask, and the states' model
// (over_states.cpp) does (SelectionKind::on_one_state): every goal (the one model's GoalMethods:
// kept sensors fixed at 1, a threshold per cell, costs, the rules; on the plain matrix its own set
// cover) and a budget counted k times or in points. Those combinations on the scene as one
// state: with one state the states' mean is the state's coverage (in units of 1 / |R|, exact),
// so the answers, bounds and proofs of SelectOverStates are those of the one state's problem. Each answer is scored again here, as every Select
// answer is (ScoreSelection: coverage, k, cost, goal or budget), its bounds and proof kept.
std::vector<Selection> SelectOnOneState(std::span<const Observation> observations,
                                        size_t reference_size, const SelectOptions& options) {
  if (options.min_points) RequirePointCounts(observations);
  const CoverageEvaluator evaluator(observations, reference_size);
  if (reference_size == 0) {
    throw InputError(options.goal ? AtPlace(options.goal_source,
                                            0,
                                            fmt::format("goal {:g} is above the 0.0000 that all {} "
                                                        "candidates reach together: R is empty — "
                                                        "lower --goal, or give the scene a target",
                                                        *options.goal, observations.size()))
                                  : "R is empty: a budget counted k times or in points has no "
                                    "cell to count — give the scene a target");
  }
  const StateObservations state{"", reference_size, observations};
  std::vector<StateSelection> answers =
      SelectOverStates(std::span<const StateObservations>(&state, 1), OverStates::kMean, options);
  std::vector<Selection> results;
  for (StateSelection& answer : answers) {
    const Selection& from = answer.selection;
    Selection s = detail::ScoreSelection(evaluator, from.chosen, from.method, options);
    s.seconds = from.seconds;
    if (from.upper_bound) s.upper_bound = std::max(*from.upper_bound, s.coverage);
    s.n_lower_bound = from.n_lower_bound;
    s.cost_lower_bound = from.cost_lower_bound;
    s.proven_optimal = from.proven_optimal;
    results.push_back(std::move(s));
  }
  return results;
}

}  // namespace

std::vector<Selection> Select(std::span<const Observation> observations,
                              size_t reference_size,
                              const SelectOptions& options) {
  options.Validate(observations.size());
  if (detail::KindFor(options).on_one_state) return SelectOnOneState(observations, reference_size, options);
  const CoverageEvaluator evaluator(observations, reference_size);
  // With kept sensors, SelectConstrained adds the best single one.
  if (options.method == Method::kBest && options.fixed.empty()) return {SelectBest(evaluator)};
  if (options.min_points) RequirePointCounts(observations);
  // Every objective but a goal: the methods on the model (ConstrainedMethods), with or without
  // rules and kept sensors.
  return detail::SelectConstrained(observations, reference_size, options);
}

std::vector<Selection> CoverageCurve(std::span<const Observation> observations,
                                     size_t reference_size, const SelectOptions& options,
                                     const std::vector<Selection>& results, int up_to) {
  const detail::SelectionKind kind = detail::KindFor(options);
  if (kind.limit != detail::SelectionKind::Limit::kSensors) return {};
  int last_n = up_to;
  for (const Selection& s : results) last_n = std::max(last_n, s.n);
  last_n = std::min(last_n, static_cast<int>(observations.size()));
  const int first_n = kind.k;
  if (last_n < first_n) return {};
  if (options.min_points) RequirePointCounts(observations);
  return detail::ConstrainedCurve(observations, reference_size, options, results, first_n,
                                  last_n);
}

}  // namespace vantage
