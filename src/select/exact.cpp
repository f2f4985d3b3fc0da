// The exact solver (SYSTEM.md, Select: `exact`): one driver over the selection model
// (model.hpp). Every objective runs the same steps; the model's kind supplies what differs:
//
//   1. the cheap bound: the greedy/submodular bounds (maximum coverage, k-coverage, budget), a
//      bound the caller knows (the unconstrained one, under rules and kept sensors), the row-sum
//      knapsack (a goal over states); the start meeting it is the answer;
//   2. what settles without search: one sensor (the best single one), small k-coverage
//      (enumeration);
//   3. a bound before CBC: the plain-coverage optimum (min points), the states' Lagrangian;
//   4. the model as one MILP in CBC's child process (milp.hpp), its answer checked in integers,
//      against the capacity, the rules and the kept sensors, and padded where it may be;
//   5. one reconciliation of the answer held and the bounds (whole cells, fractions, costs);
//   6. a bound after CBC where it did not prove: branch and bound on the Lagrangian (maximum
//      coverage), the LP bound (k-coverage, budget), the Lagrangian (rules, n sensors), the
//      states' Lagrangian (when CBC gave no bound).
//
// A goal of cells on the plain matrix (no rule, no kept sensor) is the one model that takes its own
// search (SolvePlainGoal): the fewest sensors (SolveSetCover) settle t cheaply where they can,
// then orbital branching and the model as a goal (the MILP steps), then t by t as maximum
// coverage; with a threshold or costs, orbital branching and the goal's MILP.
#include <fmt/format.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <limits>
#include <optional>
#include <string>

#include "select/cbc_answer.hpp"
#include "select/constrained.hpp"
#include "select/methods.hpp"
#include "select/milp.hpp"
#include "select/model.hpp"
#include "select/objective_bounds.hpp"
#include "select/scorer.hpp"
#include "vantage/error.hpp"
#include "vantage/interrupt.hpp"

