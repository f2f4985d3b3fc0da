#pragma once
/// The selection methods on the merged matrix (SYSTEM.md, Select). Each returns candidate indices
/// in the order chosen; coverages are counted in reference cells (element weights). Explicitly
/// instantiated for CellScorer and StatesScorer where they are templates.
#include <algorithm>
#include <chrono>
#include <concepts>
#include <cstdint>
#include <functional>
#include <limits>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "select/coverage_matrix.hpp"
#include "select/scorer.hpp"
#include "vantage/select.hpp"

namespace vantage::detail {

/// The scorers the shared methods below are instantiated for (scorer.hpp): plain selection and
/// selection over states run the same best candidate, RANSAC, greedy and local search, and "cells"
/// in their descriptions means the scorer's Score.
template <class T>
concept MethodScorer = std::same_as<T, CellScorer> || std::same_as<T, StatesScorer>;

/// How `--method all` shares `exact`'s time among its n's: exact runs only on instances of at most
/// kMaxCandidates candidates (so "all" stays interactive). Plain selection runs its n's in
/// Lanes() lanes at once (the threads allowed, at most kMaxLanes; over states and under
/// constraints one lane); each lane takes the smallest n not yet started, its runs together take
/// at most the smaller of the time limit and kSeconds of wall time, and each run gets an equal
/// share of what its lane has left for the runs it still has to expect, ⌈(n's not yet started,
/// its own included) / lanes⌉ (time a quick proof leaves goes to the larger, harder n). One lane
/// is the rule of one n after another: an equal share of what is left for the n's still to run.
/// `--method exact` alone has no size cap and the full time limit. kSeconds is sized by issue 47's
/// default run (bench/default_run.sh: the paper's largest world, N = 10, two lanes): everything
/// but exact takes about 2 s there, so the run stays within its 15 s with a third to spare, and
/// the 9 s bring its N = 8-10 within 0.3 point (6 s left them at 0.5).
class AllExactTime {
 public:
  static constexpr size_t kMaxCandidates = 2000;
  static constexpr double kSeconds = 9.0;
  /// Two lanes: the second core of a 2-core machine, idle while exact proves on one (its passes
  /// go parallel only on matrices far larger than `all`'s); each lane may hold branch and
  /// bound's stored multipliers (up to 256 MB), so no more.
  static constexpr size_t kMaxLanes = 2;
  static size_t Lanes(size_t threads_allowed, size_t runs) {
    return std::max<size_t>(1, std::min({threads_allowed, kMaxLanes, runs}));
  }
  explicit AllExactTime(double time_limit) : seconds_left_(std::min(time_limit, kSeconds)) {}
  AllExactTime(size_t candidates, double time_limit, int last_n)
      : runs_(candidates <= kMaxCandidates),
        seconds_left_(std::min(time_limit, kSeconds)),
        last_n_(last_n) {}
  bool runs() const { return runs_; }
  /// The seconds exact may take for `n` (first_n <= n <= last_n), one lane.
  double Share(int n) const { return Share(static_cast<size_t>(last_n_ - n + 1), 1); }
  /// The seconds of the next run of a lane, `runs_left` runs (this one included) not yet started
  /// in all `lanes`.
  double Share(size_t runs_left, size_t lanes) const {
    const size_t expected = (runs_left + lanes - 1) / std::max<size_t>(lanes, 1);
    return std::max(1e-3, seconds_left_ / static_cast<double>(std::max<size_t>(expected, 1)));
  }
  /// Records what one run took.
  void Spend(double seconds) { seconds_left_ = std::max(0.0, seconds_left_ - seconds); }

