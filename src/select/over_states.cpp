// Changing scenes (issue 9): selection over the states of a scene.
//
// Every state s has its own reference set R_s and one observation set per candidate. The
// states' merged matrices are stacked into one CoverageMatrix (an element is a class of cells of
// one state), and Select's own methods run on it with StatesScorer, which scores a set of
// candidates by the aggregate (its aggregation's row: shape and cell weights) of its per-state
// coverages, compared exactly (scorer.hpp). Reported coverages are recomputed from the
// observations by CoverageEvaluator, never taken from this bookkeeping.
#include <fmt/format.h>
#include <fmt/ranges.h>
#include <spdlog/spdlog.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <functional>
#include <memory>
#include <numeric>
#include <optional>

#include "select/constrained.hpp"
#include "select/coverage_matrix.hpp"
#include "select/methods.hpp"
#include "select/model.hpp"
#include "select/objective_bounds.hpp"
#include "select/run_methods.hpp"
#include "select/scorer.hpp"
#include "vantage/error.hpp"
#include "vantage/select_states.hpp"

namespace vantage {
namespace {

using Clock = std::chrono::steady_clock;
using detail::SecondsSince;

}  // namespace

const Aggregation& AggregationOf(OverStates over) {
  for (const Aggregation& row : kAggregations)
    if (row.value == over) return row;
  throw InternalError(fmt::format("no aggregation row for value {}", static_cast<int>(over)));
}

std::vector<OverStates> OverStatesValues() {
  std::vector<OverStates> values;
  for (const Aggregation& row : kAggregations) values.push_back(row.value);
  return values;
}

OverStates ParseOverStates(const std::string& name) {
  std::vector<std::string_view> names;
  for (const Aggregation& row : kAggregations) {
    if (row.name == name) return row.value;
    names.push_back(row.name);
  }
  throw InputError(fmt::format("--over-states '{}' is unknown — use {} or {}", name,
                               fmt::join(names.begin(), names.end() - 1, ", "), names.back()));
}

std::string OverStatesName(OverStates over) { return std::string(AggregationOf(over).name); }

// ----- the scorer ------------------------------------------------------------------------------

namespace detail {
namespace {

using Int = StatesScorer::Int;

// The aggregate, a fraction, of `states` states as `aggregation` counts it, from each state's
// weighted cells weighted_of(s, ω_s) = ω_s c_s and size_of(s) = |R_s|: the weighted sum
// Σ ω_s c_s / Σ ω_s |R_s|, or the least ω_s c_s. In state order, so every reader gets the same
// number.
template <class WeightedOf, class SizeOf>
double AggregateOf(const Aggregation& aggregation, size_t states, const WeightedOf& weighted_of,
                   const SizeOf& size_of) {
  double sum = 0, most = 0, least = 0;
  for (size_t s = 0; s < states; ++s) {
    const size_t size = size_of(s);
    const CellWeight w = aggregation.weight(size);
    const double value = weighted_of(s, w);
    sum += value;
    most += Weighted(static_cast<double>(size), w);
    least = s == 0 ? value : std::min(least, value);
  }
  if (aggregation.shape == AggregateShape::kMinimum) return least;
  return most > 0 ? sum / most : 0.0;
}

Int Gcd(Int a, Int b) {
  while (b != 0) {
    const Int t = a % b;
    a = b;
    b = t;
  }
  return a;
}

}  // namespace

StatesScorer::StatesScorer(const CoverageMatrix& matrix, OverStates over, int threshold)
    : matrix_(&matrix), aggregation_(&AggregationOf(over)), threshold_(threshold) {
  const size_t states = matrix.state_count();
  for (size_t s = 0; s < states; ++s)
    weight_.push_back(aggregation_->weight(matrix.StateReferenceSize(s)));
  // Common denominator L = lcm(q_s) when S · L fits comfortably, else fixed point 2^62 (whole
  // weights, as the sum's: L = 1, always exact).
  constexpr Int kLimit = Int{1} << 96;
  Int lcm = 1;
  for (size_t s = 0; s < states; ++s) {
    const auto q = static_cast<Int>(weight_[s].denominator);
    const Int next = lcm / Gcd(lcm, q) * q;
    if (next > kLimit) {
      lcm = 0;
      break;
    }
    lcm = next;
  }
  exact_ = lcm != 0;
  for (const CellWeight& w : weight_) {
    unit_.push_back(exact_ ? lcm / static_cast<Int>(w.denominator) * static_cast<Int>(w.numerator)
                           : 0);
  }
  state_of_.resize(matrix.element_count());
  for (size_t s = 0; s < states; ++s) {
    std::fill(state_of_.begin() + matrix.StateBegin(s),
              state_of_.begin() + matrix.StateBegin(s + 1), static_cast<uint32_t>(s));
  }
  row_weights_.reserve(matrix.candidate_count());
  for (uint32_t c = 0; c < matrix.candidate_count(); ++c) {
    Tally tally = Zero();
    for (const uint32_t e : matrix.Row(c)) AddElement(e, &tally);
    row_weights_.push_back(std::move(tally));
  }
}

template <bool kInSet>
StateTally StatesScorer::RowTally(uint32_t candidate, const Bitset& set) const {
  Tally tally = Zero();
  for (const uint32_t e : matrix_->Row(candidate)) {
    if (Contains(set, e) == kInSet) AddElement(e, &tally);
  }
  return tally;
}

StateTally StatesScorer::Gain(uint32_t candidate, const Bitset& covered) const {
  return RowTally<false>(candidate, covered);
}

StateTally StatesScorer::WeightIn(uint32_t candidate, const Bitset& set) const {
  return RowTally<true>(candidate, set);
}

StateTally StatesScorer::Covered(std::span<const uint32_t> chosen) const {
  Tally tally = Zero();
  if (threshold_ > 1) {  // the elements the chosen bring to threshold_ points (seers)
    const auto k = static_cast<uint32_t>(threshold_);
    std::vector<uint32_t> count(matrix_->element_count(), 0);
    for (const uint32_t c : chosen) {
      const std::vector<uint32_t>& row = matrix_->Row(c);
      for (size_t j = 0; j < row.size(); ++j) {
        const uint32_t before = count[row[j]];
        count[row[j]] += matrix_->Count(c, j);
        if (before < k && count[row[j]] >= k) AddElement(row[j], &tally);
      }
    }
    return tally;
  }
  Bitset covered = matrix_->EmptySet();
  for (const uint32_t c : chosen) {
    tally += Gain(c, covered);
    matrix_->AddTo(c, &covered);
  }
  return tally;
}

Int StatesScorer::Units(size_t state, uint64_t cells) const {
  if (exact_) return static_cast<Int>(cells) * unit_[state];
  const CellWeight& w = weight_[state];
  return ((static_cast<Int>(cells) * static_cast<Int>(w.numerator)) << 62) /
         static_cast<Int>(w.denominator);
}

StatesScorer::Score StatesScorer::ScoreOf(const Tally& cells) const {
  Int sum = 0, least = 0;
  for (size_t s = 0; s < cells.size(); ++s) {
    const Int u = Units(s, cells[s]);
    sum += u;
    least = s == 0 ? u : std::min(least, u);
  }
  if (aggregation_->shape == AggregateShape::kWeightedSum) return Score{sum, 0};
  return Score{least, sum};
}

double StatesScorer::Fraction(const Tally& cells) const {
  return AggregateOf(
      *aggregation_, cells.size(),
      [&](size_t s, const CellWeight& w) { return Weighted(static_cast<double>(cells[s]), w); },
      [&](size_t s) { return matrix_->StateReferenceSize(s); });
}

}  // namespace detail

// ----- selection over states -------------------------------------------------------------------

namespace {

// The states' `values` (each a share v_s of its R_s) aggregated as `over` asks: ω_s c_s is
// v_s · ω_s |R_s| (mean, min: v_s itself), or with whole weights (sum) the share's whole cells
// round(v_s |R_s|) · ω_s, as the scorer counts.
double Aggregate(const std::vector<double>& values, OverStates over,
                 std::span<const StateObservations> states) {
  const auto size_of = [&](size_t s) { return states[s].reference_size; };
  return detail::AggregateOf(
      AggregationOf(over), values.size(),
      [&](size_t s, const CellWeight& w) {
        const auto size = static_cast<double>(size_of(s));
        if (w.numerator % w.denominator == 0) return Weighted(std::round(values[s] * size), w);
        return values[s] * Weighted(size, w);
      },
      size_of);
}

StateSelection Scored(std::span<const StateObservations> states,
                      OverStates over,
                      Method method,
                      std::vector<uint32_t> chosen,
                      double seconds,
                      const detail::SelectionKind& kind = {}) {
  const std::optional<uint32_t> min_points = kind.min_points;
  const int k = kind.k;
  StateSelection result;
  for (const StateObservations& state : states) {
    const CoverageEvaluator evaluator(state.observations, state.reference_size);
    if (min_points) {
      // As Select scores min-points: the cells with enough points, plus the keys outside R seen.
      const double coverage = evaluator.PointCoverage(chosen, *min_points);
      result.state_coverage.push_back(coverage);
      result.state_paper_coverage.push_back(coverage + evaluator.PaperCoverage(chosen) -
                                            evaluator.Coverage(chosen));
      continue;
    }
    result.state_coverage.push_back(evaluator.Coverage(chosen, k));
    result.state_paper_coverage.push_back(evaluator.PaperCoverage(chosen, k));
  }
  Selection& s = result.selection;
  s.method = MethodName(method);
  s.n = static_cast<int>(chosen.size());
  s.chosen = std::move(chosen);
  s.coverage = Aggregate(result.state_coverage, over, states);
  s.paper_coverage = Aggregate(result.state_paper_coverage, over, states);
  s.seconds = seconds;
  s.objective = ObjectiveName(kind.objective);
  s.min_points = min_points;
  s.k = k;
  return result;
}

// An answer scored as `options` count it (their kind: k seers or the points, the objective's
// name), with a goal's or a budget's fields (goal, budget, cost).
StateSelection ScoredFor(const SelectOptions& options, std::span<const StateObservations> states,
                         OverStates over, Method method, std::vector<uint32_t> chosen,
                         double seconds) {
  const detail::SelectionKind kind = detail::KindFor(options);
  StateSelection result = Scored(states, over, method, std::move(chosen), seconds, kind);
  Selection& s = result.selection;
  if (kind.limit == detail::SelectionKind::Limit::kGoal) {
    s.goal = options.goal;
    if (options.minimize_cost) s.cost = detail::TotalCost(options.costs, s.chosen);
  } else if (kind.limit == detail::SelectionKind::Limit::kBudget) {
    s.budget = options.budget;
    s.cost = detail::TotalCost(options.costs, s.chosen);
  }
  return result;
}

// The selection model over the states `scorer` scores (its threshold and aggregate), with the
// rules and kept sensors, for `options` (a goal, or `n` sensors).
detail::SelectionModel StatesModel(const detail::StatesScorer& scorer,
                                   const detail::Feasibility* rules,
                                   const SelectOptions& options, size_t n) {
  return detail::ModelFor(options, scorer.matrix(), &scorer.aggregation(), n, rules);
}

// The methods for a goal, on the goal's model (GoalModel): the least cost (with unit costs the
// fewest sensors) whose value reaches the goal, under the rules and with the kept sensors (a
// scene without states is one state). Greedy to the goal, RANSAC's random orders taken until it,
// and exact from greedy's answer, in RunMethods' order; every method reads the model (threshold,
// costs, goal), the options only say how each runs and how answers are scored. On the plain
// matrix (one state, no rule, no kept sensor: the model in whole cells) greedy and RANSAC are the
// plain matrix's own (GreedyToGoal, RansacFitted); elsewhere StatesCostGreedy and
// StatesRansacFitted. Exact is SolveExactModel on the model either way (on the plain matrix it
// runs the set-cover search).
class GoalMethods final : public detail::MethodSteps<StateSelection> {
 public:
  GoalMethods(std::span<const StateObservations> states, OverStates over,
              const SelectOptions& options, const detail::StatesScorer& scorer,
              const detail::Feasibility& feasible, detail::SelectionModel model,
              std::vector<uint32_t> kept_start, std::vector<uint32_t> greedy,
              double greedy_seconds)
      : states_(states),
        over_(over),
        options_(options),
        scorer_(scorer),
        feasible_(feasible),
        model_(std::move(model)),
        kept_start_(std::move(kept_start)),
        greedy_(std::move(greedy)),
        greedy_seconds_(greedy_seconds) {}

