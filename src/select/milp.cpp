// The selection MILP (milp.hpp): the one builder of every exact model, and its CBC run.
#include "select/milp.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <exception>
#include <limits>

#include "select/cbc_answer.hpp"
#include "select/cbc_module.hpp"
#include "select/constrained.hpp"
#include "vantage/error.hpp"
#include "vantage/interrupt.hpp"

namespace vantage::detail {
namespace {

constexpr double kInfinity = std::numeric_limits<double>::max();

// Candidates seeing each element.
std::vector<std::vector<uint32_t>> Columns(const CoverageMatrix& matrix) {
  std::vector<std::vector<uint32_t>> columns(matrix.element_count());
  for (uint32_t i = 0; i < matrix.candidate_count(); ++i) {
    for (const uint32_t e : matrix.Row(i)) columns[e].push_back(i);
  }
  return columns;
}

// The element of a non-empty row that the fewest candidates see: any superset row contains it.
uint32_t RarestElement(const CoverageMatrix& matrix,
                       const std::vector<std::vector<uint32_t>>& columns,
                       uint32_t candidate) {
  const std::vector<uint32_t>& row = matrix.Row(candidate);
  return *std::min_element(row.begin(), row.end(), [&](uint32_t a, uint32_t b) {
    return columns[a].size() < columns[b].size();
  });
}

// Candidate i is dominated when another sees a superset at no higher cost, and is strictly better
// (a strict superset, or cheaper) or equal at a lower index. Dominance is then a strict partial
// order, so every dominated candidate sits below a kept one, and dropping all of them at once
// keeps an optimum of "at most n sensors", of a budget and of a goal, for every state's coverage
// (each is monotone in the set). `costs` empty: unit.
std::vector<bool> Dominated(const CoverageMatrix& matrix,
                            const std::vector<std::vector<uint32_t>>& columns,
                            std::span<const double> costs) {
  const size_t m = matrix.candidate_count();
  std::vector<bool> dominated(m, false);
  for (uint32_t i = 0; i < m; ++i) {
    const std::vector<uint32_t>& row = matrix.Row(i);
    if (row.empty()) {
      dominated[i] = true;
      continue;
    }
    for (const uint32_t j : columns[RarestElement(matrix, columns, i)]) {
      if (j == i) continue;
      const size_t size_j = matrix.Row(j).size();
      if (size_j < row.size()) continue;
      bool is_better = size_j > row.size() || j < i;
      if (!costs.empty()) {
        if (costs[j] > costs[i]) continue;
        // Equal rows and costs: the lower index wins; equal rows, j cheaper: j wins.
        is_better = size_j > row.size() || costs[j] < costs[i] || j < i;
      }
      if (is_better && matrix.IsSubset(i, j)) {
        dominated[i] = true;
        break;
      }
    }
  }
  return dominated;
}

// A kept candidate that sees everything `candidate` sees at no higher cost (itself when kept).
uint32_t Dominator(const CoverageMatrix& matrix,
                   const std::vector<std::vector<uint32_t>>& columns,
                   const std::vector<bool>& excluded,
                   std::span<const double> costs,
                   uint32_t candidate) {
  if (!excluded[candidate]) return candidate;
  const auto cheap_enough = [&](uint32_t j) {
    return costs.empty() || costs[j] <= costs[candidate];
  };
  if (matrix.Row(candidate).empty()) {
    for (uint32_t j = 0; j < matrix.candidate_count(); ++j) {
      if (!excluded[j] && cheap_enough(j)) return j;
    }
    return candidate;  // nothing to map to: left out of the warm start
  }
  for (const uint32_t j : columns[RarestElement(matrix, columns, candidate)]) {
    if (!excluded[j] && cheap_enough(j) && matrix.IsSubset(candidate, j)) return j;
  }
  return candidate;
}

// The model, built row by row and loaded column-wise. Rows are filled when they are added, so
// each column's entries come in ascending rows.
class Model {
 public:
  int AddColumn(double lower, double upper, double objective, bool is_integer) {
    lower_.push_back(lower);
    upper_.push_back(upper);
    objective_.push_back(objective);
    is_integer_.push_back(is_integer);
    entries_.emplace_back();
    return static_cast<int>(lower_.size()) - 1;
  }
  // A row lower <= sum value * column <= upper.
  void AddRow(const std::vector<std::pair<int, double>>& terms, double lower, double upper) {
    const int row = static_cast<int>(row_lower_.size());
    row_lower_.push_back(lower);
    row_upper_.push_back(upper);
    for (const auto& [column, value] : terms) entries_[column].emplace_back(row, value);
    nonzeros_ += terms.size();
  }
  size_t nonzeros() const { return nonzeros_; }
  int row_count() const { return static_cast<int>(row_lower_.size()); }
  int column_count() const { return static_cast<int>(lower_.size()); }

