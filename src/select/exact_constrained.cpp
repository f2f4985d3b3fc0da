// Exact selection under installation constraints (docs/constraints.md), solved by CBC:
//
//   max  sum_i a_i x_i + sum_e w_e y_e
//   s.t. T y_e <= sum_{i sees e} c_ie x_i       every element seen by two or more candidates
//                                               (T = 1, c = 1: coverage; T = k: k-coverage;
//                                               T = min_points, c the capped counts)
//        sum_i x_i <= n                         (a budget: sum_i cost_i x_i <= B)
//        x_a + x_b <= 1                         every conflicting pair
//   and with a calibration rule, a single-commodity flow over the overlap edges (both directions):
//        sum_i r_i = 1,  r_i <= x_i             one root among the chosen
//        s_i <= n r_i,   sum_i s_i = sum_i x_i  the root supplies one unit per chosen sensor
//        out_i - in_i = s_i - x_i               every chosen sensor keeps one unit
//        out_i <= (n - 1) x_i, in_i <= (n - 1) x_i   flow only through chosen sensors
//   x, r binary; y in [0, 1] (binary for T >= 2); s, f >= 0. A flow exists exactly when every
//   chosen sensor is reached from the root along edges between chosen sensors: the chosen graph
//   is connected.
//
// With T = 1 an element seen by one candidate folds into that candidate's a_i. Over the states of a
// scene the objective is the aggregate (exact_states.cpp): mean, w_e / (S |R_s|) per element;
// min, max t with t <= sum_{e in s} w_e / |R_s| y_e (and the folded a_is) per state s. A budget's
// flow carries at most one unit per kept candidate instead of n.
//
// No dominance reduction (a dominated candidate may be the only one that fits the constraints).
// Candidates that see nothing (or cost more than the budget) are left out: they join no edge and
// add no cell.
#include <coin/Cbc_C_Interface.h>
#include <fmt/format.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstring>
#include <limits>
#include <memory>

#include "select/cbc_answer.hpp"
#include "select/constrained.hpp"
#include "select/methods.hpp"
#include "select/scorer.hpp"
#include "vantage/error.hpp"
#include "vantage/interrupt.hpp"

namespace vantage::detail {
namespace {

// The Lagrangian steps of the bound when CBC cannot finish (CBC's time rules: cbc_answer.hpp).
constexpr int kLagrangianSteps = 300;

// The model, row by row, of the candidates `kept`.
class Model {
 public:
  int AddColumn(double lower, double upper, double objective, bool is_integer) {
    lower_.push_back(lower);
    upper_.push_back(upper);
    objective_.push_back(objective);
    is_integer_.push_back(is_integer);
    return static_cast<int>(lower_.size()) - 1;
  }
  void AddRow(std::vector<int> columns, std::vector<double> values, char sense, double rhs) {
    nonzeros_ += columns.size();
    rows_.push_back({std::move(columns), std::move(values), sense, rhs});
  }
  size_t nonzeros() const { return nonzeros_; }
  size_t row_count() const { return rows_.size(); }
  size_t column_count() const { return lower_.size(); }

  void LoadInto(Cbc_Model* cbc) const {
    for (size_t c = 0; c < lower_.size(); ++c) {
      Cbc_addCol(cbc, "", lower_[c], upper_[c], objective_[c], is_integer_[c] ? 1 : 0, 0,
                 nullptr, nullptr);
    }
    for (const Row& row : rows_) {
      Cbc_addRow(cbc, "", static_cast<int>(row.columns.size()), row.columns.data(),
                 row.values.data(), row.sense, row.rhs);
    }
  }