  /// The goal's model: in whole cells on the plain matrix (one state, no rule and no kept
  /// sensor), else the aggregate over the states with the rules and the kept sensors.
  static detail::SelectionModel GoalModel(std::span<const StateObservations> states,
                                          const SelectOptions& options,
                                          const detail::StatesScorer& scorer,
                                          const detail::Feasibility& feasible) {
    const size_t candidates = scorer.matrix().candidate_count();
    const bool plain =
        states.size() == 1 && options.constraints.empty() && options.fixed.empty();
    return plain ? detail::ModelFor(options, scorer.matrix(), nullptr, candidates, nullptr)
                 : StatesModel(scorer, &feasible, options, candidates);
  }
  static bool IsPlain(const detail::SelectionModel& model) {
    return model.over == nullptr;
  }
  /// Greedy to the model's goal, from the kept sensors (GoalOverStates checks what it reached).
  static std::vector<uint32_t> GreedyToTheGoal(const detail::SelectionModel& model,
                                               const detail::StatesScorer& scorer,
                                               const detail::Feasibility& feasible,
                                               const std::vector<uint32_t>& kept_start) {
    if (IsPlain(model))
      return detail::GreedyToGoal(*model.matrix, static_cast<uint64_t>(*model.goal),
                                  model.threshold, model.costs);
    return detail::StatesCostGreedy(scorer, feasible, Everyone(model), model.costs, *model.goal,
                                    kept_start);
  }