  CbcModelPtr Load(double sense) const {
    const CbcModuleApi& cbc_api = Cbc();
    CbcModelPtr model(cbc_api.cbc_new_model());
    if (!model) return model;
    std::vector<int> starts{0};
    std::vector<int> indices;
    std::vector<double> values;
    for (const auto& column : entries_) {
      for (const auto& [row, value] : column) {
        indices.push_back(row);
        values.push_back(value);
      }
      starts.push_back(static_cast<int>(indices.size()));
    }
    CbcModelHandle* cbc = model.get();
    cbc_api.cbc_load_problem(cbc, column_count(), row_count(), starts.data(), indices.data(),
                             values.data(), lower_.data(), upper_.data(), objective_.data(),
                             row_lower_.data(), row_upper_.data());
    for (int c = 0; c < column_count(); ++c)
      if (is_integer_[static_cast<size_t>(c)]) cbc_api.cbc_set_integer(cbc, c);
    cbc_api.cbc_set_obj_sense(cbc, sense);
    cbc_api.cbc_set_log_level(cbc, 0);
    cbc_api.cbc_set_parameter(cbc, "timeMode", "elapsed");  // wall clock, as the time limits mean
    return model;
  }

 private:
  std::vector<double> lower_, upper_, objective_, row_lower_, row_upper_;
  std::vector<bool> is_integer_;
  std::vector<std::vector<std::pair<int, double>>> entries_;
  size_t nonzeros_ = 0;
};

MilpAnswer BuildAndSolve(const SelectionModel& milp, const std::vector<uint32_t>& start,
                         double time_limit) {
  MilpAnswer answer;
  const CoverageMatrix& matrix = *milp.matrix;
  const size_t m = matrix.candidate_count();
  const auto threshold = static_cast<uint32_t>(milp.threshold);
  const bool maximise = !milp.goal;
  const bool has_costs = !milp.costs.empty();
  const auto resource = [&](uint32_t i) { return has_costs ? milp.costs[i] : 1.0; };
  const bool has_rules = milp.rules != nullptr && milp.rules->restricts();
  std::vector<bool> is_fixed(m, false);
  for (const uint32_t f : milp.fixed) is_fixed[f] = true;

  // Candidates: dominated ones out where a superset serves as well (T = 1, no rules that could
  // make the superset infeasible), else those that see nothing; unaffordable ones out; kept
  // sensors always in.
  const std::vector<std::vector<uint32_t>> columns = Columns(matrix);
  std::vector<bool> excluded(m, false);
  if (threshold == 1 && !has_rules) {
    excluded = Dominated(matrix, columns, milp.costs);
  } else {
    for (uint32_t i = 0; i < m; ++i) excluded[i] = matrix.Row(i).empty();
  }
  std::vector<uint32_t> kept;
  std::vector<int> x_of(m, -1);
  double kept_resource = 0;
  for (uint32_t i = 0; i < m; ++i) {
    if (maximise && resource(i) > milp.capacity) excluded[i] = true;
    if (is_fixed[i]) excluded[i] = false;
    if (excluded[i]) continue;
    x_of[i] = static_cast<int>(kept.size());
    kept.push_back(i);
    kept_resource += resource(i);
  }
  if (kept.empty()) {
    answer.note = "no candidate left after the reduction";
    return answer;
  }
  if (maximise && !has_rules && kept_resource <= milp.capacity) {
    answer.chosen = kept;  // all fit together: nothing covers more
    answer.proven_optimal = true;
    answer.note = "solved by dominance reduction";
    return answer;
  }

  // Classes: one state without point counts (or T = 1, where counts do not matter) re-merges
  // the elements over the kept candidates; otherwise each element is its own class.
  const size_t states = matrix.state_count();
  std::vector<uint32_t> state_of(matrix.element_count(), 0);
  for (size_t st = 0; st < states; ++st)
    for (uint32_t e = matrix.StateBegin(st); e < matrix.StateBegin(st + 1); ++e)
      state_of[e] = static_cast<uint32_t>(st);
  std::vector<int64_t> class_of;
  if (states == 1 && (threshold == 1 || !matrix.has_counts())) {
    std::vector<std::span<const uint32_t>> kept_rows;
    kept_rows.reserve(kept.size());
    for (const uint32_t i : kept) kept_rows.emplace_back(matrix.Row(i));
    class_of = RefinePartition(matrix.element_count(), kept_rows);
  } else {
    class_of.assign(matrix.element_count(), -1);
    for (const uint32_t i : kept)
      for (const uint32_t e : matrix.Row(i)) class_of[e] = e;
  }
  int64_t class_count = 0;
  for (const int64_t c : class_of) class_count = std::max(class_count, c + 1);
  std::vector<double> class_weight(class_count, 0.0);
  std::vector<uint32_t> class_state(class_count, 0);
  for (size_t e = 0; e < class_of.size(); ++e) {
    if (class_of[e] < 0) continue;
    class_weight[class_of[e]] += matrix.Weight(static_cast<uint32_t>(e));
    class_state[class_of[e]] = state_of[e];
  }
  // Over states a cell of state s weighs ω_s = p_s / q_s (the aggregation's row): a weighted sum
  // values it ω_s / Σ ω_s |R_s| of the aggregate, a minimum ω_s of its state's row. CBC's
  // objective is in cells of the state weighted least (`scale` per unit of the aggregate: its
  // tolerances suit magnitudes >= 1), and so is a weighted sum's goal row: ω_s / ω_least per
  // cell, whole where every weight is (then so is the objective, up to round-off).
  const Aggregation* over = milp.over;
  const bool by_min = over && over->shape == AggregateShape::kMinimum;
  const auto lighter = [](const CellWeight& a, const CellWeight& b) {
    __extension__ typedef unsigned __int128 Wide;
    return Wide{a.numerator} * b.denominator < Wide{b.numerator} * a.denominator;
  };
  std::vector<CellWeight> weight(states);
  double most = 0;         // Σ ω_s |R_s|
  CellWeight least{0, 1};  // the least positive ω_s
  bool whole_weights = true;
  for (size_t st = 0; over && st < states; ++st) {
    const size_t size = matrix.StateReferenceSize(st);
    const CellWeight w = weight[st] = over->weight(size);
    most += Weighted(static_cast<double>(size), w);
    if (w.numerator > 0 && (least.numerator == 0 || lighter(w, least))) least = w;
    whole_weights = whole_weights && w.numerator % w.denominator == 0;
  }
  if (least.numerator == 0) least = {1, 1};
  const double per_least =
      static_cast<double>(least.denominator) / static_cast<double>(least.numerator);
  const double scale = !over ? 1.0 : by_min ? per_least : most > 0 ? most * per_least : 1.0;
  std::vector<double> unit(states, 1.0);  // a class's value per weight unit (value units)
  for (size_t st = 0; over && st < states; ++st) {
    unit[st] = Weighted(1.0, weight[st]) / (by_min ? 1.0 : most);
  }
  const auto value_of = [&](int64_t c) { return class_weight[c] * unit[class_state[c]]; };
  // Goal rows: cells (one state, or each state's for a minimum), or a weighted sum in cells of
  // the state weighted least (its goal times `scale`).
  const auto goal_value_of = [&](int64_t c) {
    if (!over || by_min) return class_weight[c];
    const CellWeight& w = weight[class_state[c]];
    return class_weight[c] * static_cast<double>(w.numerator * least.denominator) /
           static_cast<double>(w.denominator * least.numerator);
  };
  const size_t groups = by_min ? states : 1;  // value rows: one, or one per state (min)
  const auto group_of = [&](int64_t c) { return by_min ? class_state[c] : 0; };

  // Each kept column's classes with its points there (capped at T), and each class's seers.
  std::vector<std::vector<std::pair<int, uint32_t>>> seers(class_count);  // column, points
  std::vector<uint32_t> reach(class_count, 0);
  {
    std::vector<int64_t> last_column(class_count, -1);
    for (size_t q = 0; q < kept.size(); ++q) {
      const std::vector<uint32_t>& row = matrix.Row(kept[q]);
      for (size_t j = 0; j < row.size(); ++j) {
        const int64_t c = class_of[row[j]];
        if (last_column[c] == static_cast<int64_t>(q)) continue;
        last_column[c] = static_cast<int64_t>(q);
        const uint32_t points = std::min(matrix.Count(kept[q], j), threshold);
        seers[c].emplace_back(static_cast<int>(q), points);
        reach[c] += points;
      }
    }
  }
  std::vector<double> goal_rhs(groups, 0.0), coverable(groups, 0.0);
  for (int64_t c = 0; c < class_count; ++c)
    if (reach[c] >= threshold) coverable[group_of(c)] += goal_value_of(c);
  bool cover_all = false;
  if (!maximise) {
    for (size_t g = 0; g < groups; ++g) {
      if (!over) goal_rhs[g] = *milp.goal;
      else if (by_min)
        goal_rhs[g] = std::ceil(*milp.goal * static_cast<double>(matrix.StateReferenceSize(g)) -
                                1e-9);
      else
        goal_rhs[g] = *milp.goal * scale;
      if (goal_rhs[g] > coverable[g] + 1e-9 * std::max(1.0, coverable[g])) {
        answer.note = "the goal is above what all candidates reach together";
        return answer;
      }
    }
    // A goal of everything that can be seen (one state): covering rows sum points x >= T,
    // without y — pure set covering, whose structure CBC's cuts know.
    cover_all = !over && goal_rhs[0] == coverable[0];
  }

  Model model;
  const int x_count = static_cast<int>(kept.size());
  // A class seen by one candidate (T = 1) folds into that candidate's column, per group.
  const auto folds = [&](int64_t c) { return threshold == 1 && reach[c] == 1; };
  std::vector<std::vector<double>> own(states, std::vector<double>(kept.size(), 0.0));
  std::vector<std::vector<double>> own_goal(groups, std::vector<double>(kept.size(), 0.0));
  for (int64_t c = 0; c < class_count; ++c) {
    if (seers[c].empty() || !folds(c) || cover_all) continue;
    const auto q = static_cast<size_t>(seers[c][0].first);
    own[class_state[c]][q] += value_of(c);
    own_goal[group_of(c)][q] += goal_value_of(c);
  }
  for (int q = 0; q < x_count; ++q) {
    double objective = 0;
    if (!maximise) {
      objective = resource(kept[static_cast<size_t>(q)]);
    } else if (!by_min) {
      for (size_t st = 0; st < states; ++st) objective += own[st][static_cast<size_t>(q)] * scale;
    }
    model.AddColumn(is_fixed[kept[static_cast<size_t>(q)]] ? 1 : 0, 1, objective, true);
  }
  // Threshold rows (and the y columns) in class order.
  const bool integer_y = threshold >= 2;
  std::vector<int> y_of(class_count, -1);
  for (int64_t c = 0; c < class_count; ++c) {
    if (seers[c].empty() || reach[c] < threshold) continue;
    std::vector<std::pair<int, double>> terms;
    if (cover_all) {
      for (const auto& [q, points] : seers[c]) terms.emplace_back(q, points);
      model.AddRow(terms, threshold, kInfinity);
      continue;
    }
    if (folds(c)) continue;
    y_of[c] = model.AddColumn(0, 1, maximise && !by_min ? value_of(c) * scale : 0.0, integer_y);
    for (const auto& [q, points] : seers[c]) terms.emplace_back(q, -static_cast<double>(points));
    terms.emplace_back(y_of[c], static_cast<double>(threshold));
    model.AddRow(terms, -kInfinity, 0.0);
  }
  if (maximise) {  // the capacity: n sensors, or the budget
    std::vector<std::pair<int, double>> terms;
    for (int q = 0; q < x_count; ++q)
      if (resource(kept[static_cast<size_t>(q)]) != 0)
        terms.emplace_back(q, resource(kept[static_cast<size_t>(q)]));
    model.AddRow(terms, -kInfinity, milp.capacity);
  } else if (!cover_all) {  // the goal, per group
    for (size_t g = 0; g < groups; ++g) {
      std::vector<std::pair<int, double>> terms;
      for (int q = 0; q < x_count; ++q)
        if (own_goal[g][static_cast<size_t>(q)] != 0)
          terms.emplace_back(q, own_goal[g][static_cast<size_t>(q)]);
      for (int64_t c = 0; c < class_count; ++c)
        if (y_of[c] >= 0 && group_of(c) == g) terms.emplace_back(y_of[c], goal_value_of(c));
      model.AddRow(terms, goal_rhs[g], kInfinity);
    }
  }
  std::vector<int> r_of;
  if (has_rules) {
    const Feasibility& rules = *milp.rules;
    for (const Conflict& c : rules.conflicts()) {
      if (x_of[c.a] < 0 || x_of[c.b] < 0) continue;
      model.AddRow({{x_of[c.a], 1.0}, {x_of[c.b], 1.0}}, -kInfinity, 1.0);
    }
    // Connectivity: the root supplies one unit per chosen sensor (at most nd), each chosen sensor
    // keeps one, and flow passes only through chosen sensors: a flow exists exactly when the
    // chosen overlap graph is connected.
    const double nd = maximise && !has_costs
                          ? static_cast<double>(std::min<size_t>(
                                static_cast<size_t>(milp.capacity), kept.size()))
                          : static_cast<double>(kept.size());
    if (rules.has_calibration() && nd >= 2) {
      std::vector<int> s_of;
      std::vector<std::pair<int, double>> root, supply;
      for (int q = 0; q < x_count; ++q) {
        r_of.push_back(model.AddColumn(0, 1, 0, true));
        s_of.push_back(model.AddColumn(0, nd, 0, false));
        model.AddRow({{q, -1.0}, {r_of.back(), 1.0}}, -kInfinity, 0.0);
        model.AddRow({{r_of.back(), -nd}, {s_of.back(), 1.0}}, -kInfinity, 0.0);
        root.emplace_back(r_of.back(), 1.0);
        supply.emplace_back(q, -1.0);
        supply.emplace_back(s_of.back(), 1.0);
      }
      model.AddRow(root, 1.0, 1.0);
      model.AddRow(supply, 0.0, 0.0);
      std::vector<std::vector<int>> out(kept.size()), in(kept.size());
      for (const uint32_t i : kept) {
        for (const uint32_t j : rules.Neighbours(i)) {
          if (x_of[j] < 0) continue;
          const int f = model.AddColumn(0, nd - 1, 0, false);
          out[static_cast<size_t>(x_of[i])].push_back(f);
          in[static_cast<size_t>(x_of[j])].push_back(f);
        }
      }
      for (int q = 0; q < x_count; ++q) {
        const auto& o = out[static_cast<size_t>(q)];
        const auto& t = in[static_cast<size_t>(q)];
        std::vector<std::pair<int, double>> balance{{q, 1.0}, {s_of[static_cast<size_t>(q)], -1.0}};
        std::vector<std::pair<int, double>> outflow{{q, -(nd - 1)}}, inflow{{q, -(nd - 1)}};
        for (const int f : o) {
          balance.emplace_back(f, 1.0);
          outflow.emplace_back(f, 1.0);
        }
        for (const int f : t) {
          balance.emplace_back(f, -1.0);
          inflow.emplace_back(f, 1.0);
        }
        model.AddRow(balance, 0.0, 0.0);
        model.AddRow(outflow, -kInfinity, 0.0);
        model.AddRow(inflow, -kInfinity, 0.0);
      }
    }
  }
  if (maximise && by_min) {  // max t, t <= each state's share
    const int t = model.AddColumn(0, 1, scale, false);
    for (size_t st = 0; st < states; ++st) {
      std::vector<std::pair<int, double>> terms;
      for (int q = 0; q < x_count; ++q)
        if (own[st][static_cast<size_t>(q)] != 0)
          terms.emplace_back(q, -own[st][static_cast<size_t>(q)]);
      for (int64_t c = 0; c < class_count; ++c)
        if (y_of[c] >= 0 && class_state[c] == st) terms.emplace_back(y_of[c], -value_of(c));
      terms.emplace_back(t, 1.0);
      model.AddRow(terms, -kInfinity, 0.0);
    }
  }

  // CBC checks its time limit only between steps: the root LP alone runs to the end, about
  // 5-15 µs per nonzero (1.3 M nonzeros: 20 s). Larger models than the limit allows are not run.
  const double max_nonzeros = CbcMaxNonzeros(time_limit);
  if (static_cast<double>(model.nonzeros()) > max_nonzeros) {
    answer.note = fmt::format(
        "MILP of {} x {} with {} nonzeros is too large for a {:.3g} s time limit (at most "
        "{:.0f}); CBC not run",
        model.row_count(), model.column_count(), model.nonzeros(), time_limit, max_nonzeros);
    return answer;
  }
  const CbcModelPtr owner = model.Load(maximise ? -1 : 1);
  if (!owner) {
    answer.note = "CBC could not create a model";
    return answer;
  }
  const CbcModuleApi& cbc_api = Cbc();
  CbcModelHandle* cbc = owner.get();
  // CBC notices its limit only between steps and overran it by up to 5 s in 60 (the 450-candidate
  // bench world): it gets kCbcTimeShare of the time, so that the whole method stays within it.
  cbc_api.cbc_set_maximum_seconds(cbc, kCbcTimeShare * time_limit);
  if (maximise && over && !whole_weights) {
    // Aggregates are fractions with no common grain worth relying on: prove to round-off only
    // (with whole weights, as the sum's, the objective counts whole cells).
    cbc_api.cbc_set_allowable_gap(cbc, 1e-10 * scale);
    cbc_api.cbc_set_allowable_fraction_gap(cbc, 0.0);
  } else if (maximise || !has_costs || AllWhole(milp.costs)) {
    cbc_api.cbc_set_allowable_gap(cbc, 0.99);  // whole cells, sensors or costs: within 1 is optimal
  }
  // Warm start on every integer column (CBC fixes the ones given, the others at 0, and solves an
  // LP for the continuous ones): `start` with each dropped candidate replaced by its dominator,
  // y where the start brings the class to T, one root.
  std::vector<int> start_columns;
  std::vector<double> start_values;
  std::vector<double> x_start(kept.size(), 0.0);
  for (const uint32_t c : start) {
    const int q = x_of[Dominator(matrix, columns, excluded, milp.costs, c)];
    if (q >= 0) x_start[static_cast<size_t>(q)] = 1.0;
  }
  int root = -1;
  for (int q = 0; q < x_count; ++q) {
    start_columns.push_back(q);
    start_values.push_back(x_start[static_cast<size_t>(q)]);
    if (root < 0 && x_start[static_cast<size_t>(q)] > 0) root = q;
  }
  if (integer_y) {
    for (int64_t c = 0; c < class_count; ++c) {
      if (y_of[c] < 0) continue;
      uint32_t points = 0;
      for (const auto& [q, p] : seers[c]) points += x_start[static_cast<size_t>(q)] > 0 ? p : 0;
      start_columns.push_back(y_of[c]);
      start_values.push_back(points >= threshold ? 1.0 : 0.0);
    }
  }
  for (size_t q = 0; q < r_of.size(); ++q) {
    start_columns.push_back(r_of[q]);
    start_values.push_back(static_cast<int>(q) == root ? 1.0 : 0.0);
  }
  cbc_api.cbc_set_mip_start_i(cbc, static_cast<int>(start_columns.size()), start_columns.data(),
                               start_values.data());

  const std::optional<CbcAnswer> solved =
      SolveInChild(cbc, x_count, kCbcKillShare * time_limit, &answer.note);
  if (!solved) return answer;
  if (std::isfinite(solved->bound)) answer.bound = solved->bound / scale;
  if (!solved->has_solution) {
    answer.note = fmt::format("CBC found no solution ({})", StatusInWords(*solved));
    return answer;
  }
  for (const int q : solved->chosen_columns) answer.chosen.push_back(kept[static_cast<size_t>(q)]);
  answer.proven_optimal = solved->proven_optimal;
  if (!answer.proven_optimal)
    answer.note = fmt::format("not proved optimal: CBC {}", StatusInWords(*solved));
  return answer;
}

}  // namespace

std::vector<bool> DominatedCandidates(const CoverageMatrix& matrix, std::span<const double> costs) {
  return Dominated(matrix, Columns(matrix), costs);
}

MilpAnswer SolveSelectionMilp(const SelectionModel& milp, const std::vector<uint32_t>& start,
                              double time_limit) {
  VANTAGE_CHECK(milp.matrix != nullptr && milp.threshold >= 1 &&
                (milp.costs.empty() || milp.costs.size() == milp.matrix->candidate_count()));
  Cbc();  // a missing CBC module is an internal error (exit 1), not a note on the answer
  try {
    return BuildAndSolve(milp, start, time_limit);
  } catch (const Interrupted&) {
    throw;
  } catch (const std::exception& e) {
    MilpAnswer answer;
    answer.note = fmt::format("CBC failed: {}", e.what());
    return answer;
  }
}

}  // namespace vantage::detail
