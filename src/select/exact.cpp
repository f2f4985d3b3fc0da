// Exact selection of one state's cells (SYSTEM.md, Select: `exact`): how each objective uses the
// selection MILP (milp.hpp) and the bounds beside it. Maximum coverage with n sensors tries CBC
// on small models, then branch and bound on the Lagrangian bound (branch_and_bound.cpp);
// k-coverage enumerates small instances; a budget and min-points tighten CBC's bound by the LP
// bound; the fewest sensors settle t cheaply where they can, then the goal MILP, then t by t.
#include <fmt/format.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <limits>
#include <optional>
#include <string>

#include "select/milp.hpp"
#include "select/methods.hpp"
#include "select/objective_bounds.hpp"
#include "vantage/error.hpp"
#include "vantage/interrupt.hpp"

namespace vantage::detail {
namespace {

// k-coverage has a weak LP relaxation (k y_e <= sum x_i lets every y_e be 1/k-covered by
// fractions of sensors), so CBC branches long even on tiny instances; up to this many n-subsets
// of the candidates that see anything, exhaustive search is faster and equally exact.
constexpr double kMaxEnumeratedSubsets = 300000;

// Models up to this many row nonzeros go to CBC first (it proves the small shared worlds in a
// few seconds); larger ones, and whatever CBC leaves unproved, go to BranchAndBound, which gets
// this share of the time limit (the rest absorbs its last node and the caller's scoring).
constexpr size_t kCbcFirstNonzeros = 100000;
constexpr double kBranchAndBoundTimeShare = 0.9;
// Below this many seconds left the root bound cannot improve on the cheap one: not started.
constexpr double kMinBranchAndBoundSeconds = 0.02;
// Min-points: the share of the time limit for the plain-coverage bound over the cells that can
// reach the points (a relaxation: a cell with enough points is seen); CBC gets the rest.
constexpr double kRelaxedBoundShare = 0.25;
// Set cover: the share of the time left that the goal MILP gets before the search t by t.
constexpr double kGoalMilpTimeShare = 0.5;
// Set cover of every cell on a symmetric instance: the share of the time left for orbital
// branching (OrbitalSetCover) before the goal MILP.
constexpr double kOrbitalTimeShare = 0.9;

// The MILP for at most n sensors (k-coverage when k >= 2); an answer with more than n sensors,
// which CBC should never return, is dropped rather than trusted.
MilpAnswer CardinalityCbc(const CoverageMatrix& matrix, int k, size_t n,
                          const std::vector<uint32_t>& start, double time_limit) {
  SelectionMilp milp;
  milp.matrix = &matrix;
  milp.threshold = k;
  milp.capacity = static_cast<double>(n);
  MilpAnswer answer = SolveSelectionMilp(milp, start, time_limit);
  if (answer.chosen.size() > n) {
    answer = MilpAnswer{};
    answer.note = "CBC returned more than n sensors";
  }
  return answer;
}

// Number of n-subsets of m items, or +inf beyond `cap`.
double SubsetCount(size_t m, size_t n, double cap) {
  double count = 1;
  for (size_t j = 0; j < n; ++j) {
    count = count * static_cast<double>(m - j) / static_cast<double>(j + 1);
    if (count > cap) return std::numeric_limits<double>::infinity();
  }
  return count;
}

// The n-subset of `pool` with the most k-covered cells, by depth-first enumeration in index order
// with the k-covered weight kept incrementally (ties: the first subset in that order).
std::vector<uint32_t> EnumerateKCoverage(const CoverageMatrix& matrix,
                                         const std::vector<uint32_t>& pool,
                                         size_t n,
                                         int k) {
  std::vector<uint32_t> count(matrix.element_count(), 0);
  std::vector<uint32_t> current, best;
  uint64_t weight = 0, best_weight = 0;
  const auto kk = static_cast<uint32_t>(k);
  const auto visit = [&](const auto& self, size_t from) -> void {
    if (current.size() == n) {
      if (best.empty() || weight > best_weight) {
        best = current;
        best_weight = weight;
      }
      return;
    }
    for (size_t p = from; p + (n - current.size()) <= pool.size(); ++p) {
      const uint32_t c = pool[p];
      const std::vector<uint32_t>& row = matrix.Row(c);
      for (size_t j = 0; j < row.size(); ++j) {
        const uint32_t e = row[j];
        const uint32_t before = count[e];
        count[e] += matrix.Count(c, j);
        if (before < kk && count[e] >= kk) weight += matrix.Weight(e);
      }
      current.push_back(c);
      self(self, p + 1);
      current.pop_back();
      for (size_t j = 0; j < row.size(); ++j) {
        const uint32_t e = row[j];
        const uint32_t before = count[e];
        count[e] -= matrix.Count(c, j);
        if (before >= kk && count[e] < kk) weight -= matrix.Weight(e);
      }
    }
  };
  visit(visit, 0);
  return best;
}

// The final upper bound of a maximisation from the cheap bound already in `result` and CBC's.
// Whole cells: the optimum is at most CBC's bound rounded down (the tolerance absorbs the
// solver's round-off). A bound below what we hold cannot be one (CBC stopped early): ignored.
// `is_cbc_optimal`: CBC proved its own answer optimal, and `cells` is at least that answer.
void SettleUpperBound(uint64_t cells, double cbc_bound, bool is_cbc_optimal, ExactResult* result) {
  if (std::isfinite(cbc_bound)) {
    const double bound_cells = std::floor(cbc_bound + 1e-6);
    if (bound_cells >= static_cast<double>(cells) &&
        bound_cells < static_cast<double>(result->upper_bound)) {
      result->upper_bound = static_cast<uint64_t>(bound_cells);
    }
  }
  if (is_cbc_optimal) result->upper_bound = cells;
  result->upper_bound = std::max(result->upper_bound, cells);
  result->proven_optimal = cells == result->upper_bound;
}

}  // namespace

GoalResult SolveGoalMilp(const CoverageMatrix& matrix, int k, std::span<const double> costs,
                         uint64_t goal_cells, const std::vector<uint32_t>& start,
                         double time_limit) {
  VANTAGE_CHECK(k >= 1 && goal_cells >= 1 && (costs.empty() || costs.size() ==
                                                                   matrix.candidate_count()));
  GoalResult result;
  SelectionMilp milp;
  milp.matrix = &matrix;
  milp.threshold = k;
  milp.costs = costs;
  milp.goal = static_cast<double>(goal_cells);
  const MilpAnswer answer = SolveSelectionMilp(milp, start, time_limit);
  result.note = answer.note;
  const bool whole = costs.empty() || AllWhole(costs);
  if (std::isfinite(answer.bound))
    result.lower_bound = whole ? std::ceil(answer.bound - 1e-6) : answer.bound - 1e-9;
  result.lower_bound = std::max(0.0, result.lower_bound);
  if (answer.chosen.empty()) return result;
  // Trusted only when it reaches the goal in integers (CBC's tolerances are not whole cells).
  if (KCoveredWeight(matrix, answer.chosen, k) < goal_cells) {
    result.note = "CBC's answer misses the goal by round-off";
    return result;
  }
  result.chosen = answer.chosen;
  result.proven_optimal = answer.proven_optimal;
  return result;
}

ExactResult SolveExact(const CoverageMatrix& matrix,
                       size_t n,
                       const std::vector<uint32_t>& start,
                       double time_limit) {
  VANTAGE_CHECK(n >= 1 && n <= matrix.candidate_count() && start.size() == n);
  const auto start_time = std::chrono::steady_clock::now();
  ExactResult result;
  result.chosen = start;
  const uint64_t start_cells = matrix.CoveredWeight(start);
  result.upper_bound = std::max(GreedyUpperBound(matrix, start, n), start_cells);
  if (start_cells == result.upper_bound) {
    result.proven_optimal = true;
    result.note = "start meets the simple bound";
    return result;
  }
  if (n == 1) {
    const uint32_t best = BestCandidate(CellScorer(matrix));
    result.chosen = {best};
    result.upper_bound = matrix.RowWeight(best);
    result.proven_optimal = true;
    return result;
  }
  size_t nonzeros = 0;
  for (const std::vector<uint32_t>& row : matrix.rows()) nonzeros += row.size();
  if (nonzeros <= kCbcFirstNonzeros) {
    MilpAnswer outcome = CardinalityCbc(matrix, 1, n, start, time_limit);
    result.note = outcome.note;
    if (!outcome.chosen.empty()) {
      std::vector<uint32_t> padded = GreedyComplete(CellScorer(matrix), outcome.chosen, n);
      if (matrix.CoveredWeight(padded) > start_cells) result.chosen = std::move(padded);
    }
    SettleUpperBound(matrix.CoveredWeight(result.chosen), outcome.bound, outcome.proven_optimal,
                     &result);
    if (result.proven_optimal) return result;
  }
  // Branch and bound on the Lagrangian bound in the time left.
  BranchAndBoundLimits limits;
  limits.seconds = kBranchAndBoundTimeShare * time_limit - SecondsSince(start_time);
  if (limits.seconds < kMinBranchAndBoundSeconds) return result;
  const BranchAndBoundResult search =
      BranchAndBound(matrix, n, result.chosen, result.upper_bound, limits);
  if (search.cells > matrix.CoveredWeight(result.chosen)) result.chosen = search.chosen;
  result.upper_bound = std::max(std::min(result.upper_bound, search.upper_bound),
                                matrix.CoveredWeight(result.chosen));
  result.proven_optimal = result.upper_bound == matrix.CoveredWeight(result.chosen);
  const std::string lp =
      search.root_lp_bound == 0
          ? std::string()
          : fmt::format("; the LP's {} cells from CLP{} in {:.1f} s, the subgradient's {}",
                        search.root_lp_bound, search.root_lp_optimal ? " (optimal)" : "",
                        search.root_lp_seconds, search.root_subgradient_bound);
  const std::string what = fmt::format(
      "branch and bound: {} nodes, root bound {} cells ({} candidates fixed in, {} removed{})",
      search.nodes, search.root_bound, search.root_fixed_in, search.root_removed, lp);
  if (result.proven_optimal) {
    result.note = what;
  } else {
    result.note = fmt::format("{}{}{}", result.note.empty() ? "" : result.note + "; ", what,
                              search.timed_out ? " — reached the time limit; raise --time-limit "
                                                 "to prove more"
                                               : "");
  }
  return result;
}

ExactResult SolveExactK(const CoverageMatrix& matrix,
                        size_t n,
                        int k,
                        const std::vector<uint32_t>& start,
                        double time_limit,
                        bool may_enumerate) {
  VANTAGE_CHECK(k >= 1 && n >= 1 && n <= matrix.candidate_count() && start.size() == n);
  if (k == 1) return SolveExact(matrix, n, start, time_limit);
  const auto start_time = std::chrono::steady_clock::now();
  ExactResult result;
  result.chosen = start;
  const uint64_t start_cells = KCoveredWeight(matrix, start, k);
  result.upper_bound = std::max(KUpperBound(matrix, start, n, k), start_cells);
  if (start_cells == result.upper_bound) {
    result.proven_optimal = true;
    result.note = "start meets the simple bound";
    return result;
  }
  std::vector<uint32_t> pool;
  for (uint32_t i = 0; i < matrix.candidate_count(); ++i) {
    if (!matrix.Row(i).empty()) pool.push_back(i);
  }
  if (pool.size() <= n ||
      (may_enumerate && std::isfinite(SubsetCount(pool.size(), n, kMaxEnumeratedSubsets)))) {
    std::vector<uint32_t> found = pool.size() <= n ? pool : EnumerateKCoverage(matrix, pool, n, k);
    found = KGreedyComplete(matrix, std::move(found), n, k);
    const uint64_t cells = KCoveredWeight(matrix, found, k);
    if (cells > start_cells) result.chosen = std::move(found);
    result.upper_bound = std::max(cells, start_cells);
    result.proven_optimal = true;
    result.note = "solved by enumeration";
    return result;
  }
  double cbc_seconds = time_limit;
  if (matrix.has_counts()) {
    // The matrix holds only the cells that can reach the points, so its plain-coverage optimum
    // bounds the min-points one, and exact proves it fast (the Lagrangian, branch and bound).
    const ExactResult relaxed =
        SolveExact(matrix, n, GreedyComplete(CellScorer(matrix), {}, n),
                   kRelaxedBoundShare * time_limit);
    result.upper_bound = std::max(std::min(result.upper_bound, relaxed.upper_bound), start_cells);
    if (start_cells == result.upper_bound) {
      result.proven_optimal = true;
      result.note = "start meets the plain-coverage bound";
      return result;
    }
    cbc_seconds = std::max(0.1 * time_limit, time_limit - SecondsSince(start_time));
  }
  MilpAnswer outcome = CardinalityCbc(matrix, k, n, start, cbc_seconds);
  result.note = outcome.note;
  if (!outcome.chosen.empty()) {
    std::vector<uint32_t> padded = KGreedyComplete(matrix, outcome.chosen, n, k);
    if (KCoveredWeight(matrix, padded, k) > start_cells) result.chosen = std::move(padded);
  }
  const uint64_t cells = KCoveredWeight(matrix, result.chosen, k);
  SettleUpperBound(cells, outcome.bound, outcome.proven_optimal, &result);
  // The LP bound's rows count seers, not points: not a bound with point counts.
  if (!matrix.has_counts())
    TightenByLpBound(CardinalityLp(matrix, n, k), cells, start_time, time_limit, &result);
  return result;
}

ExactResult SolveExactBudget(const CoverageMatrix& matrix,
                             std::span<const double> costs,
                             double budget,
                             const std::vector<uint32_t>& start,
                             double time_limit) {
  VANTAGE_CHECK(costs.size() == matrix.candidate_count() && !start.empty() &&
                TotalCost(costs, start) <= budget);
  const auto start_time = std::chrono::steady_clock::now();
  ExactResult result;
  result.chosen = start;
  const uint64_t start_cells = matrix.CoveredWeight(start);
  result.upper_bound = std::max(BudgetUpperBound(matrix, start, costs, budget), start_cells);
  if (start_cells == result.upper_bound) {
    result.proven_optimal = true;
    result.note = "start meets the simple bound";
    return result;
  }
  SelectionMilp milp;
  milp.matrix = &matrix;
  milp.costs = costs;
  milp.capacity = budget;
  MilpAnswer outcome = SolveSelectionMilp(milp, start, time_limit);
  if (!outcome.chosen.empty() && TotalCost(costs, outcome.chosen) > budget) {
    // CBC's feasibility tolerance let the costs exceed the budget by round-off: not an answer.
    const double bound = outcome.bound;
    outcome = MilpAnswer{};
    outcome.bound = bound;
    outcome.note = "CBC's answer exceeds the budget by round-off; kept the start";
  }
  result.note = outcome.note;
  if (!outcome.chosen.empty() && matrix.CoveredWeight(outcome.chosen) > start_cells)
    result.chosen = outcome.chosen;
  const uint64_t cells = matrix.CoveredWeight(result.chosen);
  SettleUpperBound(cells, outcome.bound, outcome.proven_optimal, &result);
  TightenByLpBound(BudgetLp(matrix, costs, budget), cells, start_time, time_limit, &result);
  return result;
}

SetCoverResult SolveSetCover(const CoverageMatrix& matrix,
                             uint64_t goal_cells,
                             const std::vector<uint32_t>& start,
                             double time_limit) {
  VANTAGE_CHECK(goal_cells >= 1 && !start.empty() && matrix.CoveredWeight(start) >= goal_cells);
  // Two proofs share the time. The fewest sensors is the least t whose maximum coverage reaches
  // the goal: going up from a lower bound, each t is settled by the cheapest proof (the greedy
  // bound below the goal: too few; greedy or local search reaching it: enough). What that
  // leaves open goes first to the goal as one MILP (SolveGoalMilp: its covering rows are the
  // structure CBC's cuts and bound know, where maximum coverage's LP at t fractional sensors
  // reaches any goal: Steiner triple systems, covering designs), for a share of the time, then
  // t by t to SolveExact in the rest (vantage's own matrices, whose goal rows are long).
  const auto start_time = std::chrono::steady_clock::now();
  const auto seconds_left = [&] { return time_limit - SecondsSince(start_time); };
  SetCoverResult result;
  result.chosen = start;
  size_t lower = std::max<size_t>(1, SetCoverLowerBound(matrix, goal_cells));
  lower = SetCoverLpLowerBound(matrix, goal_cells, std::min(lower, start.size()), start.size(),
                               time_limit);
  const auto settle_cheaply = [&] {  // true once settled
    for (size_t t = lower; t < result.chosen.size(); ++t) {
      const std::vector<uint32_t> greedy = GreedyComplete(CellScorer(matrix), {}, t);
      if (GreedyUpperBound(matrix, greedy, t) < goal_cells) {
        lower = t + 1;  // no t sensors reach the goal
        continue;
      }
      std::vector<uint32_t> found = LocalSearch(CellScorer(matrix), greedy);
      if (matrix.CoveredWeight(found) < goal_cells) return false;
      result.chosen = std::move(found);  // t sensors reach the goal, and t - 1 do not
      return true;
    }
    return true;
  };
  const auto finish = [&] {
    result.lower_bound = std::min(lower, result.chosen.size());
    result.proven_optimal = result.lower_bound == result.chosen.size();
    if (result.proven_optimal) result.note.clear();
    return result;
  };
  if (settle_cheaply()) return finish();
  if (goal_cells == matrix.seen_weight() && !matrix.has_counts()) {
    // Every cell: where the instance is symmetric (covering designs), orbital branching.
    const OrbitalSetCoverResult orbital =
        OrbitalSetCover(matrix, result.chosen, lower, kOrbitalTimeShare * seconds_left());
    if (orbital.applied) {
      if (orbital.chosen.size() < result.chosen.size()) result.chosen = orbital.chosen;
      lower = std::max(lower, orbital.lower_bound);
      result.note = orbital.note;
      if (lower >= result.chosen.size()) return finish();
    }
  }
  const GoalResult milp =
      SolveGoalMilp(matrix, 1, {}, goal_cells, result.chosen, kGoalMilpTimeShare * seconds_left());
  if (milp.chosen.size() >= 1 && milp.chosen.size() < result.chosen.size())
    result.chosen = milp.chosen;
  lower = std::max(lower, static_cast<size_t>(milp.lower_bound));
  if (milp.proven_optimal) lower = std::max(lower, result.chosen.size());
  result.note = milp.note;
  if (lower >= result.chosen.size() || settle_cheaply()) return finish();
  for (size_t t = lower; t < result.chosen.size(); ++t) {
    std::vector<uint32_t> found =
        LocalSearch(CellScorer(matrix), GreedyComplete(CellScorer(matrix), {}, t));
    if (matrix.CoveredWeight(found) < goal_cells) {
      const double left = seconds_left();
      if (left <= 0) {
        result.note = fmt::format("time limit reached before settling {} sensors", t);
        break;
      }
      const ExactResult exact = SolveExact(matrix, t, found, left);
      if (exact.upper_bound < goal_cells) {
        lower = t + 1;  // proven: no t sensors reach the goal
        continue;
      }
      if (matrix.CoveredWeight(exact.chosen) < goal_cells) {
        result.note = fmt::format("{} sensors not settled: {}", t,
                                  exact.note.empty() ? "solver stopped" : exact.note);
        break;
      }
      found = exact.chosen;
    }
    result.chosen = std::move(found);  // t sensors reach the goal, and t - 1 do not
    break;
  }
  return finish();
}

}  // namespace vantage::detail