  StateSelection Best() override { VANTAGE_CHECK(false); return {}; }  // Validate refuses it
  std::optional<StateSelection> TableHead() override { return std::nullopt; }
  size_t FirstN() const override { return 1; }

  /// No n to draw: each draw is a random order taken until the goal is reached.
  StateSelection Ransac(size_t, int iterations) override {
    const Clock::time_point t = Clock::now();
    std::vector<uint32_t> drawn;
    if (IsPlain(model_)) {
      detail::FittedDraws fit;
      fit.threshold = model_.threshold;
      fit.costs = model_.costs;
      fit.goal_cells = static_cast<uint64_t>(*model_.goal);
      drawn = detail::RansacFitted(*model_.matrix, fit, iterations,
                                   options_.ransac_stop_coverage, options_.seed);
    } else {
      drawn = detail::StatesRansacFitted(scorer_, feasible_, Everyone(model_), model_.costs,
                                         *model_.goal, iterations, options_.ransac_stop_coverage,
                                         options_.seed, kept_start_);
      if (drawn.empty()) drawn = greedy_;  // no order reached it under the rules
    }
    return Score(Method::kRansac, std::move(drawn), greedy_seconds_ + SecondsSince(t));
  }
  StateSelection Greedy(size_t) override { return Score(Method::kGreedy, greedy_, greedy_seconds_); }
  StateSelection Local() override { VANTAGE_CHECK(false); return {}; }  // Validate refuses it

