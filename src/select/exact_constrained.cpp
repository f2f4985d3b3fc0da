// Exact selection under installation constraints (docs/constraints.md) and with kept sensors:
// the selection MILP (milp.hpp) with its conflict rows and connectivity flow, kept sensors as
// x fixed at 1; no dominance reduction under rules (a dominated candidate may be the only one
// that fits them). The answer is checked against the constraints in integers and padded; the
// bound is the least of CBC's and the unconstrained one (constraints only remove sets).
#include <fmt/format.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>

#include "select/cbc_answer.hpp"
#include "select/milp.hpp"
#include "select/constrained.hpp"
#include "select/methods.hpp"
#include "select/scorer.hpp"
#include "vantage/error.hpp"
#include "vantage/interrupt.hpp"

namespace vantage::detail {
namespace {

// The Lagrangian steps of the bound when CBC cannot finish (CBC's time rules: cbc_answer.hpp).
constexpr int kLagrangianSteps = 300;

// CBC's answer when it satisfies the constraints (tolerances) and the capacity, padded (with n
// sensors) by whatever still fits: coverage never drops by adding a sensor.
std::optional<std::vector<uint32_t>> UsableAnswer(const CoverageMatrix& matrix,
                                                  const Feasibility& feasible,
                                                  const Capacity& capacity,
                                                  std::span<const uint32_t> fixed,
                                                  std::vector<uint32_t> chosen) {
  if (chosen.empty() || !feasible.IsFeasible(chosen)) return std::nullopt;
  for (const uint32_t f : fixed)
    if (std::find(chosen.begin(), chosen.end(), f) == chosen.end()) return std::nullopt;
  // The kept sensors first, in their order, as every other method answers.
  std::erase_if(
      chosen, [&](uint32_t c) { return std::find(fixed.begin(), fixed.end(), c) != fixed.end(); });
  chosen.insert(chosen.begin(), fixed.begin(), fixed.end());
  if (capacity.has_budget()) {
    double total = 0;
    for (const uint32_t c : chosen) total += capacity.costs[c];
    if (total > capacity.budget) return std::nullopt;
    return chosen;
  }
  if (chosen.size() > capacity.n) return std::nullopt;
  std::vector<uint32_t> found = chosen;
  for (uint32_t c = 0; c < matrix.candidate_count() && found.size() < capacity.n; ++c)
    if (feasible.CanAdd(found, c)) found.push_back(c);
  return found;
}

}  // namespace

ExactResult SolveExactConstrained(const CoverageMatrix& matrix,
                                  const Feasibility& feasible,
                                  const Capacity& capacity,
                                  const ConstrainedObjective& objective,
                                  const std::vector<uint32_t>& start,
                                  uint64_t free_bound,
                                  double time_limit) {
  VANTAGE_CHECK(feasible.IsFeasible(start) &&
                (capacity.has_budget() || (capacity.n >= 1 && start.size() <= capacity.n)));
  const auto start_time = std::chrono::steady_clock::now();
  const int k = objective.threshold;
  const auto cells_of = [&](const std::vector<uint32_t>& set) {
    return KCoveredWeight(matrix, set, k);
  };
  ExactResult result;
  result.chosen = start;
  const uint64_t start_cells = cells_of(start);
  // Constraints only remove sets: the unconstrained bound holds.
  result.upper_bound = std::max(free_bound, start_cells);
  if (start_cells == result.upper_bound) {
    result.proven_optimal = true;
    result.note = "start meets the unconstrained bound";
    return result;
  }
  SelectionMilp milp;
  milp.matrix = &matrix;
  milp.threshold = k;
  milp.costs = capacity.costs;
  milp.capacity = capacity.has_budget() ? capacity.budget : static_cast<double>(capacity.n);
  milp.fixed = objective.fixed;
  milp.rules = &feasible;
  MilpAnswer outcome = SolveSelectionMilp(milp, start, time_limit);
  result.note = outcome.note;
  const std::optional<std::vector<uint32_t>> found =
      UsableAnswer(matrix, feasible, capacity, objective.fixed, outcome.chosen);
  if (found) {
    if (cells_of(*found) > start_cells) result.chosen = *found;
  } else if (!outcome.chosen.empty()) {
    result.note = "CBC's answer breaks a constraint by round-off; kept the start";
    outcome.proven_optimal = false;
  }
  const uint64_t cells = cells_of(result.chosen);
  if (std::isfinite(outcome.bound)) {
    const double bound_cells = std::floor(outcome.bound + 1e-6);
    if (bound_cells >= static_cast<double>(cells) &&
        bound_cells < static_cast<double>(result.upper_bound))
      result.upper_bound = static_cast<uint64_t>(bound_cells);
  }
  if (outcome.proven_optimal && cells >= cells_of(outcome.chosen)) result.upper_bound = cells;
  result.upper_bound = std::max(result.upper_bound, cells);
  result.proven_optimal = cells == result.upper_bound;
  if (!result.proven_optimal && k == 1 && !capacity.has_budget()) {
    // The unconstrained Lagrangian bound in the time left.
    const double left = time_limit - SecondsSince(start_time);
    if (left > 0.05) {
      const LagrangianBound lagrangian =
          LagrangianUpperBound(matrix, capacity.n, cells, kLagrangianSteps, 0.9 * left);
      result.upper_bound = std::max(cells, std::min(result.upper_bound, lagrangian.upper_bound));
      result.proven_optimal = cells == result.upper_bound;
    }
  }
  return result;
}

StatesExactResult SolveExactStatesConstrained(const CoverageMatrix& matrix,
                                              OverStates over,
                                              const Feasibility& feasible,
                                              size_t n,
                                              const std::vector<uint32_t>& start,
                                              double time_limit,
                                              int threshold,
                                              std::span<const uint32_t> fixed) {
  VANTAGE_CHECK(n >= 1 && feasible.IsFeasible(start) && start.size() <= n);
  constexpr double kProofTolerance = 1e-9;  // as exact_states.cpp
  constexpr double kFirstBoundShare = 0.1;
  const auto begin = std::chrono::steady_clock::now();
  const StatesScorer scorer(matrix, over, threshold);
  const auto aggregate_of = [&](const std::vector<uint32_t>& set) {
    return scorer.Fraction(scorer.Covered(set));
  };
  StatesExactResult result;
  result.chosen = start;
  if (n == 1 && fixed.empty()) {  // one sensor breaks no rule: the best single one is optimal
    uint32_t best = 0;
    StatesScorer::Score best_score = scorer.ScoreOf(scorer.Covered(std::vector<uint32_t>{0}));
    for (uint32_t i = 1; i < matrix.candidate_count(); ++i) {
      const StatesScorer::Score score = scorer.ScoreOf(scorer.Covered(std::vector<uint32_t>{i}));
      if (best_score < score) {  // strict: ties keep the lower index
        best = i;
        best_score = score;
      }
    }
    result.chosen = {best};
    result.upper_bound = aggregate_of(result.chosen);
    result.proven_optimal = true;
    return result;
  }
  // The unconstrained Lagrangian bound first (of plain coverage over states, which bounds point
  // coverage too: a cell with enough points is seen): when it proves the start, CBC is not needed.
  // With point counts that bound is of plain coverage, rarely tight: then CBC first.
  double bound = threshold > 1
                     ? std::numeric_limits<double>::infinity()
                     : StatesLagrangianBound(matrix, over, n, start, kFirstBoundShare * time_limit);
  const double start_aggregate = aggregate_of(start);
  if (bound - start_aggregate <= kProofTolerance) {
    result.upper_bound = start_aggregate;
    result.proven_optimal = true;
    return result;
  }
  SelectionMilp milp;
  milp.matrix = &matrix;
  milp.threshold = threshold;
  milp.value = over == OverStates::kMin ? MilpValue::kMin : MilpValue::kMean;
  milp.capacity = static_cast<double>(n);
  milp.rules = &feasible;
  milp.fixed = fixed;
  Capacity capacity;
  capacity.n = n;
  const MilpAnswer outcome = SolveSelectionMilp(milp, start, time_limit - SecondsSince(begin));
  result.note = outcome.note;
  StatesScorer::Score score = scorer.ScoreOf(scorer.Covered(result.chosen));
  bool cbc_proved = false;
  const std::optional<std::vector<uint32_t>> found =
      UsableAnswer(matrix, feasible, capacity, fixed, outcome.chosen);
  if (found) {
    const StatesScorer::Score found_score = scorer.ScoreOf(scorer.Covered(*found));
    if (score < found_score) {
      result.chosen = *found;
      score = found_score;
    }
    cbc_proved = outcome.proven_optimal;  // and we hold at least CBC's optimum
  } else if (!outcome.chosen.empty()) {
    result.note = "CBC's answer breaks a constraint by round-off; kept the start";
  }
  const double aggregate = aggregate_of(result.chosen);
  const double cbc_bound =
      std::isfinite(outcome.bound) ? outcome.bound : std::numeric_limits<double>::infinity();
  bound = std::min(bound, cbc_proved ? aggregate : cbc_bound);
  if (!std::isfinite(outcome.bound) && !cbc_proved) {  // CBC gave no bound: its time to the bound
    const double rest = kCbcKillShare * (time_limit - SecondsSince(begin));
    if (rest > 0.01)
      bound = std::min(bound, StatesLagrangianBound(matrix, over, n, result.chosen, rest));
  }
  if (!std::isfinite(bound)) {  // no time for anything: every candidate together bounds it
    std::vector<uint32_t> everyone(matrix.candidate_count());
    for (uint32_t i = 0; i < everyone.size(); ++i) everyone[i] = i;
    bound = aggregate_of(everyone);
  }
  result.upper_bound = std::max(bound, aggregate);
  result.proven_optimal = cbc_proved || result.upper_bound - aggregate <= kProofTolerance;
  if (result.proven_optimal) {
    result.upper_bound = aggregate;
    result.note.clear();
  }
  return result;
}

}  // namespace vantage::detail
