// Exact selection as mixed-integer programs, solved by CBC (SYSTEM.md, Select: `exact`).
//
// Maximum coverage, with x_i = candidate i chosen and y_e = element e covered:
//
//   max  sum_i a_i x_i + sum_e w_e y_e
//   s.t. y_e <= sum_{i sees e} x_i   for every element e seen by two or more candidates
//        sum_i x_i <= n,  x_i in {0, 1},  y_e in [0, 1]
//
// where a_i is the weight of the elements that only candidate i sees. The other objectives
// change one part each: budget replaces the cardinality row by sum_i cost_i x_i <= budget;
// k-coverage uses k y_e <= sum_{i sees e} x_i with y binary (elements seen by fewer than k
// candidates dropped, none folded into a_i). Set cover is solved as a sequence of maximum
// coverage problems (SolveSetCover).
#include <coin/Cbc_C_Interface.h>
#include <fmt/format.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <exception>
#include <limits>
#include <memory>
#include <optional>
#include <string>

#include "select/cbc_answer.hpp"
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
// keeps an optimum of "at most n sensors", of a budget, and of set cover. `costs` empty: unit.
std::vector<bool> Dominated(const CoverageMatrix& matrix,
                            const std::vector<std::vector<uint32_t>>& columns,
                            std::span<const double> costs) {
  const size_t m = matrix.candidate_count();
  std::vector<bool> dominated(m, false);
  for (uint32_t i = 0; i < m; ++i) {
    const std::vector<uint32_t>& row = matrix.Row(i);
    if (row.empty()) {
      dominated[i] = true;  // the caller only solves when some candidate sees something
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
    return candidate;  // nothing to map to: the caller leaves it out of the warm start
  }
  for (const uint32_t j : columns[RarestElement(matrix, columns, candidate)]) {
    if (!excluded[j] && cheap_enough(j) && matrix.IsSubset(candidate, j)) return j;
  }
  return candidate;
}

// Which MILP to build (see the top of this file).
struct MilpSpec {
  int k = 1;                      // k-coverage when >= 2 (max coverage only)
  std::span<const double> costs;  // budget row coefficients; empty = cardinality (unit)
  double capacity = 0;            // n, or the budget
};

struct CbcOutcome {
  std::vector<uint32_t> chosen;  // candidate indices (empty when CBC found no solution)
  // CBC's bound on the objective: an upper bound (max) or a lower bound (set cover); NaN if none.
  double bound = std::numeric_limits<double>::quiet_NaN();
  bool proven_optimal = false;
  std::string note;
};


// The column-wise MILP both exact models hand CBC: x (candidates) are binary; y (cells) integer
// when a cell's count matters (k >= 2 or pixel counts), else continuous. Null when CBC cannot
// create a model.
CbcModelPtr LoadedCbcModel(int x_count, int y_count, int row_count,
                           const std::vector<CoinBigIndex>& starts, const std::vector<int>& indices,
                           const std::vector<double>& values,
                           const std::vector<double>& column_lower,
                           const std::vector<double>& column_upper,
                           const std::vector<double>& objective,
                           const std::vector<double>& row_lower,
                           const std::vector<double>& row_upper, bool integer_cells,
                           double sense) {
  CbcModelPtr model(Cbc_newModel());
  if (!model) return model;
  Cbc_Model* cbc = model.get();
  Cbc_loadProblem(cbc, x_count + y_count, row_count, starts.data(), indices.data(), values.data(),
                  column_lower.data(), column_upper.data(), objective.data(), row_lower.data(),
                  row_upper.data());
  for (int q = 0; q < x_count; ++q) Cbc_setInteger(cbc, q);
  if (integer_cells) {
    for (int r = 0; r < y_count; ++r) Cbc_setInteger(cbc, x_count + r);
  }
  Cbc_setObjSense(cbc, sense);
  Cbc_setLogLevel(cbc, 0);
  Cbc_setParameter(cbc, "timeMode", "elapsed");  // wall clock, as the time limits mean
  return model;
}

CbcOutcome RunCbc(const CoverageMatrix& matrix,
                  const MilpSpec& spec,
                  const std::vector<uint32_t>& start,
                  double time_limit) {
  CbcOutcome outcome;
  const size_t m = matrix.candidate_count();
  const bool has_costs = !spec.costs.empty();
  const auto resource = [&](uint32_t i) { return has_costs ? spec.costs[i] : 1.0; };
  const std::vector<std::vector<uint32_t>> columns = Columns(matrix);
  // k-coverage: a dominated candidate can still be the k-th seer, so only empty rows go.
  std::vector<bool> excluded(m, false);
  if (spec.k == 1) {
    excluded = Dominated(matrix, columns, spec.costs);
  } else {
    for (uint32_t i = 0; i < m; ++i) excluded[i] = matrix.Row(i).empty();
  }
  for (uint32_t i = 0; i < m; ++i) {
    if (resource(i) > spec.capacity) excluded[i] = true;  // unaffordable
  }
  std::vector<uint32_t> kept;
  std::vector<int> column_of(m, -1);
  double kept_resource = 0;
  for (uint32_t i = 0; i < m; ++i) {
    if (excluded[i]) continue;
    column_of[i] = static_cast<int>(kept.size());
    kept.push_back(i);
    kept_resource += resource(i);
  }
  if (kept.empty()) {
    outcome.note = "no candidate left after the reduction";
    return outcome;
  }
  if (kept_resource <= spec.capacity) {
    // All kept candidates fit together: nothing can cover more.
    outcome.chosen = kept;
    outcome.bound = static_cast<double>(KCoveredWeight(matrix, kept, spec.k));
    outcome.proven_optimal = true;
    outcome.note = "solved by dominance reduction";
    return outcome;
  }

  // Re-merge the elements over the kept candidates only. With point counts the elements stay
  // (two elements seen by the same candidates may differ in their counts; k >= 2 keeps every
  // candidate that sees anything, so the merge would find the same classes anyway).
  std::vector<std::span<const uint32_t>> kept_rows;
  kept_rows.reserve(kept.size());
  for (const uint32_t i : kept) kept_rows.emplace_back(matrix.Row(i));
  std::vector<int64_t> class_of;
  if (matrix.has_counts()) {
    class_of.assign(matrix.element_count(), -1);
    for (const std::span<const uint32_t> row : kept_rows) {
      for (const uint32_t e : row) class_of[e] = e;
    }
  } else {
    class_of = RefinePartition(matrix.element_count(), kept_rows);
  }
  int64_t class_count = 0;
  for (const int64_t c : class_of) class_count = std::max(class_count, c + 1);
  std::vector<double> class_weight(class_count, 0.0);
  std::vector<uint32_t> class_seers(class_count, 0);
  std::vector<std::vector<uint32_t>> classes_of_column(kept.size());
  std::vector<std::vector<uint32_t>> counts_of_column(kept.size());  // each class's Count
  std::vector<int64_t> last_column(class_count, -1);
  for (size_t e = 0; e < class_of.size(); ++e) {
    // -1: seen only by unaffordable candidates (budget); never coverable.
    if (class_of[e] >= 0) class_weight[class_of[e]] += matrix.Weight(static_cast<uint32_t>(e));
  }
  for (size_t q = 0; q < kept.size(); ++q) {
    const std::vector<uint32_t>& row = matrix.Row(kept[q]);
    for (size_t j = 0; j < row.size(); ++j) {
      const int64_t c = class_of[row[j]];
      if (last_column[c] == static_cast<int64_t>(q)) continue;
      last_column[c] = static_cast<int64_t>(q);
      classes_of_column[q].push_back(static_cast<uint32_t>(c));
      counts_of_column[q].push_back(matrix.Count(kept[q], j));
      class_seers[c] += counts_of_column[q].back();
    }
  }
  // y variables: k = 1, classes seen by >= 2 kept candidates (the others fold into a_i);
  // k >= 2, classes seen by >= k (the others can never count). With point counts "seen by"
  // sums the counts: k y_c <= sum_q count_qc x_q (min-points, P = k).
  const auto min_seers = static_cast<uint32_t>(std::max(2, spec.k));
  std::vector<int> y_of_class(class_count, -1);
  std::vector<double> y_weight;
  for (int64_t c = 0; c < class_count; ++c) {
    if (class_seers[c] >= min_seers) {
      y_of_class[c] = static_cast<int>(y_weight.size());
      y_weight.push_back(class_weight[c]);
    }
  }
  const int x_count = static_cast<int>(kept.size());
  const int y_count = static_cast<int>(y_weight.size());
  const int row_count = y_count + 1;  // coupling rows, then the budget/cardinality/goal row
  std::vector<CoinBigIndex> starts{0};
  std::vector<int> indices;
  std::vector<double> values;
  std::vector<double> objective;
  for (int q = 0; q < x_count; ++q) {
    double own = 0;
    std::vector<std::pair<int, double>> rows;  // coupling row, -count
    for (size_t t = 0; t < classes_of_column[q].size(); ++t) {
      const uint32_t c = classes_of_column[q][t];
      if (y_of_class[c] >= 0) {
        rows.emplace_back(y_of_class[c], -static_cast<double>(counts_of_column[q][t]));
      } else if (spec.k == 1) {
        own += class_weight[c];
      }
    }
    std::sort(rows.begin(), rows.end());
    for (const auto& [r, value] : rows) {
      indices.push_back(r);
      values.push_back(value);
    }
    if (resource(kept[q]) != 0) {
      indices.push_back(y_count);
      values.push_back(resource(kept[q]));
    }
    starts.push_back(static_cast<CoinBigIndex>(indices.size()));
    objective.push_back(own);
  }
  for (int r = 0; r < y_count; ++r) {
    indices.push_back(r);
    values.push_back(static_cast<double>(spec.k));
    starts.push_back(static_cast<CoinBigIndex>(indices.size()));
    objective.push_back(y_weight[r]);
  }
  const std::vector<double> column_lower(x_count + y_count, 0.0);
  const std::vector<double> column_upper(x_count + y_count, 1.0);
  std::vector<double> row_lower(row_count, -std::numeric_limits<double>::max());
  std::vector<double> row_upper(row_count, 0.0);
  row_upper[y_count] = spec.capacity;  // budget or cardinality

  // CBC checks its time limit only between steps: the root LP alone runs to the end, about
  // 5-15 µs per nonzero here (1.3 M nonzeros: 20 s). Larger models than the time limit allows
  // are not attempted; the answer is then the start set with the simple bound.
  const double max_nonzeros = CbcMaxNonzeros(time_limit);
  if (static_cast<double>(indices.size()) > max_nonzeros) {
    outcome.note = fmt::format(
        "MILP of {} x {} with {} nonzeros is too large for a {} s time limit (at most {:.0f}); "
        "CBC not run",
        row_count, x_count + y_count, indices.size(), time_limit, max_nonzeros);
    return outcome;
  }

  CbcModelPtr model = LoadedCbcModel(x_count, y_count, row_count, starts, indices, values,
                                     column_lower, column_upper, objective, row_lower, row_upper,
                                     spec.k >= 2, -1);  // maximise
  if (!model) {
    outcome.note = "CBC could not create a model";
    return outcome;
  }
  Cbc_Model* cbc = model.get();
  // CBC notices its limit only between steps and overran it by up to 5 s in 60 (the 450-candidate
  // bench world): it gets 85 % of the time, so that the whole method stays within the limit.
  Cbc_setMaximumSeconds(cbc, kCbcTimeShare * time_limit);
  // Objectives are whole cells or whole sensors, so an incumbent within 1 of the bound is optimal.
  Cbc_setAllowableGap(cbc, 0.99);
  // Warm start: the start set, each dominated candidate replaced by a kept superset (k = 1), and
  // for k >= 2 the y of every class the start k-covers. Every integer column gets a value: CBC
  // completes a partial start by solving an LP over the columns left out, without looking at its
  // time limit (minutes on the 450-candidate world).
  std::vector<double> start_x(x_count, 0.0);
  for (const uint32_t c : start) {
    const int q = column_of[Dominator(matrix, columns, excluded, spec.costs, c)];
    if (q >= 0) start_x[q] = 1.0;
  }
  std::vector<int> start_columns;
  std::vector<double> start_values;
  for (int q = 0; q < x_count; ++q) {
    start_columns.push_back(q);
    start_values.push_back(start_x[q]);
  }
  if (spec.k >= 2) {
    std::vector<uint32_t> start_seers(class_count, 0);
    for (int q = 0; q < x_count; ++q) {
      if (start_x[q] == 0.0) continue;
      for (size_t t = 0; t < classes_of_column[q].size(); ++t)
        start_seers[classes_of_column[q][t]] += counts_of_column[q][t];
    }
    for (int64_t c = 0; c < class_count; ++c) {
      if (y_of_class[c] < 0) continue;
      start_columns.push_back(x_count + y_of_class[c]);
      start_values.push_back(start_seers[c] >= static_cast<uint32_t>(spec.k) ? 1.0 : 0.0);
    }
  }
  Cbc_setMIPStartI(cbc, static_cast<int>(start_columns.size()), start_columns.data(),
                   start_values.data());

  const std::optional<CbcAnswer> answer =
      SolveInChild(cbc, x_count, kCbcKillShare * time_limit, &outcome.note);
  if (!answer) return outcome;
  const CbcAnswer& solved = *answer;
  if (std::isfinite(solved.bound)) outcome.bound = solved.bound;
  if (!solved.has_solution) {
    outcome.note = fmt::format("CBC found no solution ({})", StatusInWords(solved));
    return outcome;
  }
  for (const int q : solved.chosen_columns) outcome.chosen.push_back(kept[q]);
  outcome.proven_optimal = solved.proven_optimal;
  if (!outcome.proven_optimal)
    outcome.note = fmt::format("not proved optimal: CBC {}", StatusInWords(solved));
  return outcome;
}

CbcOutcome GuardedCbc(const CoverageMatrix& matrix,
                      const MilpSpec& spec,
                      const std::vector<uint32_t>& start,
                      double time_limit) {
  try {
    return RunCbc(matrix, spec, start, time_limit);
  } catch (const Interrupted&) {
    throw;
  } catch (const std::exception& e) {
    CbcOutcome outcome;
    outcome.note = fmt::format("CBC failed: {}", e.what());
    return outcome;
  } catch (...) {
    CbcOutcome outcome;
    outcome.note = "CBC failed";
    return outcome;
  }
}

// Number of n-subsets of m items, or +inf beyond `cap`.
// The MILP for at most n sensors (k-coverage when k >= 2); an answer with more than n sensors,
// which CBC should never return, is dropped rather than trusted.
CbcOutcome CardinalityCbc(const CoverageMatrix& matrix, int k, size_t n,
                          const std::vector<uint32_t>& start, double time_limit) {
  MilpSpec spec;
  spec.k = k;
  spec.capacity = static_cast<double>(n);
  CbcOutcome outcome = GuardedCbc(matrix, spec, start, time_limit);
  if (outcome.chosen.size() > n) {
    outcome = CbcOutcome{};
    outcome.note = "CBC returned more than n sensors";
  }
  return outcome;
}

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

// Whether every value is a whole number (then objective values are too, and CBC may stop
// within 1 of its bound).
bool AllWhole(std::span<const double> values) {
  return std::all_of(values.begin(), values.end(),
                     [](double v) { return v == std::floor(v); });
}

}  // namespace