  /// Exact on the model from greedy's answer, after Greedy: runs at once, never in lanes.
  std::function<detail::ExactDone<StateSelection>(double)> Exact() override {
    return [this](double seconds) {
      const Clock::time_point t = Clock::now();
      const detail::ExactAnswer exact = detail::SolveExactModel(model_, greedy_, seconds);
      if (!exact.proven_optimal && !exact.note.empty()) {
        spdlog::warn(
            "exact{}, goal {:g}: {}; reporting the best answer found and a bound",
            states_.size() == 1 ? "" : " over states", *options_.goal, exact.note);
      }
      StateSelection s = Score(Method::kExact, exact.chosen, greedy_seconds_ + SecondsSince(t));
      // The bound is on the least cost, or with unit costs on the fewest sensors.
      if (model_.costs.empty()) {
        s.selection.n_lower_bound = static_cast<int>(std::llround(exact.bound));
      } else {
        s.selection.cost_lower_bound = exact.bound;
      }
      s.selection.proven_optimal = exact.proven_optimal;
      return detail::ExactDone<StateSelection>{std::move(s), {}};
    };
  }

 private:
  // A goal has no n: every candidate may join.
  static detail::Capacity Everyone(const detail::SelectionModel& model) {
    detail::Capacity everyone;
    everyone.n = model.matrix->candidate_count();
    return everyone;
  }