 private:
  struct Row {
    std::vector<int> columns;
    std::vector<double> values;
    char sense;
    double rhs;
  };
  std::vector<double> lower_, upper_, objective_;
  std::vector<bool> is_integer_;
  std::vector<Row> rows_;
  size_t nonzeros_ = 0;
};

struct Outcome {
  std::vector<uint32_t> chosen;
  double bound = std::numeric_limits<double>::quiet_NaN();
  bool proven_optimal = false;
  std::string note;
};

// What the model maximises, in CBC's units: `scale` times the result's (cells, or an aggregate).
struct MilpSpec {
  Capacity capacity;
  int threshold = 1;
  std::vector<double> value;  ///< per element, in the result's units
  double scale = 1;
  bool by_min = false;              ///< states: max t, t <= each state's share
  double gap = 0.99;                ///< CBC's allowable gap (whole cells: within 1 is optimal)
  std::span<const uint32_t> fixed;  ///< kept sensors: x = 1
};

Outcome RunCbc(const CoverageMatrix& matrix,
               const Feasibility& feasible,
               const MilpSpec& spec,
               const std::vector<uint32_t>& start,
               double time_limit) {
  Outcome outcome;
  const Capacity& capacity = spec.capacity;
  const size_t m = matrix.candidate_count();
  std::vector<uint32_t> kept;
  std::vector<int> x_of(m, -1);
  const auto is_fixed = [&](uint32_t i) {
    return std::find(spec.fixed.begin(), spec.fixed.end(), i) != spec.fixed.end();
  };
  for (uint32_t i = 0; i < m; ++i) {
    if (!is_fixed(i)) {
      if (matrix.Row(i).empty()) continue;
      if (capacity.has_budget() && capacity.costs[i] > capacity.budget) continue;
    }
    x_of[i] = static_cast<int>(kept.size());
    kept.push_back(i);
  }
  if (kept.empty()) {
    outcome.note = "no candidate sees anything";
    return outcome;
  }
  const auto threshold = static_cast<uint32_t>(spec.threshold);
  const size_t states = matrix.state_count();
  std::vector<uint32_t> state_of(matrix.element_count(), 0);
  for (size_t st = 0; st < states; ++st) {
    for (uint32_t e = matrix.StateBegin(st); e < matrix.StateBegin(st + 1); ++e)
      state_of[e] = static_cast<uint32_t>(st);
  }
  // Seers of each element among the kept, with what each adds towards T.
  std::vector<std::vector<std::pair<int, uint32_t>>> seers(matrix.element_count());
  std::vector<uint32_t> reach(matrix.element_count(), 0);
  for (const uint32_t i : kept) {
    const std::vector<uint32_t>& row = matrix.Row(i);
    for (size_t j = 0; j < row.size(); ++j) {
      seers[row[j]].emplace_back(x_of[i], matrix.Count(i, j));
      reach[row[j]] += matrix.Count(i, j);
    }
  }
  const auto folds = [&](uint32_t e) { return threshold == 1 && seers[e].size() == 1; };
  // a_i, per state (the min rows need them apart).
  const int x_count = static_cast<int>(kept.size());
  std::vector<std::vector<double>> own(states, std::vector<double>(kept.size(), 0.0));
  for (uint32_t e = 0; e < seers.size(); ++e)
    if (folds(e)) own[state_of[e]][static_cast<size_t>(seers[e][0].first)] += spec.value[e];

  Model model;
  for (int q = 0; q < x_count; ++q) {
    double objective = 0;
    if (!spec.by_min)
      for (size_t st = 0; st < states; ++st) objective += own[st][static_cast<size_t>(q)];
    model.AddColumn(is_fixed(kept[static_cast<size_t>(q)]) ? 1 : 0, 1, objective * spec.scale,
                    true);
  }
  // Per state, the columns of its share (min).
  std::vector<std::vector<int>> share_columns(states);
  std::vector<std::vector<double>> share_values(states);
  for (uint32_t e = 0; e < seers.size(); ++e) {
    if (seers[e].empty() || folds(e) || reach[e] < threshold) continue;
    // With T >= 2 a fractional y_e would count a cell short of T seers in part: y binary.
    const int y =
        model.AddColumn(0, 1, spec.by_min ? 0.0 : spec.value[e] * spec.scale, threshold > 1);
    if (spec.by_min) {
      share_columns[state_of[e]].push_back(y);
      share_values[state_of[e]].push_back(-spec.value[e]);
    }
    std::vector<int> columns{y};
    std::vector<double> values{static_cast<double>(threshold)};
    for (const auto& [q, count] : seers[e]) {
      columns.push_back(q);
      values.push_back(-static_cast<double>(std::min(count, threshold)));
    }
    model.AddRow(std::move(columns), std::move(values), 'L', 0.0);
  }
  {
    std::vector<int> all(static_cast<size_t>(x_count));
    std::vector<double> coefficients(all.size(), 1.0);
    for (int q = 0; q < x_count; ++q) {
      all[static_cast<size_t>(q)] = q;
      if (capacity.has_budget()) coefficients[static_cast<size_t>(q)] = capacity.costs[kept[q]];
    }
    model.AddRow(all, std::move(coefficients), 'L',
                 capacity.has_budget() ? capacity.budget : static_cast<double>(capacity.n));
  }
  for (const Conflict& c : feasible.conflicts()) {
    if (x_of[c.a] < 0 || x_of[c.b] < 0) continue;
    model.AddRow({x_of[c.a], x_of[c.b]}, {1.0, 1.0}, 'L', 1.0);
  }
  // The most sensors an answer holds: the flow's capacity.
  const double nd =
      static_cast<double>(capacity.has_budget() ? kept.size() : std::min(capacity.n, kept.size()));
  std::vector<int> r_of, s_of;
  if (feasible.has_calibration() && nd >= 2) {
    std::vector<int> root_row, supply_row;
    std::vector<double> supply_values;
    for (int q = 0; q < x_count; ++q) {
      r_of.push_back(model.AddColumn(0, 1, 0, true));
      s_of.push_back(model.AddColumn(0, nd, 0, false));
      model.AddRow({r_of.back(), q}, {1.0, -1.0}, 'L', 0.0);
      model.AddRow({s_of.back(), r_of.back()}, {1.0, -nd}, 'L', 0.0);
      root_row.push_back(r_of.back());
      supply_row.push_back(s_of.back());
      supply_values.push_back(1.0);
      supply_row.push_back(q);
      supply_values.push_back(-1.0);
    }
    model.AddRow(root_row, std::vector<double>(root_row.size(), 1.0), 'E', 1.0);
    model.AddRow(supply_row, supply_values, 'E', 0.0);
    // Arcs both ways along each edge between kept candidates.
    std::vector<std::vector<int>> out(static_cast<size_t>(x_count)), in(out.size());
    for (const uint32_t i : kept) {
      for (const uint32_t j : feasible.Neighbours(i)) {
        if (x_of[j] < 0) continue;
        const int f = model.AddColumn(0, nd - 1, 0, false);
        out[static_cast<size_t>(x_of[i])].push_back(f);
        in[static_cast<size_t>(x_of[j])].push_back(f);
      }
    }
    for (int q = 0; q < x_count; ++q) {
      const auto& o = out[static_cast<size_t>(q)];
      const auto& t = in[static_cast<size_t>(q)];
      std::vector<int> columns(o.begin(), o.end());
      std::vector<double> values(o.size(), 1.0);
      columns.insert(columns.end(), t.begin(), t.end());
      values.insert(values.end(), t.size(), -1.0);
      columns.push_back(s_of[static_cast<size_t>(q)]);
      values.push_back(-1.0);
      columns.push_back(q);
      values.push_back(1.0);
      model.AddRow(std::move(columns), std::move(values), 'E', 0.0);
      std::vector<int> oc(o.begin(), o.end());
      oc.push_back(q);
      std::vector<double> ov(o.size(), 1.0);
      ov.push_back(-(nd - 1));
      model.AddRow(std::move(oc), std::move(ov), 'L', 0.0);
      std::vector<int> ic(t.begin(), t.end());
      ic.push_back(q);
      std::vector<double> iv(t.size(), 1.0);
      iv.push_back(-(nd - 1));
      model.AddRow(std::move(ic), std::move(iv), 'L', 0.0);
    }
  }
  if (spec.by_min) {
    const int t = model.AddColumn(0, 1, spec.scale, false);
    for (size_t st = 0; st < states; ++st) {
      std::vector<int> columns = share_columns[st];
      std::vector<double> values = share_values[st];
      for (int q = 0; q < x_count; ++q) {
        if (own[st][static_cast<size_t>(q)] == 0) continue;
        columns.push_back(q);
        values.push_back(-own[st][static_cast<size_t>(q)]);
      }
      columns.push_back(t);
      values.push_back(1.0);
      model.AddRow(std::move(columns), std::move(values), 'L', 0.0);
    }
  }
  const double max_nonzeros = CbcMaxNonzeros(time_limit);
  if (static_cast<double>(model.nonzeros()) > max_nonzeros) {
    outcome.note = fmt::format(
        "constrained MILP of {} x {} with {} nonzeros is too large for a {} s time limit (at "
        "most {:.0f}); CBC not run",
        model.row_count(), model.column_count(), model.nonzeros(), time_limit, max_nonzeros);
    return outcome;
  }

  CbcModelPtr owner(Cbc_newModel());
  if (!owner) {
    outcome.note = "CBC could not create a model";
    return outcome;
  }
  Cbc_Model* cbc = owner.get();
  model.LoadInto(cbc);
  Cbc_setObjSense(cbc, -1);
  Cbc_setLogLevel(cbc, 0);
  Cbc_setParameter(cbc, "timeMode", "elapsed");
  Cbc_setMaximumSeconds(cbc, kCbcTimeShare * time_limit);
  Cbc_setAllowableGap(cbc, spec.gap);
  if (spec.by_min || spec.gap < 0.5) Cbc_setAllowableFractionGap(cbc, 0.0);
  // Warm start on every integer column (exact.cpp: CBC otherwise completes it by an LP).
  std::vector<int> start_columns;
  std::vector<double> start_values;
  std::vector<double> x_start(static_cast<size_t>(x_count), 0.0);
  for (const uint32_t c : start)
    if (x_of[c] >= 0) x_start[static_cast<size_t>(x_of[c])] = 1.0;
  int root = -1;
  for (int q = 0; q < x_count; ++q) {
    start_columns.push_back(q);
    start_values.push_back(x_start[static_cast<size_t>(q)]);
    if (root < 0 && x_start[static_cast<size_t>(q)] > 0) root = q;
  }
  for (size_t q = 0; q < r_of.size(); ++q) {
    start_columns.push_back(r_of[q]);
    start_values.push_back(static_cast<int>(q) == root ? 1.0 : 0.0);
  }
  Cbc_setMIPStartI(cbc, static_cast<int>(start_columns.size()), start_columns.data(),
                   start_values.data());
  const std::optional<CbcAnswer> solved =
      SolveInChild(cbc, x_count, kCbcKillShare * time_limit, &outcome.note);
  if (!solved) return outcome;
  const CbcAnswer& answer = *solved;
  if (std::isfinite(answer.bound)) outcome.bound = answer.bound;
  if (!answer.has_solution) {
    outcome.note = fmt::format("CBC found no solution ({})", StatusInWords(answer));
    return outcome;
  }
  for (const int q : answer.chosen_columns) outcome.chosen.push_back(kept[static_cast<size_t>(q)]);
  outcome.proven_optimal = answer.proven_optimal;
  if (!outcome.proven_optimal) outcome.note = fmt::format("CBC {}", StatusInWords(answer));
  return outcome;
}

// RunCbc, a failure of CBC's (not an interrupt) turned into the note of an empty outcome: the
// caller then keeps its start and its own bound.
Outcome RunCbcOrNote(const CoverageMatrix& matrix, const Feasibility& feasible,
                     const MilpSpec& spec, const std::vector<uint32_t>& start, double time_limit) {
  try {
    return RunCbc(matrix, feasible, spec, start, time_limit);
  } catch (const Interrupted&) {
    throw;
  } catch (const std::exception& e) {
    Outcome outcome;
    outcome.note = fmt::format("CBC failed: {}", e.what());
    return outcome;
  }
}

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
  MilpSpec spec;
  spec.capacity = capacity;
  spec.threshold = k;
  spec.fixed = objective.fixed;
  spec.value.resize(matrix.element_count());
  for (uint32_t e = 0; e < matrix.element_count(); ++e) spec.value[e] = matrix.Weight(e);
  Outcome outcome = RunCbcOrNote(matrix, feasible, spec, start, time_limit);
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
                                              int threshold) {
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
  if (n == 1) {  // one sensor breaks no constraint: the best single candidate is the optimum
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
  const bool by_min = over == OverStates::kMin;
  const size_t states = matrix.state_count();
  MilpSpec spec;
  spec.capacity.n = n;
  spec.by_min = by_min;
  spec.threshold = threshold;
  spec.value.resize(matrix.element_count());
  size_t largest = 1;
  for (size_t st = 0; st < states; ++st) {
    largest = std::max(largest, matrix.StateReferenceSize(st));
    const double unit = 1.0 / static_cast<double>(matrix.StateReferenceSize(st)) /
                        (by_min ? 1.0 : static_cast<double>(states));
    for (uint32_t e = matrix.StateBegin(st); e < matrix.StateBegin(st + 1); ++e)
      spec.value[e] = matrix.Weight(e) * unit;
  }
  // CBC's objective in about cells of the largest state (exact_states.cpp).
  spec.scale = static_cast<double>(largest) * (by_min ? 1.0 : static_cast<double>(states));
  spec.gap = 1e-10 * spec.scale;
  Outcome outcome =
      RunCbcOrNote(matrix, feasible, spec, start, time_limit - SecondsSince(begin));
  result.note = outcome.note;
  StatesScorer::Score score = scorer.ScoreOf(scorer.Covered(result.chosen));
  bool cbc_proved = false;
  const std::optional<std::vector<uint32_t>> found =
      UsableAnswer(matrix, feasible, spec.capacity, {}, outcome.chosen);
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
  const double cbc_bound = std::isfinite(outcome.bound) ? outcome.bound / spec.scale
                                                        : std::numeric_limits<double>::infinity();
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
