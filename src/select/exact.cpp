// Maximum coverage as a mixed-integer program, solved by CBC (SYSTEM.md, Select: `exact`).
//
//   max  sum_i a_i x_i + sum_e w_e y_e
//   s.t. y_e <= sum_{i sees e} x_i   for every element e seen by two or more candidates
//        sum_i x_i <= n,  x_i in {0, 1},  y_e in [0, 1]
//
// where a_i is the weight of the elements that only candidate i sees.
#include <coin/Cbc_C_Interface.h>
#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <exception>
#include <limits>
#include <memory>

#include "select/methods.hpp"
#include "vantage/error.hpp"

namespace vantage::detail {
namespace {

// Largest MILP (in constraint matrix nonzeros) given to CBC per second of time limit; see RunCbc.
constexpr double kCbcNonzerosPerSecond = 40000;
constexpr double kMinCbcNonzeros = 20000;

struct CbcModelDeleter {
  void operator()(Cbc_Model* model) const { Cbc_deleteModel(model); }
};
using CbcModelPtr = std::unique_ptr<Cbc_Model, CbcModelDeleter>;

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

// Candidate i is dominated when another sees a strict superset, or the same set at a lower index.
// Dominance is a strict partial order, so every dominated candidate sits below a kept one and
// dropping all of them at once keeps an optimum of "at most n sensors".
std::vector<bool> Dominated(const CoverageMatrix& matrix,
                            const std::vector<std::vector<uint32_t>>& columns) {
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
      if ((size_j > row.size() || (size_j == row.size() && j < i)) && matrix.IsSubset(i, j)) {
        dominated[i] = true;
        break;
      }
    }
  }
  return dominated;
}

// A kept candidate that sees everything `candidate` sees (itself when kept).
uint32_t Dominator(const CoverageMatrix& matrix,
                   const std::vector<std::vector<uint32_t>>& columns,
                   const std::vector<bool>& dominated,
                   uint32_t candidate) {
  if (!dominated[candidate]) return candidate;
  if (matrix.Row(candidate).empty()) {
    for (uint32_t j = 0; j < matrix.candidate_count(); ++j) {
      if (!dominated[j]) return j;
    }
  }
  for (const uint32_t j : columns[RarestElement(matrix, columns, candidate)]) {
    if (!dominated[j] && matrix.IsSubset(candidate, j)) return j;
  }
  VANTAGE_CHECK(false);
  return candidate;
}

struct CbcOutcome {
  std::vector<uint32_t> chosen;  // candidate indices (empty when CBC found no solution)
  double bound = std::numeric_limits<double>::infinity();
  bool proven_optimal = false;
  std::string note;
};