  StateSelection Score(Method method, std::vector<uint32_t> chosen, double seconds) const {
    VANTAGE_CHECK(feasible_.IsFeasible(chosen));
    return ScoredFor(options_, states_, over_, method, std::move(chosen), seconds);
  }

  std::span<const StateObservations> states_;
  OverStates over_;
  const SelectOptions& options_;
  const detail::StatesScorer& scorer_;
  const detail::Feasibility& feasible_;
  const detail::SelectionModel model_;
  std::vector<uint32_t> kept_start_;
  std::vector<uint32_t> greedy_;  // greedy's answer, where exact starts
  double greedy_seconds_;
};

// A goal: checks that it can be reached (by all candidates, then under the rules), the kept
// sensors alone where they reach it, greedy's answer, then GoalMethods in RunMethods' order.
std::vector<StateSelection> GoalOverStates(std::span<const StateObservations> states,
                                           OverStates over,
                                           const SelectOptions& options,
                                           const detail::StatesScorer& scorer,
                                           const detail::Feasibility& feasible,
                                           const std::vector<uint32_t>& kept_start,
                                           Clock::time_point start) {
  const double goal = *options.goal;
  const detail::CoverageMatrix& matrix = scorer.matrix();
  const auto unreachable = [&](const std::string& reach, const std::string& relax) {
    // One state is a scene without states (Select's combinations on the one model).
    const std::string what =
        states.size() == 1
            ? fmt::format("goal {:g} {}", goal, reach)
            : fmt::format("goal {:g} over the {} ({}) {}", goal, options.groups,
                          OverStatesName(over), reach);
    return InputError(options.goal_source == "--goal"
                          ? AtPlace("--goal", 0, fmt::format("{} — lower --goal{}", what, relax))
                          : fmt::format("{}: {} — lower the scene's goal, or give a lower "
                                        "--goal{}",
                                        options.goal_source, what, relax));
  };
  std::vector<uint32_t> everyone(matrix.candidate_count());
  std::iota(everyone.begin(), everyone.end(), 0U);
  const double reach = scorer.Fraction(scorer.Covered(everyone));
  // One state counts the goal in whole cells (GoalCells), as its methods do.
  const int threshold = detail::Threshold(options);
  const bool reachable =
      states.size() == 1
          ? detail::GoalCells(goal, matrix.reference_size()) <=
                (threshold == 1 && !matrix.has_counts()
                     ? matrix.seen_weight()
                     : detail::KCoveredWeight(matrix, everyone, threshold))
          : detail::GoalReached(reach, goal);
  if (!reachable) {
    const std::string counted =
        options.min_points ? fmt::format(" (cells holding {} points)", *options.min_points)
        : options.k >= 2   ? fmt::format(" (cells seen {} times)", options.k)
                           : std::string();
    throw unreachable(fmt::format("is above the {:.4f}{} that all {} candidates reach together",
                                  reach, counted, matrix.candidate_count()),
                      "");
  }
  if (kept_start.size() == options.fixed.size() && !options.fixed.empty() &&
      detail::GoalReached(scorer.Fraction(scorer.Covered(options.fixed)), goal)) {
    StateSelection s =
        ScoredFor(options, states, over, Method::kBest, options.fixed, SecondsSince(start));
    s.selection.method = "kept";
    return {s};
  }
  const detail::SelectionModel model = GoalMethods::GoalModel(states, options, scorer, feasible);
  std::vector<uint32_t> greedy = GoalMethods::GreedyToTheGoal(model, scorer, feasible, kept_start);
  // The plain matrix's greedy reaches any goal all candidates reach; under the rules, where greedy
  // cannot, the most any feasible set reaches decides.
  if (!GoalMethods::IsPlain(model) &&
      !detail::GoalReached(scorer.Fraction(scorer.Covered(greedy)), goal)) {
    detail::SelectionModel most_model = model;
    most_model.goal.reset();  // the most any set reaches, at no price
    most_model.costs = {};
    const detail::ExactAnswer most = detail::SolveExactModel(most_model, greedy, options.time_limit);
    const double best = scorer.Fraction(scorer.Covered(most.chosen));
    if (!detail::GoalReached(best, goal)) {
      throw unreachable(
          most.proven_optimal || most.bound < goal - 1e-9
              ? fmt::format("cannot be reached: the installation constraints allow at most {:.4f}",
                            std::min(most.bound, reach))
              : fmt::format("cannot be reached: no set of sensors that satisfies the "
                            "installation constraints was found to reach it (the best reaches "
                            "{:.4f})",
                            best),
          " or relax the constraints");
    }
    greedy = most.chosen;
  }
  GoalMethods methods(states, over, options, scorer, feasible, model, kept_start,
                      std::move(greedy), SecondsSince(start));
  return detail::RunMethods<StateSelection>(methods, options, matrix.candidate_count(), start);
}

// The states' stacked matrix for the objective of `options`: with min_points, with the counts
// (which every observation must then carry).
detail::CoverageMatrix StatesMatrix(std::span<const StateObservations> states,
                                    const SelectOptions& options) {
  std::vector<detail::StateBlock> blocks;
  for (const StateObservations& state : states)
    blocks.push_back({state.observations, state.reference_size});
  if (!options.min_points) return detail::CoverageMatrix(blocks);
  for (const StateObservations& state : states) {
    for (const Observation& o : state.observations) {
      if (!o.has_point_counts())
        throw FieldError({"min_points"},
                         fmt::format("min_points needs the pixel counts per cell, which state "
                                     "'{}' does not carry",
                                     state.name));
    }
  }
  return detail::CoverageMatrix(blocks, *options.min_points);
}

void Validate(std::span<const StateObservations> states, const SelectOptions& options) {
  if (states.empty()) throw InputError("--over-states: there are no states to select over");
  const size_t candidates = states.front().observations.size();
  for (const StateObservations& state : states) {
    if (state.observations.size() != candidates) {
      throw InputError(fmt::format("--over-states: state '{}' has {} observations but state '{}' "
                                   "has {} — every state needs one per candidate",
                                   state.name, state.observations.size(),
                                   states.front().name, candidates));
    }
    if (state.reference_size == 0) {
      throw InputError(fmt::format("--over-states: state '{}' has an empty reference set (no "
                                   "target surface)",
                                   state.name));
    }
  }
  options.Validate(candidates);
  for (const StateObservations& state : states) {
    for (size_t c = 0; c < candidates; ++c) {
      for (const uint32_t index : state.observations[c].reference_indices) {
        if (index >= state.reference_size) {
          throw InputError(
              fmt::format("--over-states: state '{}': candidate {} sees reference "
                          "cell {} but the state's R has {} cells",
                          state.name, c, index, state.reference_size));
        }
      }
    }
  }
}

// The methods on the states' model (n sensors or a budget), scored over the states.
class StatesRun final : public detail::MethodSteps<StateSelection> {
 public:
  StatesRun(std::span<const StateObservations> states, OverStates over,
            const SelectOptions& options, const detail::StatesScorer& scorer,
            const detail::Feasibility& feasible, double setup_seconds,
            std::vector<uint32_t> kept_start)
      : states_(states),
        over_(over),
        options_(options),
        scorer_(scorer),
        feasible_(feasible),
        setup_seconds_(setup_seconds),
        kept_start_(kept_start),
        methods_(scorer, feasible, options, setup_seconds, std::move(kept_start)) {}

