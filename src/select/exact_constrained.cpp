// Exact selection under installation constraints (docs/constraints.md), solved by CBC:
//
//   max  sum_i a_i x_i + sum_e w_e y_e
//   s.t. y_e <= sum_{i sees e} x_i              every element seen by two or more candidates
//        sum_i x_i <= n
//        x_a + x_b <= 1                         every conflicting pair
//   and with a calibration rule, a single-commodity flow over the overlap edges (both directions):
//        sum_i r_i = 1,  r_i <= x_i             one root among the chosen
//        s_i <= n r_i,   sum_i s_i = sum_i x_i  the root supplies one unit per chosen sensor
//        out_i - in_i = s_i - x_i               every chosen sensor keeps one unit
//        out_i <= (n - 1) x_i, in_i <= (n - 1) x_i   flow only through chosen sensors
//   x, r binary; y in [0, 1]; s, f >= 0. A flow exists exactly when every chosen sensor is
//   reached from the root along edges between chosen sensors: the chosen graph is connected.
//
// No dominance reduction (a dominated candidate may be the only one that fits the constraints).
// Candidates that see nothing are left out: they join no edge and add no cell.
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

Outcome RunCbc(const CoverageMatrix& matrix, const Feasibility& feasible, size_t n,
               const std::vector<uint32_t>& start, double time_limit) {
  Outcome outcome;
  const size_t m = matrix.candidate_count();
  std::vector<uint32_t> kept;
  std::vector<int> x_of(m, -1);
  for (uint32_t i = 0; i < m; ++i) {
    if (matrix.Row(i).empty()) continue;
    x_of[i] = static_cast<int>(kept.size());
    kept.push_back(i);
  }
  if (kept.empty()) {
    outcome.note = "no candidate sees anything";
    return outcome;
  }
  std::vector<std::vector<int>> seers(matrix.element_count());
  for (const uint32_t i : kept)
    for (const uint32_t e : matrix.Row(i)) seers[e].push_back(x_of[i]);
  std::vector<double> own(kept.size(), 0.0);
  for (uint32_t e = 0; e < seers.size(); ++e)
    if (seers[e].size() == 1) own[static_cast<size_t>(seers[e][0])] += matrix.Weight(e);

  Model model;
  const int x_count = static_cast<int>(kept.size());
  for (int q = 0; q < x_count; ++q) model.AddColumn(0, 1, own[static_cast<size_t>(q)], true);
  for (uint32_t e = 0; e < seers.size(); ++e) {
    if (seers[e].size() < 2) continue;
    const int y = model.AddColumn(0, 1, matrix.Weight(e), false);
    std::vector<int> columns{y};
    std::vector<double> values{1.0};
    for (const int q : seers[e]) {
      columns.push_back(q);
      values.push_back(-1.0);
    }
    model.AddRow(std::move(columns), std::move(values), 'L', 0.0);
  }
  {
    std::vector<int> all(static_cast<size_t>(x_count));
    for (int q = 0; q < x_count; ++q) all[static_cast<size_t>(q)] = q;
    model.AddRow(all, std::vector<double>(all.size(), 1.0), 'L', static_cast<double>(n));
  }
  for (const Conflict& c : feasible.conflicts()) {
    if (x_of[c.a] < 0 || x_of[c.b] < 0) continue;
    model.AddRow({x_of[c.a], x_of[c.b]}, {1.0, 1.0}, 'L', 1.0);
  }
  const double nd = static_cast<double>(n);
  std::vector<int> r_of, s_of;
  if (feasible.has_calibration() && n >= 2) {
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
  Cbc_setAllowableGap(cbc, 0.99);  // whole cells: within 1 of the bound is optimal
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

}  // namespace

ExactResult SolveExactConstrained(const CoverageMatrix& matrix, const Feasibility& feasible,
                                  size_t n, const std::vector<uint32_t>& start,
                                  double time_limit) {
  VANTAGE_CHECK(n >= 1 && feasible.IsFeasible(start) && start.size() <= n);
  const auto start_time = std::chrono::steady_clock::now();
  ExactResult result;
  result.chosen = start;
  const uint64_t start_cells = matrix.CoveredWeight(start);
  // Constraints only remove sets: the unconstrained bound holds.
  result.upper_bound = std::max(GreedyUpperBound(matrix, start, n), start_cells);
  if (start_cells == result.upper_bound) {
    result.proven_optimal = true;
    result.note = "start meets the unconstrained bound";
    return result;
  }
  Outcome outcome;
  try {
    outcome = RunCbc(matrix, feasible, n, start, time_limit);
  } catch (const Interrupted&) {
    throw;
  } catch (const std::exception& e) {
    outcome = Outcome{};
    outcome.note = fmt::format("CBC failed: {}", e.what());
  }
  result.note = outcome.note;
  // CBC's answer, trusted only when it satisfies the constraints (tolerances), padded up to n
  // with whatever still fits.
  if (!outcome.chosen.empty() && outcome.chosen.size() <= n && feasible.IsFeasible(outcome.chosen)) {
    std::vector<uint32_t> found = outcome.chosen;
    for (uint32_t c = 0; c < matrix.candidate_count() && found.size() < n; ++c)
      if (feasible.CanAdd(found, c)) found.push_back(c);
    if (matrix.CoveredWeight(found) > start_cells) result.chosen = std::move(found);
  } else if (!outcome.chosen.empty()) {
    result.note = "CBC's answer breaks a constraint by round-off; kept the start";
    outcome.proven_optimal = false;
  }
  const uint64_t cells = matrix.CoveredWeight(result.chosen);
  if (std::isfinite(outcome.bound)) {
    const double bound_cells = std::floor(outcome.bound + 1e-6);
    if (bound_cells >= static_cast<double>(cells) &&
        bound_cells < static_cast<double>(result.upper_bound))
      result.upper_bound = static_cast<uint64_t>(bound_cells);
  }
  if (outcome.proven_optimal && cells >= matrix.CoveredWeight(outcome.chosen))
    result.upper_bound = cells;
  result.upper_bound = std::max(result.upper_bound, cells);
  result.proven_optimal = cells == result.upper_bound;
  if (!result.proven_optimal) {
    // The unconstrained Lagrangian bound in the time left.
    const double left =
        time_limit -
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start_time).count();
    if (left > 0.05) {
      const LagrangianBound lagrangian =
          LagrangianUpperBound(matrix, n, cells, kLagrangianSteps, 0.9 * left);
      result.upper_bound = std::max(cells, std::min(result.upper_bound, lagrangian.upper_bound));
      result.proven_optimal = cells == result.upper_bound;
    }
  }
  return result;
}

}  // namespace vantage::detail
