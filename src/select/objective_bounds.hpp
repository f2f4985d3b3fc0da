#pragma once
/// LP-strength bounds for the objectives beyond maximum coverage with n sensors (issue 14):
/// k-coverage, budget, set cover and selection over the states of a scene. All rest on one
/// Lagrangian relaxation of a weighted coverage LP (objective_bounds.cpp); maximum coverage with
/// n sensors itself has its own (LagrangianUpperBound, methods.hpp).
#include <chrono>
#include <cstddef>
#include <cstdint>
#include <span>
#include <string>
#include <vector>

#include "select/coverage_matrix.hpp"
#include "select/methods.hpp"
#include "vantage/select_states.hpp"

namespace vantage::detail {

class StatesScorer;

/// A weighted maximum coverage LP over `matrix`:
///   max sum_e weights_e y_e  s.t.  k y_e <= sum_{i sees e} x_i,  x, y in [0, 1],
///   and sum_i x_i <= n (costs empty) or sum_i costs_i x_i <= budget.
/// Its optimum bounds the integer problem's; elements that fewer than k usable candidates see
/// count nothing (no answer k-covers them), and candidates costing more than the budget are not
/// usable (no answer contains them), which only tightens it.
struct CoverageLp {
  const CoverageMatrix* matrix = nullptr;
  std::vector<uint64_t> weights;  ///< per element of matrix; below 2^43 in total
  uint32_t k = 1;                 ///< >= 1
  size_t n = 0;                   ///< cardinality, when costs is empty: 1 <= n
  std::span<const double> costs;  ///< per candidate, >= 0; empty: the cardinality row
  double budget = 0;              ///< with costs
};

/// `matrix`'s own element weights (cells), for CoverageLp::weights.
std::vector<uint64_t> CellWeights(const CoverageMatrix& matrix);
/// The LP of maximum k-coverage of `matrix`'s cells with n sensors.
CoverageLp CardinalityLp(const CoverageMatrix& matrix, size_t n, int k = 1);
/// The LP of maximum coverage of `matrix`'s cells within a budget.
CoverageLp BudgetLp(const CoverageMatrix& matrix, std::span<const double> costs, double budget);

/// A proven upper bound on a CoverageLp (hence on its integer problem).
struct CoverageLpBound {
  uint64_t upper_bound = 0;  ///< floor of L(multipliers), evaluated exactly: valid for any input
  /// The usable candidates the relaxed subproblem picks (x_i > 0) at the best multipliers: an
  /// LP-guided answer (n of them for the cardinality row; within the budget plus at most one more
  /// for the knapsack).
  std::vector<uint32_t> chosen;
  int iterations = 0;  ///< subgradient steps taken
};

/// Relaxes the coverage rows with multipliers mu_e / k, mu in [0, w] (mu_e = k lambda_e):
///   L(mu) = sum_e (w_e - mu_e) + max_x sum_i x_i r_i / k,  r_i = sum_{e in row i} mu_e,
/// where the max over x is the n largest r_i (cardinality) or, for a budget, the fractional
/// knapsack, bounded through its dual theta B + sum_i max(0, r_i - theta c_i) (valid for every
/// theta >= 0, equal to the knapsack LP at the critical ratio). L bounds the LP for every mu, and
/// its minimum is the LP optimum; it is sought by projected subgradient steps (Polyak, towards
/// `target`, e.g. the incumbent's value), and the best multipliers are re-evaluated in integers
/// (mu truncated to fixed point, which keeps it a valid multiplier; the knapsack dual in long
/// double with its worst-case round-off added). Stops after `max_iterations`, at `time_limit`
/// seconds, once the bound is <= target (nothing better than the target exists) or when the steps
/// stall. Deterministic up to the clock.
CoverageLpBound BoundCoverageLp(const CoverageLp& lp,
                                uint64_t target,
                                int max_iterations,
                                double time_limit);

/// Lowers *upper_bound (cells of maximum coverage or k-coverage, with or without a budget) to the
/// bound of `lp` when that is smaller (never below `cells`, what the answer held scores), in 90 %
/// of what is left of `time_limit` seconds since `start` when that allows enough steps
/// (LpBoundSteps); nothing when `cells` already meets it.
void TightenByLpBound(const CoverageLp& lp,
                      uint64_t cells,
                      std::chrono::steady_clock::time_point start,
                      double time_limit,
                      double* upper_bound);

/// Subgradient steps that fit in `seconds` on `matrix` (by its nonzeros), within the limits the
/// bounds use; 0 when too few would fit to be worth it.
int LpBoundSteps(const CoverageMatrix& matrix, double seconds);

/// Lower bound on the sensors reaching `goal_cells`, given that `lower` - 1 sensors are known too
/// few and `upper` enough: the least t such that the LP bound of maximum coverage with t sensors
/// reaches the goal, by bisection (maximum coverage grows with t, so one t proven too few proves
/// every smaller one). Within a quarter of `time_limit` seconds (the rest is for settling the t
/// above it); returns >= lower and <= upper.
size_t SetCoverLpLowerBound(const CoverageMatrix& matrix,
                            uint64_t goal_cells,
                            size_t lower,
                            size_t upper,
                            double time_limit);

/// A proven upper bound on the aggregate `over` (a fraction) of any n sensors over the states of
/// the stacked `matrix`: the least CoverageLp bound, over G = 2^40, of the weights
/// ceil(G a_s w_e / |R_s|) for the state multipliers a tried (mean: a = 1/S; sum: a_s = |R_s| /
/// sum |R|; min: a on the simplex, from uniform by exponentiated-gradient steps), within
/// `seconds`; +inf when no steps fit.
/// `start` (n sensors) is the Polyak target.
double StatesLagrangianBound(const CoverageMatrix& matrix,
                             OverStates over,
                             size_t n,
                             const std::vector<uint32_t>& start,
                             double seconds);

/// A proven lower bound on the cost (`costs`; empty: the count) of any set that holds `fixed`
/// and whose aggregate over states reaches `goal`: coverage is subadditive, so the others must
/// together bring, per state (min) or in sum (mean, sum), what the kept sensors lack; a fractional
/// knapsack over each candidate's whole row is the cheapest way to bring it.
double RowSumGoalBound(const StatesScorer& scorer, std::span<const double> costs, double goal,
                       std::span<const uint32_t> fixed);

}  // namespace vantage::detail