  /// The best single candidate (optimal for n = 1), or with kept sensors the best single
  /// addition: greedy's first step from them (with a chain to join them, not one addition).
  StateSelection Best() override {
    const size_t kept = options_.fixed.size();
    if (kept_start_.size() > kept)
      throw InputError(fmt::format("--method best adds one sensor to the {} kept ones, and they "
                                   "need a chain of {} to join them — use another method",
                                   kept, kept_start_.size() - kept));
    StateSelection s;
    if (kept == 0) {
      const Clock::time_point t = Clock::now();
      s = Scored(states_, over_, Method::kBest, {detail::BestCandidate(scorer_)},
                 setup_seconds_ + SecondsSince(t));
    } else {
      s = Score(Method::kBest, methods_.Greedy(kept + 1));
    }
    s.selection.upper_bound = s.selection.coverage;
    s.selection.proven_optimal = true;
    return s;
  }
  /// As Select: min-points and k-coverage have no best.
  std::optional<StateSelection> TableHead() override {
    if (scorer_.k() != 1 || options_.budget || kept_start_.size() > options_.fixed.size())
      return std::nullopt;
    return Best();
  }
  /// k-coverage from n = k; below the kept sensors and their chain no answer exists.
  size_t FirstN() const override {
    return std::max({static_cast<size_t>(options_.k), options_.fixed.size() + 1,
                     kept_start_.size()});
  }
  StateSelection Ransac(size_t n, int iterations) override {
    return Score(Method::kRansac, methods_.Ransac(Room(n), iterations));
  }
  StateSelection Greedy(size_t n) override {
    return Score(Method::kGreedy, methods_.Greedy(Room(n)));
  }
  StateSelection Local() override { return Score(Method::kLocal, methods_.Local()); }
  std::function<detail::ExactDone<StateSelection>(double)> Exact() override {
    return [this, methods = methods_](double seconds) {
      detail::ConstrainedAnswer answer = methods.Exact(seconds);
      std::function<void()> log = std::move(answer.log);
      return detail::ExactDone<StateSelection>{Score(Method::kExact, std::move(answer)),
                                               std::move(log)};
    };
  }

