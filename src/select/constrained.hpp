#pragma once
/// Selection under installation constraints (vantage/constraints.hpp, docs/constraints.md):
/// greedy, local search, RANSAC and the MILP of maximum coverage restricted to feasible sets —
/// no conflicting pair chosen, and with a calibration rule a connected overlap graph.
#include <cstdint>
#include <functional>
#include <optional>
#include <span>
#include <vector>

#include "select/coverage_matrix.hpp"
#include "select/methods.hpp"
#include "select/model.hpp"
#include "select/objective_bounds.hpp"
#include "select/scorer.hpp"
#include "vantage/constraints.hpp"
#include "vantage/select.hpp"

namespace vantage::detail {

/// Which sets of candidates the constraints allow.
class Feasibility {
 public:
  Feasibility(std::span<const Observation> observations, const InstallConstraints& constraints);
  size_t candidate_count() const { return conflicts_of_.size(); }
  bool has_calibration() const { return has_calibration_; }
  /// A conflict pair or the calibration rule restricts which sets are allowed.
  bool restricts() const { return !conflicts_.empty() || has_calibration_; }
  /// Whether a and b may not both be chosen.
  bool InConflict(uint32_t a, uint32_t b) const;
  /// Whether a and b are joined in the overlap graph (calibration rule).
  bool Joined(uint32_t a, uint32_t b) const;
  /// Sorted neighbours of `candidate` in the overlap graph (empty without a calibration rule).
  const std::vector<uint32_t>& Neighbours(uint32_t candidate) const {
    return neighbours_[candidate];
  }
  /// The conflict pairs (a < b).
  std::span<const Conflict> conflicts() const { return conflicts_; }
  /// Whether `set` + `candidate` keeps every conflict out and (with a calibration rule, `set`
  /// not empty) joins `candidate` to a member of `set`.
  bool CanAdd(std::span<const uint32_t> set, uint32_t candidate) const;
  /// No conflicting pair in `set`, and its overlap graph connected (with a calibration rule).
  bool IsFeasible(std::span<const uint32_t> set) const;