 private:
  bool runs_ = true;
  double seconds_left_;
  int last_n_ = 1;
};

/// How `--method all` shares RANSAC's iterations among its n's: the n asked (the world's N) runs
/// the iterations asked (the paper's I); the n's below it share kDrawnSensors drawn sensors
/// equally, n running min(I, floor(kDrawnSensors / ((N - 1) n))) iterations (at least 1), so
/// that together they add a bounded time (about 0.3 s on issue 47's bench world) whatever I is.
/// Counted in iterations, not seconds: the answers depend on the seed only.
struct AllRansacShare {
  static constexpr double kDrawnSensors = 5e5;
  /// The iterations RANSAC runs at `n` of a table up to `last_n` when `iterations` are asked.
  static int Iterations(int iterations, int n, int last_n);
};

/// The candidate whose row scores best alone; ties go to the lower index. Needs >= 1 candidate.
template <MethodScorer Scorer>
uint32_t BestCandidate(const Scorer& scorer);

/// The paper's Algorithm 2: up to `iterations` random n-subsets, iteration i drawn from
/// Rng(seed, Stream::kRansac, i) as SelectSensorsRandomly does; keeps a subset only when it scores
/// strictly better (k-coverage: Covered counts the k-covered cells); stops once the best reaches
/// `stop_coverage` (a Fraction). The first draw is always kept, so the answer has n sensors even
/// when every draw covers nothing.
template <MethodScorer Scorer>
std::vector<uint32_t> RansacChoice(
    const Scorer& scorer, size_t n, int iterations, double stop_coverage, uint64_t seed);

/// What RansacFitted's draws must fit: a budget, or a goal.
struct FittedDraws {
  /// A cell counts once the set puts this many points (seers: k; pixels: min_points) in it.
  int threshold = 1;
  std::span<const double> costs;  ///< per candidate: a budget's, or the price a goal minimises
  std::optional<double> budget;   ///< a budget, or none for a goal
  uint64_t goal_cells = 0;        ///< a goal in cells, or 0 for a budget
  std::span<const uint32_t> start;  ///< kept sensors: in every draw, never dropped
  /// Installation rules (Feasibility::CanAdd / IsFeasible), or none.
  std::function<bool(std::span<const uint32_t>, uint32_t)> may_add;
  std::function<bool(std::span<const uint32_t>)> is_feasible;
};

/// Algorithm 2 for a budget or a goal, where no fixed n is drawn: draw i is a random order of
/// every candidate (RansacDraw's stream i, shuffled to the end), taken in passes from `start`,
/// each candidate added when it adds points the threshold counts, fits the budget and the rules;
/// for a goal until it is reached, then latest first each sensor the goal no longer needs is
/// dropped. Keeps the draw covering the most cells (budget; stops at `stop_coverage`) or reaching
/// the goal at the least price (sum of costs, unit without; ties: the earlier draw). Empty when
/// no draw reached the goal, or (budget) none added anything to an empty start. Deterministic.
std::vector<uint32_t> RansacFitted(const CoverageMatrix& matrix, const FittedDraws& fit,
                                   int iterations, double stop_coverage, uint64_t seed);

/// Sum of `costs` over `chosen`.
double TotalCost(std::span<const double> costs, std::span<const uint32_t> chosen);

/// What a cell needs to count under `options`: min_points when counted in points, else k
/// (KindFor(options).threshold, model.hpp).
int Threshold(const SelectOptions& options);

/// The matrix the methods run on for `options`: with min_points, the one with point counts.
CoverageMatrix MatrixFor(std::span<const Observation> observations, size_t reference_size,
                         const SelectOptions& options);

/// A Selection of `chosen` named `method`, scored under the objective of `options` (coverage or
/// k-coverage, with goal / budget and cost filled in as report.json shows them); seconds 0.
Selection ScoreSelection(const CoverageEvaluator& evaluator, std::vector<uint32_t> chosen,
                         const std::string& method, const SelectOptions& options);

/// Greedy from the start set `chosen` up to n sensors: each step adds the candidate that scores
/// best with the chosen (ties: lower index), lazily where the scorer allows it; once nothing adds
/// anything, the lowest-index unused candidates fill up to n. Needs k() = 1.
template <MethodScorer Scorer>
std::vector<uint32_t> GreedyComplete(const Scorer& scorer, std::vector<uint32_t> chosen, size_t n);

/// Set cover: lazy greedy from nothing, adding the candidate of largest gain (ties: lower index)
/// until the covered cells reach `goal_cells`. Needs 1 <= goal_cells <= seen_weight().
std::vector<uint32_t> GreedyToGoal(const CoverageMatrix& matrix, uint64_t goal_cells);

/// The goal with a threshold k (cells seen k times; with a count matrix, cells holding k
/// points) and optional `costs`: each step adds the candidate completing the most cells per
/// cost (ties: the most points added where missing, per cost; then the lower index) until the
/// k-covered cells reach `goal_cells`; then drops, dearest first, each sensor the goal does not
/// need. k = 1 without costs or counts: GreedyToGoal above. Needs all candidates to reach it.
std::vector<uint32_t> GreedyToGoal(const CoverageMatrix& matrix, uint64_t goal_cells, int k,
                                   std::span<const double> costs);

/// Cheap lower bound on the sensors that bring `goal_cells` cells to k points each: the fewest
/// largest rows whose capped points (weight times min(count, k)) add up to k times the goal.
size_t ThresholdGoalLowerBound(const CoverageMatrix& matrix, uint64_t goal_cells, int k);

/// k-coverage greedy from `chosen` up to n sensors. Plain k-coverage gains are all zero until k
/// sensors overlap, so each step compares gains level by level: first the cells the candidate
/// brings to k seers, then (ties) those it brings to k - 1, ..., then to 1 seer: deepen what is
/// partly seen before widening. Ties: lower index; once nothing adds anything at any level, the
/// lowest-index unused candidates fill up to n. Not lazy (k-coverage is not submodular).
std::vector<uint32_t> KGreedyComplete(const CoverageMatrix& matrix,
                                      std::vector<uint32_t> chosen,
                                      size_t n,
                                      int k);

/// Seconds of wall time since `start` (every method's timing and time limit).
inline double SecondsSince(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

/// Each element's points from the candidates added so far, capped at k: seers for k-coverage,
/// pixel hits with a count matrix (min-points). What the threshold greedies (PointsGreedyComplete
/// and the constrained ones) keep between steps.
class CappedPoints {
 public:
  CappedPoints(const CoverageMatrix& matrix, int k)
      : matrix_(&matrix), k_(static_cast<uint32_t>(k)), points_(matrix.element_count(), 0) {}
  void Add(uint32_t candidate) {
    const std::vector<uint32_t>& row = matrix_->Row(candidate);
    for (size_t j = 0; j < row.size(); ++j)
      points_[row[j]] = std::min(k_, points_[row[j]] + matrix_->Count(candidate, j));
  }
  /// visit(element, more, completes) for each element of `candidate` still short of k: the
  /// points it would add there (up to what is missing), and whether that brings it to k.
  template <typename Visit>
  void ForEachMissing(uint32_t candidate, const Visit& visit) const {
    const std::vector<uint32_t>& row = matrix_->Row(candidate);
    for (size_t j = 0; j < row.size(); ++j) {
      const uint32_t have = points_[row[j]];
      if (have >= k_) continue;
      const uint32_t more = std::min(k_ - have, matrix_->Count(candidate, j));
      visit(row[j], more, have + more >= k_);
    }
  }
  /// (weight of the elements `candidate` completes, weight times the points it adds where they
  /// are missing): the threshold greedies' order of gains.
  std::pair<uint64_t, uint64_t> Gain(uint32_t candidate) const {
    std::pair<uint64_t, uint64_t> gain{0, 0};
    ForEachMissing(candidate, [&](uint32_t element, uint32_t more, bool completes) {
      if (completes) gain.first += matrix_->Weight(element);
      gain.second += uint64_t{more} * matrix_->Weight(element);
    });
    return gain;
  }

 private:
  const CoverageMatrix* matrix_;
  uint32_t k_;
  std::vector<uint32_t> points_;
};

/// Min-points greedy (a matrix with point counts, k = min_points) from `chosen` up to n sensors:
/// each step adds the candidate that completes the most cells (brings their points to k), ties
/// broken by the most points it adds where they are still missing (each cell's share up to k,
/// times its weight), then by the lower index; once nothing adds anything, the lowest-index
/// unused candidates fill up to n. KGreedyComplete runs it for a matrix with counts.
std::vector<uint32_t> PointsGreedyComplete(const CoverageMatrix& matrix,
                                           std::vector<uint32_t> chosen, size_t n, int k);

/// Budgeted maximum coverage (Khuller, Moss, Naor 1999): lazy greedy on gain per cost among the
/// candidates that still fit in the remaining budget (zero cost: infinite ratio; ties: larger
/// gain, then lower index), until none adds anything; then the best single affordable candidate
/// if it covers more (this comparison gives the (1 - 1/e)/2 guarantee). Never above `budget`;
/// at least one sensor. Needs a candidate with cost <= budget.
std::vector<uint32_t> GreedyBudget(const CoverageMatrix& matrix,
                                   std::span<const double> costs,
                                   double budget);

/// Options of LocalSearch beyond the cardinality objective (k-coverage is the scorer's k()).
struct LocalOptions {
  std::span<const double> costs;  ///< with a budget: per-candidate costs, else empty
  double budget = 0;              ///< total cost cap when `costs` is not empty
  /// Also try 2-swaps (two out, two in) once no 1-swap helps: for cells (CellScorer) with k = 1
  /// and without a budget only, and only while the search stays cheap (a cap on pair evaluations
  /// per pass).
  bool two_swap = true;
};

/// Best-improvement swap local search from `chosen`: repeatedly makes the swap (one chosen out,
/// one unused in, in place) that scores best (k-covered cells for k >= 2), until no swap scores
/// better than the current answer; with a budget, swaps must keep the total cost within it, and
/// adding a sensor that fits is a move too. Then, where cheap, the best 2-swap, and back to
/// 1-swaps. Ties go to the earlier position, then to the lower candidate index. Deterministic,
/// never worse than `chosen`.
template <MethodScorer Scorer>
std::vector<uint32_t> LocalSearch(const Scorer& scorer,
                                  std::vector<uint32_t> chosen,
                                  const LocalOptions& options = {});

/// Min-points local search (a matrix with point counts, k = min_points): best-improvement
/// 1-swaps, as LocalSearch makes them, scored by the cells whose points reach k. Ties go to the
/// earlier position, then to the lower index. Deterministic, never worse than `chosen`.
std::vector<uint32_t> PointsLocalSearch(const CoverageMatrix& matrix, std::vector<uint32_t> chosen,
                                        int k);

/// Cheap upper bound on the cells any n sensors can cover (submodularity): the cells of `chosen`
/// plus the n largest gains over them, at most the cells seen by anyone.
uint64_t SimpleUpperBound(const CoverageMatrix& matrix, std::span<const uint32_t> chosen, size_t n);

/// The least SimpleUpperBound over `chosen` and every prefix of the greedy answer for n (the empty
/// one included): usually much tighter than over the final answer alone.
uint64_t GreedyUpperBound(const CoverageMatrix& matrix, std::span<const uint32_t> chosen, size_t n);

/// Cheap upper bound on the cells that any selection within `budget` covers: the cells of a set S
/// plus the fractional knapsack of the gains over S (submodularity), for S = `chosen` and S = {}
/// (the smaller), at most the cells seen by the affordable candidates.
uint64_t BudgetUpperBound(const CoverageMatrix& matrix,
                          std::span<const uint32_t> chosen,
                          std::span<const double> costs,
                          double budget);

/// Cheap upper bound on the k-covered cells of any n sensors: the 1-coverage GreedyUpperBound of
/// n sensors, at most the cells seen by k or more candidates.
uint64_t KUpperBound(const CoverageMatrix& matrix,
                     std::span<const uint32_t> chosen,
                     size_t n,
                     int k);

/// Cheap lower bound on the sensors that reach `goal_cells`: the fewest largest rows whose
/// sizes add up to the goal.
size_t SetCoverLowerBound(const CoverageMatrix& matrix, uint64_t goal_cells);

/// A Lagrangian upper bound on the cells of any n sensors, and the subgradient steps it took.
struct LagrangianBound {
  uint64_t upper_bound = 0;  ///< cells; >= the optimum for every input
  long double value = 0;     ///< L of the multipliers returned, exact (upper_bound = its floor)
  int iterations = 0;        ///< subgradient steps taken
  std::vector<double> lambda;  ///< the multipliers of `value`, one per element
};

/// Maximum coverage in the Lagrangian's terms (lagrangian.cpp): at most `slots` of `rows` (sorted
/// element indices), covering elements of `weights` (an element of weight 0 counts for nothing).
struct LagrangianProblem {
  std::span<const std::vector<uint32_t>> rows;
  std::span<const uint32_t> weights;
  size_t slots = 0;
  /// Optional (empty, or one per row): each row's elements as runs of consecutive indices,
  /// flattened [begin, end) pairs, the same sets as `rows` (RowRuns). Given, SubgradientSteps and
  /// EvaluateExactly sum rows through prefix sums over the elements: cheaper where the runs are
  /// long (EvaluateExactly's integers are the same either way; the steps' doubles round
  /// differently).
  std::span<const std::vector<uint32_t>> runs = {};
};

/// `row` (ascending) as runs of consecutive indices: [begin, end) pairs, appended to `*runs`.
void AppendRuns(std::span<const uint32_t> row, std::vector<uint32_t>* runs);

/// Calls body(begin, end) over [0, count) in ranges, on TBB's threads when the pass touches enough
/// `nonzeros` to pay for it (else once, on this thread). Every index is in exactly one range, so a
/// body whose result for index i depends only on i gives the same results whatever the thread
/// count (the Lagrangian's row sums: each row summed by one thread, in element order).
void ForEachRow(size_t count, size_t nonzeros,
                const std::function<void(size_t begin, size_t end)>& body);

/// Where the multiplier search starts: each element's weight shared among the rows that see it.
std::vector<double> StartMultipliers(const LagrangianProblem& problem);

/// What SubgradientSteps did.
struct SubgradientResult {
  double estimate = std::numeric_limits<double>::infinity();  ///< L of the best, in doubles
  int iterations = 0;
  double scale = 0;  ///< the step scale reached (to continue the search where it stopped)
};

/// Projected subgradient steps on L from `lambda` (Polyak steps towards `incumbent`, scaled by
/// `step_scale`, halved when the bound stalls); leaves the best multipliers met in `lambda`. Stops
/// after `max_steps`, after `seconds`, or once the estimate is below incumbent + 1/2.
SubgradientResult SubgradientSteps(const LagrangianProblem& problem,
                                   uint64_t incumbent,
                                   int max_steps,
                                   double step_scale,
                                   double seconds,
                                   std::vector<double>* lambda);

/// Exact coordinate descent on L from `lambda`, `passes` times over the elements: with mu the
/// slots-th largest row (L = slots mu + sum_i max(0, r_i - mu) + sum_e (w_e - lambda_e) there),
/// each lambda_e in turn moves to the largest minimiser of that function in lambda_e alone
/// (where the second row through e would rise above mu, within [0, w_e]), then mu is
/// recomputed. L never rises (up to round-off: EvaluateExactly decides), and it moves far from
/// where subgradient steps stall (a node of multi_bin_picking, N = 8: two passes lower L by
/// about as much as 150 steps), but it stalls itself, so it follows the steps instead of
/// replacing them.
void CoordinateDescent(const LagrangianProblem& problem, int passes, std::vector<double>* lambda);

/// Step scale of a search from StartMultipliers (warm starts take smaller ones).
inline constexpr double kStartStepScale = 2.0;

/// L(lambda) in exact integers: lambda truncated to multiples of 2^-bits (still a valid
/// multiplier), every value below scaled by 2^bits.
struct ExactLagrangian {
  uint64_t scaled_value = 0;     ///< L; floor(L) cells is an upper bound on the optimum
  int bits = 0;
  std::vector<uint64_t> rows;    ///< r_i of every row
  std::vector<uint32_t> chosen;  ///< the slots largest rows (ties: lower index), sorted
  uint64_t last_chosen = 0;      ///< the smallest chosen r (0 when fewer rows than slots)
  uint64_t next_row = 0;         ///< the largest r not chosen (0 when none)
};

/// L(lambda) exactly (see ExactLagrangian).
ExactLagrangian EvaluateExactly(const LagrangianProblem& problem, std::span<const double> lambda);

/// Rows fixed by the bound: every selection that reaches `threshold` cells contains each of
/// `fixed_in` and none of `removed`.
struct Fixing {
  std::vector<uint32_t> fixed_in;
  std::vector<uint32_t> removed;
};

/// Lagrangian fixing: a row whose forced inclusion (exclusion) brings L below `threshold` is
/// removed (fixed in). A proof from exact integers, whatever the multipliers.
Fixing LagrangianFixing(const LagrangianProblem& problem,
                        const ExactLagrangian& exact,
                        uint64_t threshold);

/// The Lagrangian relaxation of the coverage rows y_e <= sum_{i sees e} x_i (lagrangian.cpp):
/// minimises L(lambda) = (the n largest sum_{e in row i} lambda_e) + sum_e (w_e - lambda_e) over
/// 0 <= lambda <= w by projected subgradient steps (Polyak, towards `incumbent`, the cells of a
/// known answer) and returns L of the best multipliers found, recomputed exactly in integers and
/// rounded down (and at most the n largest rows): a valid bound whatever the steps did, converging
/// to the LP relaxation's optimum.
/// Deterministic up to `max_iterations`; stops early at `time_limit` seconds, when the bound
/// falls below incumbent + 1 (proof of optimality) or when the steps stall.
LagrangianBound LagrangianUpperBound(const CoverageMatrix& matrix,
                                     size_t n,
                                     uint64_t incumbent,
                                     int max_iterations,
                                     double time_limit);

/// Limits of BranchAndBound.
struct BranchAndBoundLimits {
  double seconds = 0;      ///< wall clock for the whole search
  int root_steps = 1000;   ///< subgradient steps at the root (from the start multipliers)
  double root_share = 0.5;  ///< share of `seconds` the root's steps and LP may take
  bool root_lp = true;      ///< CLP's LP relaxation at the root, after the steps (lp_bound.hpp)
  /// Nodes bounded at most (then the search stops as at the time limit): a stopping point that
  /// does not depend on the clock, for tests.
  long max_nodes = std::numeric_limits<long>::max();
};

/// Where BranchAndBound's time went (wall seconds; for bench/bnb_probe, not reported).
struct BranchAndBoundProfile {
  double root_seconds = 0;     ///< the root's multipliers (steps and CLP)
  double rebuild_seconds = 0;  ///< rebuilding nodes from the queue
  double rows_seconds = 0;     ///< building each bound's free rows
  double eval_seconds = 0;     ///< exact evaluations of L
  double offer_seconds = 0;    ///< incumbents offered (greedy completion, local search)
  double fixing_seconds = 0;   ///< Lagrangian fixing
  double descent_seconds = 0;  ///< coordinate descent at nodes
  long evaluations = 0;        ///< bounds evaluated exactly
  bool runs = false;           ///< rows were passed as runs of consecutive elements
};

struct BranchAndBoundResult {
  std::vector<uint32_t> chosen;  ///< n sensors, never covering less than the start
  uint64_t cells = 0;            ///< what `chosen` covers
  uint64_t upper_bound = 0;      ///< cells; >= the optimum
  bool proven_optimal = false;
  bool timed_out = false;        ///< stopped by the time limit (or by max_nodes)
  long nodes = 0;
  uint64_t root_bound = 0;       ///< the Lagrangian bound at the root (before branching)
  size_t root_fixed_in = 0;      ///< candidates Lagrangian fixing settled at the root
  size_t root_removed = 0;
  int root_steps = 0;
  uint64_t root_subgradient_bound = 0;  ///< the root's bound from the subgradient steps alone
  uint64_t root_lp_bound = 0;    ///< the root's bound at CLP's duals (0: CLP not run)
  double root_lp_seconds = 0;    ///< CLP's time at the root
  bool root_lp_optimal = false;  ///< CLP finished the root LP (else stopped at its time)
  bool root_lp_improved = false;  ///< the LP's rounded x gave a better incumbent
  BranchAndBoundProfile profile;
};

/// Maximum coverage with n sensors by branch and bound on the Lagrangian bound with fixing at
/// every node (branch_and_bound.cpp; at the root also CLP's LP relaxation, see `root_lp`), from
/// the incumbent `start` (n sensors) and a known bound `upper_bound` (>= the optimum), within
/// `limits`. Deterministic for a given stopping point;
/// throws Interrupted when asked to stop.
BranchAndBoundResult BranchAndBound(const CoverageMatrix& matrix,
                                    size_t n,
                                    const std::vector<uint32_t>& start,
                                    uint64_t upper_bound,
                                    const BranchAndBoundLimits& limits);

struct ExactResult {
  std::vector<uint32_t> chosen;
  uint64_t upper_bound = 0;  ///< cells; >= the cells chosen covers
  bool proven_optimal = false;
  std::string note;  ///< why the solver was not used or failed; empty when it ran normally
};

/// Maximum coverage with n sensors from `start` (n sensors) within `time_limit` seconds: the
/// selection model (model.hpp) with capacity n, through SolveExactModel, in cells. Matrices
/// of up to 100 k row nonzeros go to CBC first, as a MILP warm-started from `start` and shrunk
/// first: dominated candidates are dropped (with "at most n" sensors that loses nothing; the
/// answer is padded back to n), elements are re-merged over the remaining candidates, and
/// elements that only one candidate sees go into that candidate's objective. Larger matrices,
/// and whatever CBC leaves unproved, go to BranchAndBound in the time left (none when too
/// little is left: then `start` or CBC's answer with the better of GreedyUpperBound and CBC's
/// bound). Never returns fewer cells than `start` covers.
ExactResult SolveExact(const CoverageMatrix& matrix,
                       size_t n,
                       const std::vector<uint32_t>& start,
                       double time_limit);

struct SetCoverResult {
  std::vector<uint32_t> chosen;
  size_t lower_bound = 0;  ///< sensors; <= chosen.size()
  bool proven_optimal = false;
  std::string note;
};

/// What SolveGoalMilp found.
struct GoalResult {
  std::vector<uint32_t> chosen;  ///< reaches the goal: `start`, or CBC's answer when cheaper
  double lower_bound = 0;        ///< proven: no answer reaching the goal costs less
  bool proven_optimal = false;   ///< chosen's cost meets lower_bound (CBC's proof)
  std::string note;              ///< why CBC was not run, or stopped
};

/// The goal as one MILP (the cheapest answer that reaches the goal), the selection model with a
/// goal in cells through SolveExactModel (chosen: the better of `start` and CBC's answer):
///   min sum_i cost_i x_i  s.t.  k y_e <= sum_{i sees e} count_ie x_i,  sum_e w_e y_e >= goal,
/// x binary, y in [0, 1] (binary for k >= 2 or point counts). A goal of everything the
/// candidates can reach becomes covering rows sum_{i sees e} count_ie x_i >= k, without y. With
/// k = 1 dominated candidates are dropped and elements re-merged over the others (RunCbc's
/// reductions). `costs` empty: unit (the fewest sensors). Warm-started from `start` (which must
/// reach the goal), solved in a child within `time_limit` seconds (cbc_answer.hpp's shares); not
/// attempted beyond CbcMaxNonzeros(time_limit). Whole costs: the bound is rounded up.
GoalResult SolveGoalMilp(const CoverageMatrix& matrix, int k, std::span<const double> costs,
                         uint64_t goal_cells, const std::vector<uint32_t>& start,
                         double time_limit);

/// A cover of every cell on a symmetric instance: the share of the time left that
/// OrbitalSetCover gets before the goal MILP (which gets the rest unless it proved).
inline constexpr double kOrbitalTimeShare = 0.9;

/// What OrbitalSetCover found.
struct OrbitalSetCoverResult {
  bool applied = false;  ///< false: too large, costs not whole and positive, or no symmetry
  std::vector<uint32_t> chosen;  ///< sees every cell; `start` unless a cheaper cover was found
  double lower_bound = 0;        ///< proven, whole: every cover costs at least this
  bool proven_optimal = false;
  size_t nodes = 0;
  std::string note;
};

/// The fewest sensors (`costs` empty) or the cheapest (whole, positive costs) that see every cell
/// any candidate sees (no point counts), by branch and bound with orbital branching
/// (set_cover_search.cpp): dominated candidates dropped, each node bounded by its LP relaxation
/// (a certified dual), branching on an orbit of the node's own symmetry group (nauty,
/// symmetry.hpp, candidates coloured by cost). Applied only where that group moves some candidate
/// (covering designs, Steiner triple systems) and the matrix has at most 3,000 candidates and
/// 200 k nonzeros; otherwise returns `start` and `applied` false at once. `start` must see every
/// cell; `lower` is a proven lower bound on the cost. Within `time_limit` seconds; deterministic.
OrbitalSetCoverResult OrbitalSetCover(const CoverageMatrix& matrix,
                                      std::span<const double> costs,
                                      const std::vector<uint32_t>& start,
                                      double lower,
                                      double time_limit);

/// Fewest sensors reaching `goal_cells` (a lower bound on the sensors any answer needs is part of
/// the result): the least t whose maximum coverage reaches the goal. Going up from
/// SetCoverLowerBound and the LP's bound, each t is settled cheaply where it can be
/// (GreedyUpperBound: too few; greedy + LocalSearch: enough); a goal of every seen cell then goes
/// to OrbitalSetCover for 90 % of the time left (where it applies: a symmetric instance); what is
/// left goes to the goal as one MILP (SolveGoalMilp) for half of the time left, then t by t to
/// SolveExact in the rest. Stops
/// at the first t it cannot settle; never returns more sensors than `start` (which reaches it).
SetCoverResult SolveSetCover(const CoverageMatrix& matrix,
                             uint64_t goal_cells,
                             const std::vector<uint32_t>& start,
                             double time_limit);

}  // namespace vantage::detail