namespace vantage::detail {
namespace {

using Clock = std::chrono::steady_clock;

// k-coverage has a weak LP relaxation (k y_e <= sum x_i lets every y_e be 1/k-covered by
// fractions of sensors), so CBC branches long even on tiny instances; up to this many n-subsets
// of the candidates that see anything, exhaustive search is faster and equally exact.
constexpr double kMaxEnumeratedSubsets = 300000;
// Maximum coverage: models up to this many row nonzeros go to CBC first (it proves the small
// shared worlds in a few seconds); larger ones, and whatever CBC leaves unproved, go to
// BranchAndBound, which gets this share of the time limit (the rest absorbs its last node and
// the caller's scoring).
constexpr size_t kCbcFirstNonzeros = 100000;
constexpr double kBranchAndBoundTimeShare = 0.9;
// Below this many seconds left the root bound cannot improve on the cheap one: not started.
constexpr double kMinBranchAndBoundSeconds = 0.02;
// Min-points: the share of the time limit for the plain-coverage bound over the cells that can
// reach the points (a relaxation: a cell with enough points is seen); CBC gets the rest.
constexpr double kRelaxedBoundShare = 0.25;
// Set cover: the share of the time left that the goal MILP gets before the search t by t.
constexpr double kGoalMilpTimeShare = 0.5;
// Rules with n sensors: the Lagrangian steps of the bound when CBC cannot finish.
constexpr int kLagrangianSteps = 300;
// States: the share of the time limit for the Lagrangian bound tried before CBC; an answer
// within kProofTolerance (a fraction of R) of the bound is proven.
constexpr double kFirstBoundShare = 0.1;
constexpr double kProofTolerance = 1e-9;

// What differs between objectives: the model's kind.
enum class Kind {
  kCoverage,     // cells, n sensors, k = 1, no rules or kept sensors
  kThreshold,    // cells, n sensors, k >= 2 or point counts
  kBudget,       // cells within a budget
  kRules,        // cells under rules or with kept sensors (n or a budget)
  kStates,       // an aggregate over states, n sensors, k = 1, no rules or kept sensors
  kStatesRules,  // over states with rules, kept sensors, a budget or a threshold
  kGoal,         // the least cost reaching cells
  kStatesGoal,   // the least cost reaching an aggregate over states
};

Kind KindOf(const SelectionModel& model) {
  const bool cells = model.over == nullptr;
  if (model.goal) return cells ? Kind::kGoal : Kind::kStatesGoal;
  const bool plain = model.rules == nullptr && model.fixed.empty();
  if (!cells) {
    return plain && model.costs.empty() && model.threshold == 1 ? Kind::kStates
                                                                : Kind::kStatesRules;
  }
  if (!plain) return Kind::kRules;
  if (!model.costs.empty()) return Kind::kBudget;
  return model.threshold == 1 ? Kind::kCoverage : Kind::kThreshold;
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

// The model's objective: how a set scores, which of two is better, and what CBC's answer must
// satisfy to be used.
class Objective {
 public:
  explicit Objective(const SelectionModel& model)
      : model_(model), matrix_(*model.matrix), kind_(KindOf(model)) {
    if (model.over) states_.emplace(matrix_, model.over->value, model.threshold);
    most_ = MostSensors();
  }

  Kind kind() const { return kind_; }
  bool is_goal() const { return model_.goal.has_value(); }
  bool is_states() const { return states_.has_value(); }
  const StatesScorer& states() const { return *states_; }
  /// The most sensors an answer holds: n, or with a budget the kept ones and the cheapest others
  /// that fit beside them (what a cardinality bound may assume).
  size_t most() const { return most_; }

  /// Maximise: cells or the aggregate (a fraction); goal: the cost (the count with unit costs).
  double Value(std::span<const uint32_t> set) const {
    if (is_goal()) return Cost(set);
    if (is_states()) return states_->Fraction(states_->Covered(set));
    if (kind_ == Kind::kCoverage || kind_ == Kind::kBudget)
      return static_cast<double>(matrix_.CoveredWeight(set));
    return static_cast<double>(KCoveredWeight(matrix_, set, model_.threshold));
  }
  double Cost(std::span<const uint32_t> set) const {
    return model_.costs.empty() ? static_cast<double>(set.size()) : TotalCost(model_.costs, set);
  }
  /// Whether `a` is strictly better than `b` (over states: the scorer's Score, its ties broken).
  bool Better(const std::vector<uint32_t>& a, const std::vector<uint32_t>& b) const {
    if (is_goal()) return Cost(a) < Cost(b);
    if (is_states())
      return states_->ScoreOf(states_->Covered(b)) < states_->ScoreOf(states_->Covered(a));
    return Value(a) > Value(b);
  }
  /// Whether `value` (of what is held) meets `bound` (proves it optimal).
  bool Meets(double value, double bound) const {
    if (is_goal()) return value <= bound;
    if (is_states()) return bound - value <= kProofTolerance;
    return value == bound;
  }

  /// The best single candidate (ties: the lower index).
  uint32_t BestSingle() const {
    if (!is_states()) return BestCandidate(CellScorer(matrix_));
    const auto score = [&](uint32_t i) {
      return states_->ScoreOf(states_->Covered(std::vector<uint32_t>{i}));
    };
    uint32_t best = 0;
    StatesScorer::Score best_score = score(0);
    for (uint32_t i = 1; i < matrix_.candidate_count(); ++i) {
      const StatesScorer::Score s = score(i);
      if (best_score < s) {  // strict: ties keep the lower index
        best = i;
        best_score = s;
      }
    }
    return best;
  }

  /// CBC's `chosen` as an answer: within the capacity, holding the kept sensors (first, in their
  /// order, as every method answers), feasible under the rules and reaching the goal, all in
  /// integers (CBC's tolerances are not); padded to n where coverage allows. Nullopt with `why`
  /// (empty: nothing to say) when it is not one.
  std::optional<std::vector<uint32_t>> Usable(std::vector<uint32_t> chosen,
                                              std::string* why) const {
    why->clear();
    if (chosen.empty()) return std::nullopt;
    const size_t n = static_cast<size_t>(model_.capacity);
    switch (kind_) {
      case Kind::kCoverage:
      case Kind::kThreshold:
      case Kind::kStates:
        if (chosen.size() > n) {
          *why = "CBC returned more than n sensors";
          return std::nullopt;
        }
        if (kind_ == Kind::kCoverage) return GreedyComplete(CellScorer(matrix_), chosen, n);
        if (kind_ == Kind::kThreshold) return KGreedyComplete(matrix_, chosen, n, model_.threshold);
        return GreedyComplete(*states_, chosen, n);
      case Kind::kBudget:
        if (TotalCost(model_.costs, chosen) > model_.capacity) {
          *why = "CBC's answer exceeds the budget by round-off; kept the start";
          return std::nullopt;
        }
        return chosen;
      case Kind::kRules:
      case Kind::kStatesRules:
      case Kind::kGoal:
      case Kind::kStatesGoal:
        break;
    }
    const Feasibility* rules = model_.rules;
    const std::span<const uint32_t> fixed = model_.fixed;
    const auto is_fixed = [&](uint32_t c) {
      return std::find(fixed.begin(), fixed.end(), c) != fixed.end();
    };
    const bool has_fixed = std::all_of(fixed.begin(), fixed.end(), [&](uint32_t f) {
      return std::find(chosen.begin(), chosen.end(), f) != chosen.end();
    });
    if ((rules != nullptr && !rules->IsFeasible(chosen)) || !has_fixed) {
      if (!is_goal()) *why = "CBC's answer breaks a constraint by round-off; kept the start";
      return std::nullopt;
    }
    std::erase_if(chosen, is_fixed);
    chosen.insert(chosen.begin(), fixed.begin(), fixed.end());
    if (is_goal()) {
      const bool reaches =
          is_states() ? GoalReached(states_->Fraction(states_->Covered(chosen)), *model_.goal)
                      : KCoveredWeight(matrix_, chosen, model_.threshold) >=
                            static_cast<uint64_t>(*model_.goal);
      if (!reaches) {
        *why = "CBC's answer misses the goal by round-off";
        return std::nullopt;
      }
      return chosen;
    }
    if (!model_.costs.empty()) {
      if (TotalCost(model_.costs, chosen) > model_.capacity) {
        *why = "CBC's answer breaks a constraint by round-off; kept the start";
        return std::nullopt;
      }
      return chosen;
    }
    if (chosen.size() > n) {
      *why = "CBC's answer breaks a constraint by round-off; kept the start";
      return std::nullopt;
    }
    for (uint32_t c = 0; c < matrix_.candidate_count() && chosen.size() < n; ++c)
      if (rules == nullptr ? std::find(chosen.begin(), chosen.end(), c) == chosen.end()
                           : rules->CanAdd(chosen, c))
        chosen.push_back(c);
    return chosen;
  }

 private:
  size_t MostSensors() const {
    if (is_goal()) return matrix_.candidate_count();
    if (model_.costs.empty()) return static_cast<size_t>(model_.capacity);
    std::vector<double> others;
    double left = model_.capacity;
    for (uint32_t c = 0; c < matrix_.candidate_count(); ++c) {
      if (std::find(model_.fixed.begin(), model_.fixed.end(), c) != model_.fixed.end())
        left -= model_.costs[c];
      else
        others.push_back(model_.costs[c]);
    }
    std::sort(others.begin(), others.end());
    size_t n = model_.fixed.size();
    for (const double cost : others) {
      if (cost > left) break;
      left -= cost;
      ++n;
    }
    return n;
  }

  const SelectionModel& model_;
  const CoverageMatrix& matrix_;
  Kind kind_;
  std::optional<StatesScorer> states_;
  size_t most_ = 0;
};

// The model as one MILP, with the kind's bounds (steps 1-6 above): every model but a goal on the
// plain matrix, and that goal's own MILP (SolveGoalMilp).
ExactAnswer SolveModelMilp(const SelectionModel& model,
                           const std::vector<uint32_t>& start,
                           double time_limit,
                           const ExactHints& hints) {
  const Clock::time_point begin = Clock::now();
  const CoverageMatrix& matrix = *model.matrix;
  const Objective objective(model);
  const Kind kind = objective.kind();
  const size_t n = objective.most();
  const int k = model.threshold;
  const size_t m = matrix.candidate_count();
  switch (kind) {
    case Kind::kCoverage:
    case Kind::kThreshold:
    case Kind::kStates:
      VANTAGE_CHECK(k >= 1 && n >= 1 && n <= m && start.size() == n);
      break;
    case Kind::kBudget:
      VANTAGE_CHECK(model.costs.size() == m && !start.empty() &&
                    TotalCost(model.costs, start) <= model.capacity);
      break;
    case Kind::kRules:
    case Kind::kStatesRules:
      VANTAGE_CHECK((model.rules == nullptr || model.rules->IsFeasible(start)) &&
                    (!model.costs.empty() || (n >= 1 && start.size() <= n)));
      break;
    case Kind::kGoal:
      VANTAGE_CHECK(k >= 1 && *model.goal >= 1 && (model.costs.empty() || model.costs.size() == m));
      break;
    case Kind::kStatesGoal:
      break;
  }
  ExactAnswer result;
  result.chosen = start;
  double value = objective.Value(start);
  const auto proven = [&](std::string note) {
    result.bound = value;
    result.proven_optimal = true;
    result.note = std::move(note);
    return result;
  };

  // 1. The cheap bound.
  double bound = std::numeric_limits<double>::infinity();
  std::string meets_note = "start meets the simple bound";
  switch (kind) {
    case Kind::kCoverage:
      bound = static_cast<double>(GreedyUpperBound(matrix, start, n));
      break;
    case Kind::kThreshold:
      bound = static_cast<double>(KUpperBound(matrix, start, n, k));
      break;
    case Kind::kBudget:
      bound = static_cast<double>(BudgetUpperBound(matrix, start, model.costs, model.capacity));
      break;
    case Kind::kRules:  // constraints only remove sets: the unconstrained bound holds
      bound = hints.known_bound.value_or(static_cast<double>(matrix.seen_weight()));
      meets_note = "start meets the unconstrained bound";
      break;
    case Kind::kStates:
    case Kind::kStatesRules:
      break;
    case Kind::kGoal:
      bound = 0;
      meets_note.clear();
      break;
    case Kind::kStatesGoal:
      bound = RowSumGoalBound(objective.states(), model.costs, *model.goal, model.fixed);
      meets_note.clear();
      break;
  }
  if (!objective.is_goal() && !objective.is_states()) bound = std::max(bound, value);
  if (objective.Meets(value, bound)) return proven(meets_note);

  // 2. What settles without search: the best single sensor; small k-coverage by enumeration.
  if (n == 1 && (kind == Kind::kCoverage || kind == Kind::kStates ||
                 (kind == Kind::kStatesRules && model.fixed.empty() && model.costs.empty()))) {
    result.chosen = {objective.BestSingle()};
    value = objective.Value(result.chosen);
    return proven("");
  }
  if (kind == Kind::kThreshold) {
    std::vector<uint32_t> pool;
    for (uint32_t i = 0; i < m; ++i)
      if (!matrix.Row(i).empty()) pool.push_back(i);
    if (pool.size() <= n || (hints.may_enumerate &&
                             std::isfinite(SubsetCount(pool.size(), n, kMaxEnumeratedSubsets)))) {
      std::vector<uint32_t> found =
          pool.size() <= n ? pool : EnumerateKCoverage(matrix, pool, n, k);
      found = KGreedyComplete(matrix, std::move(found), n, k);
      if (objective.Better(found, result.chosen)) result.chosen = std::move(found);
      value = objective.Value(result.chosen);
      return proven("solved by enumeration");
    }
  }

  // 3. A bound before CBC, and CBC's time.
  double cbc_seconds = time_limit;
  if (kind == Kind::kThreshold && matrix.has_counts()) {
    // The matrix holds only the cells that can reach the points, so its plain-coverage optimum
    // bounds the min-points one, and exact proves it fast (the Lagrangian, branch and bound).
    SelectionModel relaxed;
    relaxed.matrix = &matrix;
    relaxed.capacity = static_cast<double>(n);
    const ExactAnswer plain = SolveExactModel(relaxed, GreedyComplete(CellScorer(matrix), {}, n),
                                              kRelaxedBoundShare * time_limit);
    bound = std::max(std::min(bound, plain.bound), value);
    if (objective.Meets(value, bound)) return proven("start meets the plain-coverage bound");
    cbc_seconds = std::max(0.1 * time_limit, time_limit - SecondsSince(begin));
  } else if (objective.is_states() && !objective.is_goal()) {
    // Of plain coverage over states, which bounds point coverage too (a cell with enough points
    // is seen), but rarely tightly: with a threshold, CBC first.
    if (k == 1) {
      bound = StatesLagrangianBound(matrix, objective.states().over(), n, start,
                                    kFirstBoundShare * time_limit);
      if (objective.Meets(value, bound)) return proven("");
    }
    cbc_seconds = time_limit - SecondsSince(begin);
  }

  // 4. The model as one MILP.
  bool cbc_proved = false;
  double cbc_bound = std::numeric_limits<double>::quiet_NaN();
  size_t nonzeros = 0;
  if (kind == Kind::kCoverage)
    for (const std::vector<uint32_t>& row : matrix.rows()) nonzeros += row.size();
  if (kind != Kind::kCoverage || nonzeros <= kCbcFirstNonzeros) {
    SelectionModel milp = model;
    if (kind == Kind::kStatesGoal) milp.goal = *model.goal - 1e-9;  // GoalReached's tolerance
    const MilpAnswer answer = SolveSelectionMilp(milp, result.chosen, cbc_seconds);
    result.note = answer.note;
    std::string why;
    const std::optional<std::vector<uint32_t>> found = objective.Usable(answer.chosen, &why);
    if (found && objective.Better(*found, result.chosen)) result.chosen = *found;
    if (!found && !why.empty()) result.note = why;
    cbc_proved = found && answer.proven_optimal;  // and we hold at least CBC's optimum
    cbc_bound = answer.bound;
  }

  // 5. The answer held and the bounds, reconciled.
  value = objective.Value(result.chosen);
  if (objective.is_goal()) {
    const bool whole = model.costs.empty() || AllWhole(model.costs);
    if (std::isfinite(cbc_bound))
      bound = std::max(bound, whole ? std::ceil(cbc_bound - 1e-6) : cbc_bound - 1e-9);
    if (cbc_proved) bound = value;
    bound = std::max(0.0, std::min(bound, value));
  } else if (objective.is_states()) {
    if (cbc_proved)
      bound = std::min(bound, value);
    else if (std::isfinite(cbc_bound))
      bound = std::min(bound, cbc_bound);
  } else {
    // Whole cells: the optimum is at most CBC's bound rounded down (the tolerance absorbs the
    // solver's round-off). A bound below what we hold cannot be one (CBC stopped early).
    if (std::isfinite(cbc_bound)) {
      const double cells = std::floor(cbc_bound + 1e-6);
      if (cells >= value && cells < bound) bound = cells;
    }
    if (cbc_proved) bound = value;
    bound = std::max(bound, value);
  }

  // 6. The kind's bound after CBC, where it did not prove.
  if (!objective.Meets(value, bound)) {
    switch (kind) {
      case Kind::kCoverage: {  // branch and bound on the Lagrangian bound in the time left
        BranchAndBoundLimits limits;
        limits.seconds = kBranchAndBoundTimeShare * time_limit - SecondsSince(begin);
        if (limits.seconds < kMinBranchAndBoundSeconds) break;
        const BranchAndBoundResult search =
            BranchAndBound(matrix, n, result.chosen, static_cast<uint64_t>(bound), limits);
        if (static_cast<double>(search.cells) > value) result.chosen = search.chosen;
        value = objective.Value(result.chosen);
        bound = std::max(std::min(bound, static_cast<double>(search.upper_bound)), value);
        const std::string lp =
            search.root_lp_bound == 0
                ? std::string()
                : fmt::format("; the LP's {} cells from CLP{} in {:.1f} s, the subgradient's {}",
                              search.root_lp_bound, search.root_lp_optimal ? " (optimal)" : "",
                              search.root_lp_seconds, search.root_subgradient_bound);
        const std::string what = fmt::format(
            "branch and bound: {} nodes, root bound {} cells ({} candidates fixed in, {} "
            "removed{})",
            search.nodes, search.root_bound, search.root_fixed_in, search.root_removed, lp);
        if (value == bound) {
          result.note = what;
        } else {
          result.note = fmt::format("{}{}{}", result.note.empty() ? "" : result.note + "; ", what,
                                    search.timed_out ? " — reached the time limit; raise "
                                                       "--time-limit to prove more"
                                                     : "");
        }
        break;
      }
      case Kind::kThreshold:  // the LP bound's rows count seers, not points
        if (!matrix.has_counts())
          TightenByLpBound(CardinalityLp(matrix, n, k), static_cast<uint64_t>(value), begin,
                           time_limit, &bound);
        break;
      case Kind::kBudget:
        TightenByLpBound(BudgetLp(matrix, model.costs, model.capacity),
                         static_cast<uint64_t>(value), begin, time_limit, &bound);
        break;
      case Kind::kRules:
        if (k == 1 && model.costs.empty()) {  // the unconstrained Lagrangian in the time left
          const double left = time_limit - SecondsSince(begin);
          if (left > 0.05) {
            const LagrangianBound lagrangian = LagrangianUpperBound(
                matrix, n, static_cast<uint64_t>(value), kLagrangianSteps, 0.9 * left);
            bound = std::max(value, std::min(bound, static_cast<double>(lagrangian.upper_bound)));
          }
        }
        break;
      case Kind::kStates:
      case Kind::kStatesRules:
        if (!std::isfinite(cbc_bound)) {  // CBC gave no bound: its time to the Lagrangian
          const double rest = kCbcKillShare * (time_limit - SecondsSince(begin));
          if (rest > 0.01) {
            bound = std::min(bound, StatesLagrangianBound(matrix, objective.states().over(), n,
                                                          result.chosen, rest));
          }
        }
        break;
      case Kind::kGoal:
      case Kind::kStatesGoal:
        break;
    }
  }

  // 7. The answer.
  if (objective.is_states() && !objective.is_goal()) {
    if (!std::isfinite(bound)) {  // no time for anything: every candidate together bounds it
      std::vector<uint32_t> everyone(m);
      for (uint32_t i = 0; i < everyone.size(); ++i) everyone[i] = i;
      bound = objective.Value(everyone);
    }
    bound = std::max(bound, value);
    if (hints.known_bound && *hints.known_bound < bound)  // the unconstrained bound, last
      bound = std::max(*hints.known_bound, value);
  }
  result.bound = bound;
  result.proven_optimal = cbc_proved || objective.Meets(value, bound);
  if (result.proven_optimal) {
    result.bound = value;
    if (objective.is_states() || objective.is_goal()) result.note.clear();
  }
  return result;
}

// A goal of cells with no rule and no kept sensor: the plain matrix's goal.
bool IsPlainGoal(const SelectionModel& model) {
  const bool rules = model.rules != nullptr && model.rules->restricts();
  return model.goal && model.over == nullptr && model.fixed.empty() && !rules;
}

// The plain matrix's goal: the fewest sensors by the set-cover search (SolveSetCover) where a
// cell counts once and every sensor costs one; otherwise (k >= 2, points, costs) the cheapest
// cover of every cell by orbital branching first where the instance is symmetric, then the goal
// MILP unless proven, with the cheap bound where CBC gives none.
ExactAnswer SolvePlainGoal(const SelectionModel& model, const std::vector<uint32_t>& start,
                           double time_limit) {
  const Clock::time_point begin = Clock::now();
  const CoverageMatrix& matrix = *model.matrix;
  const auto goal_cells = static_cast<uint64_t>(*model.goal);
  const int k = model.threshold;
  const bool priced = !model.costs.empty();
  ExactAnswer answer;
  if (k == 1 && !matrix.has_counts() && !priced) {
    SetCoverResult cover = SolveSetCover(matrix, goal_cells, start, time_limit);
    return {std::move(cover.chosen), static_cast<double>(cover.lower_bound), cover.proven_optimal,
            std::move(cover.note)};
  }
  const auto price = [&](const std::vector<uint32_t>& chosen) {
    return priced ? TotalCost(model.costs, chosen) : static_cast<double>(chosen.size());
  };
  answer.chosen = start;
  OrbitalSetCoverResult orbital;
  double milp_seconds = time_limit;
  if (priced && k == 1 && !matrix.has_counts() && goal_cells == matrix.seen_weight()) {
    orbital = OrbitalSetCover(matrix, model.costs, start, 0, kOrbitalTimeShare * time_limit);
    if (price(orbital.chosen) < price(answer.chosen)) answer.chosen = orbital.chosen;
    milp_seconds = time_limit - std::chrono::duration<double>(Clock::now() - begin).count();
  }
  GoalResult milp;
  if (!orbital.proven_optimal)
    milp = SolveGoalMilp(matrix, k, model.costs, goal_cells, answer.chosen, milp_seconds);
  if (!milp.chosen.empty() && price(milp.chosen) < price(answer.chosen)) answer.chosen = milp.chosen;
  answer.note =
      orbital.applied ? orbital.note + (milp.note.empty() ? "" : "; " + milp.note) : milp.note;
  const double held = price(answer.chosen);
  if (priced) {
    answer.bound = std::min(std::max(milp.lower_bound, orbital.lower_bound), held);
    answer.proven_optimal = milp.proven_optimal || orbital.proven_optimal || held <= answer.bound;
  } else {
    const size_t cheap = ThresholdGoalLowerBound(matrix, goal_cells, k);
    const size_t lower = std::max(cheap, static_cast<size_t>(milp.lower_bound));
    answer.bound = static_cast<double>(std::min(lower, answer.chosen.size()));
    answer.proven_optimal = milp.proven_optimal || answer.bound == held;
  }
  if (answer.proven_optimal) answer.bound = held;
  return answer;
}

}  // namespace

ExactAnswer SolveExactModel(const SelectionModel& model,
                            const std::vector<uint32_t>& start,
                            double time_limit,
                            const ExactHints& hints) {
  if (IsPlainGoal(model)) return SolvePlainGoal(model, start, time_limit);
  return SolveModelMilp(model, start, time_limit, hints);
}

ExactResult SolveExact(const CoverageMatrix& matrix,
                       size_t n,
                       const std::vector<uint32_t>& start,
                       double time_limit) {
  SelectionModel model;
  model.matrix = &matrix;
  model.capacity = static_cast<double>(n);
  ExactAnswer answer = SolveExactModel(model, start, time_limit);
  return {std::move(answer.chosen), static_cast<uint64_t>(answer.bound), answer.proven_optimal,
          std::move(answer.note)};
}

GoalResult SolveGoalMilp(const CoverageMatrix& matrix,
                         int k,
                         std::span<const double> costs,
                         uint64_t goal_cells,
                         const std::vector<uint32_t>& start,
                         double time_limit) {
  SelectionModel model;
  model.matrix = &matrix;
  model.threshold = k;
  model.costs = costs;
  model.goal = static_cast<double>(goal_cells);
  ExactAnswer answer = SolveModelMilp(model, start, time_limit, {});
  return {std::move(answer.chosen), answer.bound, answer.proven_optimal, std::move(answer.note)};
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
  std::string searched;  // what OrbitalSetCover did, where it ran
  const auto finish = [&] {
    result.lower_bound = std::min(lower, result.chosen.size());
    result.proven_optimal = result.lower_bound == result.chosen.size();
    if (!searched.empty())  // orbital branching's nodes first
      result.note = result.note.empty() ? searched : searched + "; " + result.note;
    if (result.proven_optimal) result.note.clear();
    return result;
  };
  if (settle_cheaply()) return finish();
  if (goal_cells == matrix.seen_weight() && !matrix.has_counts()) {
    // Every cell: where the instance is symmetric (covering designs), orbital branching.
    const OrbitalSetCoverResult orbital = OrbitalSetCover(
        matrix, {}, result.chosen, static_cast<double>(lower), kOrbitalTimeShare * seconds_left());
    if (orbital.applied) {
      if (orbital.chosen.size() < result.chosen.size()) result.chosen = orbital.chosen;
      lower = std::max(lower, static_cast<size_t>(orbital.lower_bound));
      searched = orbital.note;
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