 private:
  bool IsConnected(std::span<const uint32_t> set) const;
  std::vector<Conflict> conflicts_;
  std::vector<std::vector<uint32_t>> conflicts_of_;
  std::vector<std::vector<uint32_t>> neighbours_;
  bool has_calibration_ = false;
};

/// How large a constrained answer may grow: at most n sensors, or (with `costs`) a total cost
/// within `budget` (n is then the candidate count).
struct Capacity {
  size_t n = 0;
  std::span<const double> costs;  ///< per candidate with a budget, else empty
  double budget = 0;
  bool has_budget() const { return !costs.empty(); }
  /// Whether `set` with `candidate` added (or put at position `replaced`, when < set.size())
  /// stays within the capacity; costs summed in the set's order, as TotalCost sums an answer.
  bool Fits(std::span<const uint32_t> set,
            uint32_t candidate,
            size_t replaced = static_cast<size_t>(-1)) const;
};

/// Greedy under the constraints (any scorer: cells, k-coverage, point counts, states): each step
/// adds the feasible candidate (Feasibility::CanAdd, within `capacity`) that ranks best with the
/// chosen, ties to the lower index. The rank is the scorer's (Rank of the gain) for k = 1;
/// for k >= 2 (k-coverage, min-points) the cells a candidate completes, ties broken by the
/// seers or points it adds where they are still missing (PointsGreedyComplete's rule); with a
/// budget the gain per cost (GreedyBudget's order). Zero gains are taken too, up to n (budget:
/// greedy stops once nothing adds anything); stops early, with fewer sensors, when no candidate
/// can be added, and (set cover) once the covered cells reach `goal_cells` (0: no goal).
/// With `start` (kept sensors, feasible) greedy adds to it.
template <MethodScorer Scorer>
std::vector<uint32_t> ConstrainedGreedy(const Scorer& scorer,
                                        const Feasibility& feasible,
                                        const Capacity& capacity,
                                        uint64_t goal_cells = 0,
                                        std::vector<uint32_t> start = {});

/// Best-improvement local search under the constraints from the feasible `start`: moves are
/// adding a candidate (while it fits) and 1-swaps, each kept only when the set stays feasible,
/// fits and scores strictly better; ties go to the earlier position, then the lower index. The
/// first `frozen` positions (kept sensors) are never swapped out.
template <MethodScorer Scorer>
std::vector<uint32_t> ConstrainedLocal(const Scorer& scorer,
                                       const Feasibility& feasible,
                                       std::vector<uint32_t> start,
                                       const Capacity& capacity,
                                       size_t frozen = 0);

/// Algorithm 2 with the draws of RansacChoice (RansacDraw), infeasible draws rejected (they count
/// as iterations); draws scored by the scorer. With `fixed` (kept sensors), each draw is the
/// kept ones and n - |fixed| of the others (RansacDraw over the others, in index order). Empty
/// when no draw was feasible.
template <MethodScorer Scorer>
std::vector<uint32_t> ConstrainedRansac(const Scorer& scorer,
                                        const Feasibility& feasible,
                                        size_t n,
                                        int iterations,
                                        double stop_coverage,
                                        uint64_t seed,
                                        std::span<const uint32_t> fixed = {});

/// Greedy over states towards a budget or a goal (the cost-aware greedy): each step adds the
/// feasible candidate that fits `capacity` with the largest rise of the aggregate per cost
/// (`costs`; empty: per sensor), the rise compared as the scorer's Score (primary, then secondary)
/// of the cells it completes (the threshold's rule: seers or points), ties to the larger rise, then
/// the more points added where missing, then the lower index; a free candidate with a rise first.
/// Stops when nothing fits or adds anything, or once the aggregate reaches `goal` (GoalReached).
/// Without kept sensors and with a budget, the best affordable single candidate replaces the
/// answer when it scores better (the classic budgeted greedy's guard).
std::vector<uint32_t> StatesCostGreedy(const StatesScorer& scorer,
                                       const Feasibility& feasible,
                                       const Capacity& capacity,
                                       std::span<const double> costs,
                                       std::optional<double> goal,
                                       std::vector<uint32_t> start);

/// Whether an aggregate over states (a fraction) reaches a goal: within 1e-9, as GoalCells rounds.
inline bool GoalReached(double aggregate, double goal) { return aggregate >= goal - 1e-9; }

/// RANSAC fitted to a budget or a goal over states (no n to draw): each iteration takes a random
/// order of all candidates (RansacDraw) and adds, from `start`, each that keeps the set feasible
/// and within `capacity`, until the goal is reached (goal) or the order ends. Budget: the best
/// score wins; goal: the cheapest set (`costs`, empty: the fewest) that reaches it, ties to the
/// better score. Empty when no order reached the goal.
std::vector<uint32_t> StatesRansacFitted(const StatesScorer& scorer,
                                         const Feasibility& feasible,
                                         const Capacity& capacity,
                                         std::span<const double> costs,
                                         std::optional<double> goal,
                                         int iterations,
                                         double stop_coverage,
                                         uint64_t seed,
                                         const std::vector<uint32_t>& start);

/// What one constrained method answered: `upper_bound` (exact only) as a share of R (cells
/// scorer) or an aggregate over states.
struct ConstrainedAnswer {
  std::vector<uint32_t> chosen;
  double seconds = 0;
  std::optional<double> upper_bound;
  bool proven_optimal = false;
  std::function<void()> log;  ///< exact: what it has to say, logged by the caller (in n order)
};

/// The methods for one n (or one budget), each built on the one before (local from greedy's
/// answer, exact warm-started from local's), seconds including the steps
/// each needed. One implementation for every scorer: plain coverage, k-coverage and point counts
/// (CellScorer with k = the threshold, over the matrix MatrixFor gives) with n sensors or a
/// budget, and the states of a scene (StatesScorer). A goal is over_states.cpp's GoalMethods.
template <MethodScorer Scorer>
class ConstrainedMethods {
 public:
  /// `start`: what every answer grows from — the kept sensors (options.fixed) and, when they are
  /// not connected, the chain that joins them (BridgeKept); feasible. Every n given is at least
  /// its size (but for a budget).
  ConstrainedMethods(const Scorer& scorer,
                     const Feasibility& feasible,
                     const SelectOptions& options,
                     double setup_seconds,
                     std::vector<uint32_t> start = {});
  /// Where no rule and no kept sensor restricts the sets (IsFree), each method is the plain one:
  /// for cells RansacChoice (RansacFitted for a budget), the lazy GreedyComplete (KGreedyComplete
  /// with a threshold, GreedyBudget for a budget), LocalSearch with 2-swaps (PointsLocalSearch
  /// with point counts) and one exact solve; over states RansacChoice, GreedyComplete,
  /// LocalSearch's 1-swaps and one exact solve.
  ConstrainedAnswer Ransac(size_t n, int iterations) const;
  ConstrainedAnswer Greedy(size_t n);
  /// After Greedy(n). The unconstrained local search's answer too, when it is feasible and scores
  /// better (constraints that do not bind then change nothing).
  ConstrainedAnswer Local();
  /// After Local().
  ConstrainedAnswer Exact(double time_limit) const;
  /// No rule and no kept sensor (over states also no budget and k = 1): the plain methods apply,
  /// and exact touches no shared state (`all`'s lanes may run it at once).
  bool IsFree() const;