 private:
  // A budget has no n: every method grows within it.
  size_t Room(size_t n) const {
    return options_.budget ? scorer_.matrix().candidate_count() : n;
  }
  StateSelection Score(Method method, detail::ConstrainedAnswer answer) const {
    VANTAGE_CHECK(feasible_.IsFeasible(answer.chosen));
    if (options_.budget)
      VANTAGE_CHECK(detail::TotalCost(options_.costs, answer.chosen) <= *options_.budget);
    StateSelection s =
        ScoredFor(options_, states_, over_, method, std::move(answer.chosen), answer.seconds);
    if (answer.upper_bound)
      s.selection.upper_bound = std::max(*answer.upper_bound, s.selection.coverage);
    s.selection.proven_optimal = answer.proven_optimal;
    return s;
  }

  std::span<const StateObservations> states_;
  OverStates over_;
  const SelectOptions& options_;
  const detail::StatesScorer& scorer_;
  const detail::Feasibility& feasible_;
  double setup_seconds_;
  std::vector<uint32_t> kept_start_;
  detail::ConstrainedMethods<detail::StatesScorer> methods_;
};

}  // namespace

std::vector<StateSelection> SelectOverStates(std::span<const StateObservations> states,
                                             OverStates over,
                                             const SelectOptions& options,
                                             std::span<const Observation> calibration_cells) {
  Validate(states, options);
  const Clock::time_point start = Clock::now();
  const detail::CoverageMatrix matrix = StatesMatrix(states, options);
  // What a cell needs to count: its points, or k seers (k-coverage; 1: plain coverage).
  const int threshold = options.min_points ? static_cast<int>(*options.min_points) : options.k;
  const detail::StatesScorer scorer(matrix, over, threshold);
  const double setup = SecondsSince(start);

  // Every objective but a goal runs the methods on the states' model (ConstrainedMethods over
  // the StatesScorer): under the installation rules (the calibration overlap graph is the first
  // state's, or `calibration_cells`), from the kept sensors (their x fixed at 1 in the MILP),
  // counted k times or in points; with none of these, the plain methods.
  const detail::Feasibility feasible(
      calibration_cells.empty() ? states.front().observations : calibration_cells,
      options.constraints);
  const std::vector<uint32_t> kept_start = detail::KeptStart(feasible, options);
  if (options.goal)
    return GoalOverStates(states, over, options, scorer, feasible, kept_start, start);
  const size_t kept = options.fixed.size();
  const auto n = static_cast<size_t>(options.n);
  if (!options.budget && kept > 0 && kept_start.size() == kept && n <= kept) {
    // No room: the kept sensors are the answer.
    StateSelection s = ScoredFor(options, states, over, Method::kBest, options.fixed, setup);
    s.selection.method = "kept";
    return {s};
  }
  if (!options.budget && n < kept_start.size())
    throw InputError(fmt::format("n = {}: joining the {} kept sensors takes {} more sensors", n,
                                 kept, kept_start.size() - kept));
  StatesRun run(states, over, options, scorer, feasible, setup, kept_start);
  return detail::RunMethods<StateSelection>(run, options, matrix.candidate_count(), start);
}

Selection ScoreChosenOverStates(std::span<const StateObservations> states, OverStates over,
                                std::vector<uint32_t> chosen, const std::string& method,
                                const SelectOptions& options) {
  StateSelection scored = ScoredFor(options, states, over, Method::kLocal, std::move(chosen), 0);
  scored.selection.method = method;
  scored.selection.seconds = 0;
  scored.selection.state_coverage = std::move(scored.state_coverage);
  return std::move(scored.selection);
}

std::vector<uint32_t> ImproveOverStatesBySwaps(std::span<const StateObservations> states,
                                               OverStates over, std::vector<uint32_t> start,
                                               const SelectOptions& options) {
  VANTAGE_CHECK(!options.goal && !states.empty());
  const detail::CoverageMatrix matrix = StatesMatrix(states, options);
  const int threshold = options.min_points ? static_cast<int>(*options.min_points) : options.k;
  const detail::StatesScorer scorer(matrix, over, threshold);
  const detail::Feasibility feasible(states.front().observations, options.constraints);
  detail::Capacity capacity;
  capacity.n = static_cast<size_t>(options.n);
  if (options.budget) {
    capacity.n = matrix.candidate_count();
    capacity.costs = options.costs;
    capacity.budget = *options.budget;
  }
  // The kept sensors first, never swapped out (ConstrainedLocal's frozen positions).
  const std::vector<uint32_t>& fixed = options.fixed;
  std::erase_if(start, [&](uint32_t c) {
    return std::find(fixed.begin(), fixed.end(), c) != fixed.end();
  });
  start.insert(start.begin(), fixed.begin(), fixed.end());
  return detail::ConstrainedLocal(scorer, feasible, std::move(start), capacity, fixed.size());
}

}  // namespace vantage