GoalResult SolveGoalMilp(const CoverageMatrix& matrix, int k, std::span<const double> costs,
                         uint64_t goal_cells, const std::vector<uint32_t>& start,
                         double time_limit) {
  VANTAGE_CHECK(k >= 1 && goal_cells >= 1 && (costs.empty() || costs.size() ==
                                                                   matrix.candidate_count()));
  GoalResult result;
  const size_t m = matrix.candidate_count();
  const auto cost = [&](uint32_t i) { return costs.empty() ? 1.0 : costs[i]; };
  const std::vector<std::vector<uint32_t>> columns = Columns(matrix);
  // k = 1: a dominated candidate is replaced by its dominator in any answer at no higher cost
  // and no less coverage; k >= 2 (or point counts): it can still be the k-th seer.
  std::vector<bool> excluded(m, false);
  if (k == 1 && !matrix.has_counts()) {
    excluded = Dominated(matrix, columns, costs);
  } else {
    for (uint32_t i = 0; i < m; ++i) excluded[i] = matrix.Row(i).empty();
  }
  std::vector<uint32_t> kept;
  std::vector<int> column_of(m, -1);
  for (uint32_t i = 0; i < m; ++i) {
    if (excluded[i]) continue;
    column_of[i] = static_cast<int>(kept.size());
    kept.push_back(i);
  }
  // Classes of elements seen by the same kept candidates (the elements themselves with point
  // counts or k >= 2, where they are already merged over every candidate that sees anything).
  std::vector<int64_t> class_of(matrix.element_count(), -1);
  if (k == 1 && !matrix.has_counts()) {
    std::vector<std::span<const uint32_t>> kept_rows;
    for (const uint32_t i : kept) kept_rows.emplace_back(matrix.Row(i));
    class_of = RefinePartition(matrix.element_count(), kept_rows);
  } else {
    for (const uint32_t i : kept)
      for (const uint32_t e : matrix.Row(i)) class_of[e] = e;
  }
  int64_t class_count = 0;
  for (const int64_t c : class_of) class_count = std::max(class_count, c + 1);
  std::vector<double> class_weight(class_count, 0.0);
  std::vector<uint32_t> class_seers(class_count, 0);
  std::vector<std::vector<std::pair<uint32_t, uint32_t>>> entries(kept.size());  // class, count
  for (size_t e = 0; e < class_of.size(); ++e)
    if (class_of[e] >= 0) class_weight[class_of[e]] += matrix.Weight(static_cast<uint32_t>(e));
  std::vector<int64_t> last_column(class_count, -1);
  for (size_t q = 0; q < kept.size(); ++q) {
    const std::vector<uint32_t>& row = matrix.Row(kept[q]);
    for (size_t j = 0; j < row.size(); ++j) {
      const int64_t c = class_of[row[j]];
      if (last_column[c] == static_cast<int64_t>(q)) continue;
      last_column[c] = static_cast<int64_t>(q);
      entries[q].emplace_back(static_cast<uint32_t>(c), matrix.Count(kept[q], j));
      class_seers[c] += entries[q].back().second;
    }
  }
  const auto threshold = static_cast<uint32_t>(k);
  double coverable = 0;
  for (int64_t c = 0; c < class_count; ++c)
    if (class_seers[c] >= threshold) coverable += class_weight[c];
  if (static_cast<double>(goal_cells) > coverable) {
    result.note = "the goal is above what all candidates reach together";
    return result;
  }
  // Every coverable class needed (a goal of all that can be seen): covering rows
  // sum_q count x_q >= k, pure set covering, whose structure CBC's cuts know. Otherwise
  // k y_c <= sum_q count x_q and the goal row sum_c w_c y_c (+ the weight of the classes only
  // x_q sees, for k = 1) >= goal; y continuous for k = 1 (x integer makes it 0 or up to 1 where
  // covered), binary for k >= 2.
  const bool cover_all = static_cast<double>(goal_cells) == coverable;
  const uint32_t min_seers = cover_all ? threshold : std::max<uint32_t>(2, threshold);
  std::vector<int> row_of_class(class_count, -1);
  std::vector<double> y_weight;
  for (int64_t c = 0; c < class_count; ++c) {
    if (class_seers[c] >= threshold && (cover_all || class_seers[c] >= min_seers)) {
      row_of_class[c] = static_cast<int>(y_weight.size());
      y_weight.push_back(class_weight[c]);
    }
  }
  const int x_count = static_cast<int>(kept.size());
  const int class_rows = static_cast<int>(y_weight.size());
  const int y_count = cover_all ? 0 : class_rows;
  const int row_count = class_rows + (cover_all ? 0 : 1);
  const int goal_row = class_rows;
  std::vector<CoinBigIndex> starts{0};
  std::vector<int> indices;
  std::vector<double> values;
  std::vector<double> objective;
  for (int q = 0; q < x_count; ++q) {
    double own = 0;
    for (const auto& [c, count] : entries[q]) {
      if (row_of_class[c] >= 0) {
        indices.push_back(row_of_class[c]);
        values.push_back(cover_all ? static_cast<double>(count) : -static_cast<double>(count));
      } else if (!cover_all && k == 1) {
        own += class_weight[c];
      }
    }
    if (own != 0) {
      indices.push_back(goal_row);
      values.push_back(own);
    }
    starts.push_back(static_cast<CoinBigIndex>(indices.size()));
    objective.push_back(cost(kept[q]));
  }
  for (int r = 0; r < y_count; ++r) {
    indices.push_back(r);
    values.push_back(static_cast<double>(k));
    indices.push_back(goal_row);
    values.push_back(y_weight[r]);
    starts.push_back(static_cast<CoinBigIndex>(indices.size()));
    objective.push_back(0.0);
  }
  const double max_nonzeros = CbcMaxNonzeros(time_limit);
  if (static_cast<double>(indices.size()) > max_nonzeros) {
    result.note = fmt::format(
        "goal MILP of {} x {} with {} nonzeros is too large for a {:.3g} s time limit (at most "
        "{:.0f}); CBC not run",
        row_count, x_count + y_count, indices.size(), time_limit, max_nonzeros);
    return result;
  }
  const std::vector<double> column_lower(x_count + y_count, 0.0);
  const std::vector<double> column_upper(x_count + y_count, 1.0);
  std::vector<double> row_lower(row_count), row_upper(row_count);
  for (int r = 0; r < class_rows; ++r) {
    row_lower[r] = cover_all ? static_cast<double>(k) : -std::numeric_limits<double>::max();
    row_upper[r] = cover_all ? std::numeric_limits<double>::max() : 0.0;
  }
  if (!cover_all) {
    row_lower[goal_row] = static_cast<double>(goal_cells);
    row_upper[goal_row] = std::numeric_limits<double>::max();
  }
  CbcModelPtr model = LoadedCbcModel(x_count, y_count, row_count, starts, indices, values,
                                     column_lower, column_upper, objective, row_lower, row_upper,
                                     k >= 2 || matrix.has_counts(), 1);  // minimise
  if (!model) {
    result.note = "CBC could not create a model";
    return result;
  }
  Cbc_Model* cbc = model.get();
  Cbc_setMaximumSeconds(cbc, kCbcTimeShare * time_limit);
  const bool whole = costs.empty() || AllWhole(costs);
  if (whole) Cbc_setAllowableGap(cbc, 0.99);  // whole sensors or whole costs
  // Warm start: `start` with each dominated candidate replaced by its dominator (no less
  // coverage), and every y at what the start reaches; every column gets a value.
  std::vector<double> start_values(x_count + y_count, 0.0);
  for (const uint32_t c : start) {
    const int q = column_of[Dominator(matrix, columns, excluded, costs, c)];
    if (q >= 0) start_values[q] = 1.0;
  }
  std::vector<uint32_t> start_seers(class_count, 0);
  for (int q = 0; q < x_count; ++q) {
    if (start_values[q] == 0.0) continue;
    for (const auto& [c, count] : entries[q]) start_seers[c] += count;
  }
  for (int64_t c = 0; c < class_count; ++c) {
    if (row_of_class[c] >= 0 && !cover_all)
      start_values[x_count + row_of_class[c]] = start_seers[c] >= threshold ? 1.0 : 0.0;
  }
  std::vector<int> start_columns(x_count + y_count);
  for (int j = 0; j < x_count + y_count; ++j) start_columns[j] = j;
  Cbc_setMIPStartI(cbc, x_count + y_count, start_columns.data(), start_values.data());
  const std::optional<CbcAnswer> answer =
      SolveInChild(cbc, x_count, kCbcKillShare * time_limit, &result.note);
  if (!answer) return result;
  if (std::isfinite(answer->bound))
    result.lower_bound = whole ? std::ceil(answer->bound - 1e-6) : answer->bound - 1e-9;
  result.lower_bound = std::max(0.0, result.lower_bound);
  if (!answer->has_solution) {
    result.note = fmt::format("CBC found no solution ({})", StatusInWords(*answer));
    return result;
  }
  for (const int q : answer->chosen_columns) result.chosen.push_back(kept[q]);
  // Trusted only when it reaches the goal in integers (CBC's tolerances are not whole cells).
  if (KCoveredWeight(matrix, result.chosen, k) < goal_cells) {
    result.chosen.clear();
    result.note = "CBC's answer misses the goal by round-off";
    return result;
  }
  result.proven_optimal = answer->proven_optimal;
  if (!result.proven_optimal)
    result.note = fmt::format("not proved optimal: CBC {}", StatusInWords(*answer));
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
    CbcOutcome outcome = CardinalityCbc(matrix, 1, n, start, time_limit);
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
  CbcOutcome outcome = CardinalityCbc(matrix, k, n, start, cbc_seconds);
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
  MilpSpec spec;
  spec.costs = costs;
  spec.capacity = budget;
  CbcOutcome outcome = GuardedCbc(matrix, spec, start, time_limit);
  if (!outcome.chosen.empty() && TotalCost(costs, outcome.chosen) > budget) {
    // CBC's feasibility tolerance let the costs exceed the budget by round-off: not an answer.
    const double bound = outcome.bound;
    outcome = CbcOutcome{};
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