CbcOutcome RunCbc(const CoverageMatrix& matrix,
                  size_t n,
                  const std::vector<uint32_t>& start,
                  double time_limit) {
  CbcOutcome outcome;
  const std::vector<std::vector<uint32_t>> columns = Columns(matrix);
  const std::vector<bool> dominated = Dominated(matrix, columns);
  std::vector<uint32_t> kept;
  std::vector<int> column_of(matrix.candidate_count(), -1);
  for (uint32_t i = 0; i < matrix.candidate_count(); ++i) {
    if (dominated[i]) continue;
    column_of[i] = static_cast<int>(kept.size());
    kept.push_back(i);
  }
  if (kept.size() <= n) {  // all undominated candidates together see every seen cell
    outcome.chosen = kept;
    outcome.bound = static_cast<double>(matrix.seen_weight());
    outcome.proven_optimal = true;
    outcome.note = "solved by dominance reduction";
    return outcome;
  }

  // Re-merge the elements over the kept candidates only.
  std::vector<std::span<const uint32_t>> kept_rows;
  kept_rows.reserve(kept.size());
  for (const uint32_t i : kept) kept_rows.emplace_back(matrix.Row(i));
  const std::vector<int64_t> class_of = RefinePartition(matrix.element_count(), kept_rows);
  int64_t class_count = 0;
  for (const int64_t c : class_of) class_count = std::max(class_count, c + 1);
  std::vector<double> class_weight(class_count, 0.0);
  std::vector<uint32_t> class_seers(class_count, 0);
  std::vector<std::vector<uint32_t>> classes_of_column(kept.size());
  std::vector<int64_t> last_column(class_count, -1);
  for (size_t e = 0; e < class_of.size(); ++e) {
    VANTAGE_CHECK(class_of[e] >= 0);  // every element is seen by a kept candidate
    class_weight[class_of[e]] += matrix.Weight(static_cast<uint32_t>(e));
  }
  for (size_t q = 0; q < kept.size(); ++q) {
    for (const uint32_t e : matrix.Row(kept[q])) {
      const int64_t c = class_of[e];
      if (last_column[c] == static_cast<int64_t>(q)) continue;
      last_column[c] = static_cast<int64_t>(q);
      classes_of_column[q].push_back(static_cast<uint32_t>(c));
      ++class_seers[c];
    }
  }
  // y variables for classes seen by >= 2 kept candidates; the others fold into a_i.
  std::vector<int> y_of_class(class_count, -1);
  std::vector<double> y_weight;
  for (int64_t c = 0; c < class_count; ++c) {
    if (class_seers[c] >= 2) {
      y_of_class[c] = static_cast<int>(y_weight.size());
      y_weight.push_back(class_weight[c]);
    }
  }
  const int x_count = static_cast<int>(kept.size());
  const int y_count = static_cast<int>(y_weight.size());
  const int row_count = y_count + 1;  // coupling rows, then the cardinality row
  std::vector<CoinBigIndex> starts{0};
  std::vector<int> indices;
  std::vector<double> values;
  std::vector<double> objective;
  for (int q = 0; q < x_count; ++q) {
    double own = 0;
    std::vector<int> rows;
    for (const uint32_t c : classes_of_column[q]) {
      if (y_of_class[c] >= 0) {
        rows.push_back(y_of_class[c]);
      } else {
        own += class_weight[c];
      }
    }
    std::sort(rows.begin(), rows.end());
    for (const int r : rows) {
      indices.push_back(r);
      values.push_back(-1.0);
    }
    indices.push_back(y_count);
    values.push_back(1.0);
    starts.push_back(static_cast<CoinBigIndex>(indices.size()));
    objective.push_back(own);
  }
  for (int r = 0; r < y_count; ++r) {
    indices.push_back(r);
    values.push_back(1.0);
    starts.push_back(static_cast<CoinBigIndex>(indices.size()));
    objective.push_back(y_weight[r]);
  }
  const std::vector<double> column_lower(x_count + y_count, 0.0);
  const std::vector<double> column_upper(x_count + y_count, 1.0);
  std::vector<double> row_lower(row_count, -std::numeric_limits<double>::max());
  std::vector<double> row_upper(row_count, 0.0);
  row_upper[y_count] = static_cast<double>(n);

  // CBC checks its time limit only between steps: the root LP alone runs to the end, about
  // 5-15 µs per nonzero here (1.3 M nonzeros: 20 s). Larger models than the time limit allows
  // are not attempted; the answer is then the start set with the simple bound.
  const double max_nonzeros = std::max(kMinCbcNonzeros, kCbcNonzerosPerSecond * time_limit);
  if (static_cast<double>(indices.size()) > max_nonzeros) {
    outcome.note = fmt::format(
        "MILP of {} x {} with {} nonzeros is too large for a {} s time limit (at most {:.0f}); "
        "CBC not run",
        row_count, x_count + y_count, indices.size(), time_limit, max_nonzeros);
    return outcome;
  }

  CbcModelPtr model(Cbc_newModel());
  if (!model) {
    outcome.note = "CBC could not create a model";
    return outcome;
  }
  Cbc_Model* cbc = model.get();
  Cbc_loadProblem(cbc, x_count + y_count, row_count, starts.data(), indices.data(), values.data(),
                  column_lower.data(), column_upper.data(), objective.data(), row_lower.data(),
                  row_upper.data());
  for (int q = 0; q < x_count; ++q) Cbc_setInteger(cbc, q);
  Cbc_setObjSense(cbc, -1);  // maximise
  Cbc_setLogLevel(cbc, 0);
  Cbc_setParameter(cbc, "timeMode", "elapsed");  // wall clock, as options.time_limit means
  Cbc_setMaximumSeconds(cbc, time_limit);
  // Weights are whole cells, so an incumbent within 1 of the bound is optimal.
  Cbc_setAllowableGap(cbc, 0.99);
  // Warm start: the start set, each dominated candidate replaced by a kept superset.
  std::vector<int> start_columns;
  start_columns.reserve(start.size());
  for (const uint32_t c : start) {
    start_columns.push_back(column_of[Dominator(matrix, columns, dominated, c)]);
  }
  std::sort(start_columns.begin(), start_columns.end());
  start_columns.erase(std::unique(start_columns.begin(), start_columns.end()), start_columns.end());
  const std::vector<double> ones(start_columns.size(), 1.0);
  Cbc_setMIPStartI(cbc, static_cast<int>(start_columns.size()), start_columns.data(), ones.data());

  Cbc_solve(cbc);
  const double bound = Cbc_getBestPossibleObjValue(cbc);
  if (std::isfinite(bound)) outcome.bound = bound;
  const double* solution = Cbc_bestSolution(cbc);
  if (solution == nullptr) {
    outcome.note = fmt::format("CBC found no solution (status {}, secondary {})", Cbc_status(cbc),
                               Cbc_secondaryStatus(cbc));
    return outcome;
  }
  for (int q = 0; q < x_count; ++q) {
    if (solution[q] > 0.5) outcome.chosen.push_back(kept[q]);
  }
  if (outcome.chosen.size() > n) {
    outcome.chosen.clear();
    outcome.note = "CBC returned more than n sensors";
    return outcome;
  }
  outcome.proven_optimal = Cbc_isProvenOptimal(cbc) != 0;
  if (!outcome.proven_optimal) {
    outcome.note = fmt::format("CBC stopped before proving optimality (secondary status {})",
                               Cbc_secondaryStatus(cbc));
  }
  return outcome;
}

}  // namespace