 private:
  Capacity CapacityFor(size_t n) const;
  double Share(uint64_t cells) const;
  /// A budget (the model's costs and capacity) instead of n sensors.
  bool HasBudget() const { return !model_.costs.empty(); }
  bool HasRules() const { return feasible_.restricts(); }
  const Scorer& scorer_;
  const Feasibility& feasible_;
  /// The question every method answers: ModelFor(options), its capacity n set per n (a budget's
  /// is the budget); the methods read its threshold, costs, budget and kept sensors.
  SelectionModel model_;
  uint64_t seed_;                // RANSAC's draws
  double ransac_stop_coverage_;  // RANSAC stops once a draw reaches this share
  double setup_seconds_;
  std::vector<uint32_t> start_;
  size_t n_ = 0;
  std::vector<uint32_t> greedy_;
  std::vector<uint32_t> local_;
  std::vector<uint32_t> free_local_;  // the unconstrained local search's answer for n_
  double greedy_seconds_ = 0;
  double local_seconds_ = 0;
};

/// The kept sensors `fixed` joined into one part of the overlap graph (calibration rule): `fixed`
/// first, then the members of the shortest chains (breadth-first over the overlap graph, fewest
/// sensors, ties to the lower index) that join the part of the first kept sensor to the nearest
/// other part, until one part is left. No chain member conflicts with anything chosen. `fixed`
/// itself when it is connected (or there is no calibration rule); empty when no chain joins two
/// of its parts. A heuristic (joining parts with fewest sensors is a Steiner tree problem): the
/// MILP, which keeps only `fixed` at 1, may join them with fewer.
std::vector<uint32_t> BridgeKept(const Feasibility& feasible, std::span<const uint32_t> fixed);

/// What every answer grows from with kept sensors (options.fixed): BridgeKept's chain. InputError
/// when two kept sensors conflict, no chain joins them, or the chain breaks the budget.
std::vector<uint32_t> KeptStart(const Feasibility& feasible, const SelectOptions& options);

/// Select for maximum coverage (n sensors, k-coverage, point counts, a budget), with or without
/// the constraints and kept sensors (fixed variables of the model, never a residual problem):
/// ConstrainedMethods in RunMethods' order. Not for a goal.
std::vector<Selection> SelectConstrained(std::span<const Observation> observations,
                                         size_t reference_size, const SelectOptions& options);

/// CoverageCurve: greedy and local at every n from first_n (past the kept sensors and their
/// chain) to last_n that `results` lacks.
std::vector<Selection> ConstrainedCurve(std::span<const Observation> observations,
                                        size_t reference_size,
                                        const SelectOptions& options,
                                        const std::vector<Selection>& results,
                                        int first_n,
                                        int last_n);

/// The draw `iteration` of RANSAC (ransac.cpp): n distinct candidates of order->size(); `order`
/// must hold the identity permutation and is restored.
void RansacDraw(uint64_t seed, uint64_t iteration, size_t n, std::vector<uint32_t>* order,
                std::vector<uint32_t>* drawn);

}  // namespace vantage::detail
