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
                                              const Capacity& capacity,
                                              const std::vector<uint32_t>& start,
                                              double time_limit,
                                              int threshold,
                                              std::span<const uint32_t> fixed) {
  // The most sensors any answer holds: n, or with a budget the kept ones and the cheapest others
  // that fit beside them (what the cardinality bound may assume).
  size_t n = capacity.n;
  if (capacity.has_budget()) {
    std::vector<double> others;
    double left = capacity.budget;
    for (uint32_t c = 0; c < matrix.candidate_count(); ++c) {
      if (std::find(fixed.begin(), fixed.end(), c) != fixed.end())
        left -= capacity.costs[c];
      else
        others.push_back(capacity.costs[c]);
    }
    std::sort(others.begin(), others.end());
    n = fixed.size();
    for (const double cost : others) {
      if (cost > left) break;
      left -= cost;
      ++n;
    }
  }
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
  if (n == 1 && fixed.empty() && !capacity.has_budget()) {
    // One sensor breaks no rule: the best single one is optimal.
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
  milp.capacity = capacity.has_budget() ? capacity.budget : static_cast<double>(n);
  milp.costs = capacity.costs;
  milp.rules = &feasible;
  milp.fixed = fixed;
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

double RowSumGoalBound(const StatesScorer& scorer, std::span<const double> costs, double goal,
                       std::span<const uint32_t> fixed) {
  const CoverageMatrix& matrix = scorer.matrix();
  const size_t states = matrix.state_count();
  const StateTally kept = scorer.Covered(fixed);
  const auto cost_of = [&](uint32_t c) { return costs.empty() ? 1.0 : costs[c]; };
  double kept_cost = 0;
  for (const uint32_t f : fixed) kept_cost += cost_of(f);
  // The cheapest fractional choice of others whose values (value(c)) sum to `need`.
  const auto knapsack = [&](double need, const auto& value) {
    if (need <= 0) return 0.0;
    struct Item {
      double value, cost;
    };
    std::vector<Item> items;
    for (uint32_t c = 0; c < matrix.candidate_count(); ++c) {
      if (std::find(fixed.begin(), fixed.end(), c) != fixed.end()) continue;
      const double v = value(c);
      if (v > 0) items.push_back({v, cost_of(c)});
    }
    std::sort(items.begin(), items.end(), [](const Item& a, const Item& b) {
      return a.value * b.cost > b.value * a.cost;  // value per cost, free ones first
    });
    double total = 0;
    for (const Item& item : items) {
      if (item.value >= need) return total + item.cost * need / item.value;
      need -= item.value;
      total += item.cost;
    }
    return std::numeric_limits<double>::infinity();  // unreachable
  };
  // Slack below the goal: GoalReached's 1e-9 and some round-off, so the bound stays proven.
  const double target = goal - 1e-9 - 1e-12;
  double others = 0;
  if (scorer.over() == OverStates::kMean) {
    const auto share = [&](const StateTally& t) {
      double sum = 0;
      for (size_t st = 0; st < states; ++st)
        sum += static_cast<double>(t[st]) / static_cast<double>(matrix.StateReferenceSize(st));
      return sum / static_cast<double>(states);
    };
    others = knapsack(target - share(kept) - 1e-12,
                      [&](uint32_t c) { return share(scorer.RowWeight(c)); });
  } else {
    for (size_t st = 0; st < states; ++st) {
      const double r = static_cast<double>(matrix.StateReferenceSize(st));
      others = std::max(others, knapsack(target * r - static_cast<double>(kept[st]) - 1e-9,
                                         [&](uint32_t c) {
                                           return static_cast<double>(scorer.RowWeight(c)[st]);
                                         }));
    }
  }
  if (!std::isfinite(others)) others = 0;  // only round-off: a start reaches the goal
  if (costs.empty()) others = std::ceil(others - 1e-9);
  return kept_cost + std::max(0.0, others);
}

GoalResult SolveStatesGoal(const StatesScorer& scorer,
                           const Feasibility& feasible,
                           std::span<const double> costs,
                           double goal,
                           std::span<const uint32_t> fixed,
                           const std::vector<uint32_t>& start,
                           double time_limit) {
  const CoverageMatrix& matrix = scorer.matrix();
  const auto cost_of = [&](const std::vector<uint32_t>& set) {
    return costs.empty() ? static_cast<double>(set.size()) : TotalCost(costs, set);
  };
  GoalResult result;
  result.chosen = start;
  result.lower_bound = RowSumGoalBound(scorer, costs, goal, fixed);
  if (cost_of(start) <= result.lower_bound) {  // the start meets the simple bound
    result.lower_bound = cost_of(start);
    result.proven_optimal = true;
    return result;
  }
  SelectionMilp milp;
  milp.matrix = &matrix;
  milp.threshold = scorer.k();
  milp.value = scorer.over() == OverStates::kMin ? MilpValue::kMin : MilpValue::kMean;
  milp.costs = costs;
  milp.goal = goal - 1e-9;  // GoalReached's tolerance: the model is the goal exactly
  milp.fixed = fixed;
  milp.rules = &feasible;
  const MilpAnswer answer = SolveSelectionMilp(milp, start, time_limit);
  result.note = answer.note;
  const bool whole = costs.empty() || AllWhole(costs);
  if (std::isfinite(answer.bound)) {
    result.lower_bound = std::max(
        result.lower_bound, whole ? std::ceil(answer.bound - 1e-6) : answer.bound - 1e-9);
  }
  bool cbc_answer = false;
  if (!answer.chosen.empty() && feasible.IsFeasible(answer.chosen) &&
      std::all_of(fixed.begin(), fixed.end(), [&](uint32_t f) {
        return std::find(answer.chosen.begin(), answer.chosen.end(), f) != answer.chosen.end();
      })) {
    // The kept sensors first, in their order, as every other method answers.
    std::vector<uint32_t> found(fixed.begin(), fixed.end());
    for (const uint32_t c : answer.chosen)
      if (std::find(fixed.begin(), fixed.end(), c) == fixed.end()) found.push_back(c);
    if (!GoalReached(scorer.Fraction(scorer.Covered(found)), goal)) {
      result.note = "CBC's answer misses the goal by round-off";
    } else if (cost_of(found) <= cost_of(result.chosen)) {
      cbc_answer = cost_of(found) < cost_of(result.chosen) || answer.proven_optimal;
      if (cost_of(found) < cost_of(result.chosen)) result.chosen = std::move(found);
    }
  }
  const double cost = cost_of(result.chosen);
  if (cbc_answer && answer.proven_optimal) result.lower_bound = cost;
  result.lower_bound = std::min(result.lower_bound, cost);
  result.proven_optimal = cost <= result.lower_bound;
  if (result.proven_optimal) result.note.clear();
  return result;
}

}  // namespace vantage::detail