ExactResult SolveExact(const CoverageMatrix& matrix,
                       size_t n,
                       const std::vector<uint32_t>& start,
                       double time_limit) {
  VANTAGE_CHECK(n >= 1 && n <= matrix.candidate_count() && start.size() == n);
  ExactResult result;
  result.chosen = start;
  const uint64_t start_cells = matrix.CoveredWeight(start);
  result.upper_bound = std::max(SimpleUpperBound(matrix, start, n), start_cells);
  if (start_cells == result.upper_bound) {
    result.proven_optimal = true;
    result.note = "start meets the simple bound";
    return result;
  }
  if (n == 1) {
    const uint32_t best = BestCandidate(matrix);
    result.chosen = {best};
    result.upper_bound = matrix.RowWeight(best);
    result.proven_optimal = true;
    return result;
  }
  CbcOutcome outcome;
  try {
    outcome = RunCbc(matrix, n, start, time_limit);
  } catch (const std::exception& e) {
    outcome = CbcOutcome{};
    outcome.note = fmt::format("CBC failed: {}", e.what());
  } catch (...) {
    outcome = CbcOutcome{};
    outcome.note = "CBC failed";
  }
  result.note = outcome.note;
  if (!outcome.chosen.empty()) {
    std::vector<uint32_t> padded = GreedyComplete(matrix, outcome.chosen, n);
    if (matrix.CoveredWeight(padded) > start_cells) result.chosen = std::move(padded);
  }
  const uint64_t cells = matrix.CoveredWeight(result.chosen);
  // Whole cells: the optimum is at most the bound rounded down (the tolerance absorbs the
  // solver's round-off). A bound below what we hold cannot be one (CBC stopped early): ignored.
  const double bound_cells = std::floor(outcome.bound + 1e-6);
  if (bound_cells >= static_cast<double>(cells) &&
      bound_cells < static_cast<double>(result.upper_bound)) {
    result.upper_bound = static_cast<uint64_t>(bound_cells);
  }
  if (outcome.proven_optimal) result.upper_bound = cells;  // cells >= CBC's own optimum
  result.upper_bound = std::max(result.upper_bound, cells);
  result.proven_optimal = cells == result.upper_bound;
  return result;
}

}  // namespace vantage::detail
