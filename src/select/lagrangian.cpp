// A Lagrangian upper bound for maximum coverage with n sensors and the fixing it allows (issue 14).
//
// The problem on the merged matrix: max sum_e w_e y_e s.t. y_e <= sum_{i sees e} x_i,
// sum_i x_i <= n, x binary, y in [0, 1]. Relaxing the coverage rows with multipliers lambda_e >= 0:
//
//   L(lambda) = max_{|S| <= n} sum_{i in S} r_i + sum_e max(0, w_e - lambda_e),
//   r_i = sum_{e in row i} lambda_e,
//
// an upper bound on the optimum for every lambda >= 0, and min_lambda L = the LP relaxation's
// optimum (the subproblem's polytope is integral). Multipliers above w_e never help, so lambda
// stays in [0, w]. The minimum is sought by projected subgradient steps (Polyak, towards the
// incumbent); the bound returned is L of the best multipliers re-evaluated exactly in fixed point.
//
// Fixing: L with x_i = 1 forced is L - r_(n) + r_i for i outside the n chosen rows, and L with
// x_i = 0 forced is L - r_i + r_(n+1) for i among them (r_(j) the j-th largest row). Each is an
// upper bound on the problem with that constraint added, so when it is below a threshold T, no
// answer with that value of x_i reaches T.
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <bit>
#include <chrono>
#include <cmath>
#include <functional>
#include <numeric>
#include <utility>

#include "select/methods.hpp"
#include "vantage/error.hpp"
#include "vantage/interrupt.hpp"

namespace vantage::detail {
namespace {

// Polyak step scale: halved after kPatience steps without a better bound, and the search ends
// once it falls below kMinStepScale.
constexpr double kMinStepScale = 1e-7;
constexpr int kPatience = 30;
// ForEachRow: passes over fewer nonzeros stay on the calling thread, and no task gets fewer rows
// than kRowGrain. On the contended 2-core machine of bench/RESULTS.md ("Faster branch and bound
// nodes") two threads made branch and bound slower on the 450-candidate worlds (passes of 0.1-0.7
// M nonzeros, 0.1-0.5 ms: a worker descheduled mid-pass stalls the whole pass), so only passes of
// several milliseconds go parallel.
constexpr size_t kParallelNonzeros = 2000000;
constexpr size_t kRowGrain = 8;

// The indices of the `count` largest `values` (ties: the lower index), in no particular order.
template <typename T>
void TopN(std::span<const T> values, size_t count, std::vector<uint32_t>* order) {
  order->resize(values.size());
  std::iota(order->begin(), order->end(), 0u);
  count = std::min(count, values.size());
  if (count == 0) {
    order->clear();
    return;
  }
  std::nth_element(order->begin(), order->begin() + static_cast<std::ptrdiff_t>(count) - 1,
                   order->end(), [&](uint32_t a, uint32_t b) {
                     return values[a] > values[b] || (values[a] == values[b] && a < b);
                   });
  order->resize(count);
}

}  // namespace

void ForEachRow(size_t count,
                size_t nonzeros,
                const std::function<void(size_t begin, size_t end)>& body) {
  if (count == 0) return;
  if (nonzeros < kParallelNonzeros || count < 2 * kRowGrain) {
    body(0, count);
    return;
  }
  tbb::parallel_for(
      tbb::blocked_range<size_t>(0, count, kRowGrain),
      [&](const tbb::blocked_range<size_t>& range) { body(range.begin(), range.end()); });
}

void AppendRuns(std::span<const uint32_t> row, std::vector<uint32_t>* runs) {
  for (size_t j = 0; j < row.size(); ++j) {
    if (j == 0 || row[j] != row[j - 1] + 1) {
      if (j > 0) runs->push_back(row[j - 1] + 1);
      runs->push_back(row[j]);
    }
  }
  if (!row.empty()) runs->push_back(row.back() + 1);
}

std::vector<double> StartMultipliers(const LagrangianProblem& problem) {
  std::vector<uint32_t> seers(problem.weights.size(), 0);
  for (const std::vector<uint32_t>& row : problem.rows) {
    for (const uint32_t e : row) ++seers[e];
  }
  // Each element's weight shared among its seers (an element seen once keeps all of it; one seen
  // by nobody gets its whole weight, which removes it from L).
  std::vector<double> lambda(problem.weights.size());
  for (size_t e = 0; e < lambda.size(); ++e) {
    lambda[e] = static_cast<double>(problem.weights[e]) / std::max<uint32_t>(seers[e], 1);
  }
  return lambda;
}

SubgradientResult SubgradientSteps(const LagrangianProblem& problem,
                                   uint64_t incumbent,
                                   int max_steps,
                                   double step_scale,
                                   double seconds,
                                   std::vector<double>* lambda) {
  const auto start_time = std::chrono::steady_clock::now();
  const size_t m = problem.rows.size();
  const size_t elements = problem.weights.size();
  VANTAGE_CHECK(lambda->size() == elements);
  std::vector<double>& l = *lambda;
  // Warm starts may come from a problem with more weight (branch and bound zeroes the elements
  // its fixed candidates cover): project onto [0, w] first, or the estimates would run low.
  // sum_e (w_e - lambda_e), summed in element order (the update below sums it in the same order
  // for the next step, so every step's value is the same double whatever pass computes it).
  double free_weight = 0;
  for (size_t e = 0; e < elements; ++e) {
    l[e] = std::clamp(l[e], 0.0, static_cast<double>(problem.weights[e]));
    free_weight += problem.weights[e] - l[e];
  }
  // With runs, rows are summed as differences of prefix sums of lambda, and the chosen rows'
  // cover counted through a difference array (both in passes over the runs, not the elements).
  const bool by_runs = !problem.runs.empty();
  VANTAGE_CHECK(!by_runs || problem.runs.size() == m);
  size_t nonzeros = 0;
  for (const std::vector<uint32_t>& row : problem.rows) nonzeros += row.size();
  if (by_runs) {
    nonzeros = 0;
    for (const std::vector<uint32_t>& row : problem.runs) nonzeros += row.size();
  }
  std::vector<double> prefix(by_runs ? elements + 1 : 0, 0.0);  // prefix[k] = sum_{e < k} l_e
  std::vector<int32_t> difference(by_runs ? elements + 1 : 0, 0);
  if (by_runs) {
    for (size_t e = 0; e < elements; ++e) prefix[e + 1] = prefix[e] + l[e];
  }
  std::vector<double> best_lambda = l;
  SubgradientResult result;
  std::vector<double> rows(m);
  std::vector<uint32_t> chosen;
  std::vector<uint32_t> covered(elements, 0u);  // zero between steps (reset over the chosen rows)
  std::vector<double> step(elements);
  double scale = step_scale;
  int stale = 0;
  for (int it = 0; it < max_steps && scale >= kMinStepScale; ++it) {
    ThrowIfInterrupted();
    if (std::chrono::duration<double>(std::chrono::steady_clock::now() - start_time).count() >
        seconds) {
      break;
    }
    ++result.iterations;
    double value = free_weight;
    // Each row's sum is one thread's, in element order: the same whatever the thread count.
    ForEachRow(m, nonzeros, [&](size_t begin, size_t end) {
      for (size_t i = begin; i < end; ++i) {
        double r = 0;
        if (by_runs) {
          const std::vector<uint32_t>& runs = problem.runs[i];
          for (size_t j = 0; j < runs.size(); j += 2) r += prefix[runs[j + 1]] - prefix[runs[j]];
        } else {
          for (const uint32_t e : problem.rows[i]) r += l[e];
        }
        rows[i] = r;
      }
    });
    TopN(std::span<const double>(rows), problem.slots, &chosen);
    for (const uint32_t i : chosen) value += rows[i];
    if (value < result.estimate - 1e-9) {
      result.estimate = value;
      best_lambda = l;
      stale = 0;
    } else if (++stale >= kPatience) {
      scale /= 2;
      stale = 0;
    }
    // Whole cells: below incumbent + 1 the bound proves the incumbent optimal (half a cell is
    // left for round-off in this estimate; the exact value decides).
    if (result.estimate < static_cast<double>(incumbent) + 0.5) break;
    // Subgradient dL/dlambda_e = (seers of e in the chosen) - 1, projected onto [0, w].
    if (by_runs) {
      for (const uint32_t i : chosen) {
        const std::vector<uint32_t>& runs = problem.runs[i];
        for (size_t j = 0; j < runs.size(); j += 2) {
          ++difference[runs[j]];
          --difference[runs[j + 1]];
        }
      }
      int32_t count = 0;
      for (size_t e = 0; e < elements; ++e) {
        count += difference[e];
        difference[e] = 0;
        covered[e] = static_cast<uint32_t>(count);
      }
      difference[elements] = 0;
    } else {
      for (const uint32_t i : chosen) {
        for (const uint32_t e : problem.rows[i]) ++covered[e];
      }
    }
    double norm = 0;
    for (size_t e = 0; e < elements; ++e) {
      double g = static_cast<double>(covered[e]) - 1.0;
      if ((g > 0 && l[e] <= 0) || (g < 0 && l[e] >= problem.weights[e])) g = 0;
      step[e] = g;
      norm += g * g;
    }
    if (!by_runs) {
      for (const uint32_t i : chosen) {
        for (const uint32_t e : problem.rows[i]) covered[e] = 0;
      }
    }
    if (norm == 0) break;  // lambda is optimal: L(lambda) is the LP bound
    const double t = scale * (value - static_cast<double>(incumbent)) / norm;
    free_weight = 0;
    for (size_t e = 0; e < elements; ++e) {
      l[e] = std::clamp(l[e] - t * step[e], 0.0, static_cast<double>(problem.weights[e]));
      free_weight += problem.weights[e] - l[e];
    }
    if (by_runs) {
      for (size_t e = 0; e < elements; ++e) prefix[e + 1] = prefix[e] + l[e];
    }
  }
  *lambda = std::move(best_lambda);
  result.scale = scale;
  return result;
}

void CoordinateDescent(const LagrangianProblem& problem, int passes, std::vector<double>* lambda) {
  const size_t m = problem.rows.size();
  const size_t elements = problem.weights.size();
  VANTAGE_CHECK(lambda->size() == elements);
  if (m == 0 || problem.slots == 0 || problem.slots > m) return;
  std::vector<double>& l = *lambda;
  for (size_t e = 0; e < elements; ++e)
    l[e] = std::clamp(l[e], 0.0, static_cast<double>(problem.weights[e]));
  // The rows through each element (the transpose of `rows`, in compressed form).
  std::vector<uint32_t> start(elements + 1, 0);
  for (const std::vector<uint32_t>& row : problem.rows) {
    for (const uint32_t e : row) ++start[e + 1];
  }
  for (size_t e = 0; e < elements; ++e) start[e + 1] += start[e];
  // The rows' sums in the same pass.
  std::vector<uint32_t> seers(start.back());
  std::vector<uint32_t> next(start.begin(), start.end() - 1);
  std::vector<double> rows(m, 0.0);
  for (uint32_t i = 0; i < m; ++i) {
    double r = 0;
    for (const uint32_t e : problem.rows[i]) {
      seers[next[e]++] = i;
      r += l[e];
    }
    rows[i] = r;
  }
  std::vector<double> sorted;
  for (int pass = 0; pass < passes; ++pass) {
    ThrowIfInterrupted();
    sorted = rows;
    std::nth_element(sorted.begin(), sorted.begin() + static_cast<std::ptrdiff_t>(problem.slots) - 1,
                     sorted.end(), std::greater<>());
    const double mu = sorted[problem.slots - 1];
    // In lambda_e alone the function's slope is -1 + (rows through e above mu): lambda_e = t is
    // where row i reaches mu, t_i = mu - (r_i - lambda_e). Between the smallest two t_i (of the
    // largest two rows) the slope is 0; the largest point of it leaves the other rows as they are.
    constexpr double kNone = -std::numeric_limits<double>::infinity();
    for (size_t e = 0; e < elements; ++e) {
      double largest = kNone;
      double second_largest = kNone;
      for (uint32_t k = start[e]; k < start[e + 1]; ++k) {
        const double r = rows[seers[k]];
        second_largest = std::max(second_largest, std::min(largest, r));
        largest = std::max(largest, r);
      }
      const double w = problem.weights[e];
      const double first = mu - largest + l[e];          // +inf without a row
      const double second = mu - second_largest + l[e];  // +inf without a second row
      const double target = std::clamp(std::max(first, std::min(second, w)), 0.0, w);
      if (target == l[e]) continue;
      for (uint32_t k = start[e]; k < start[e + 1]; ++k) rows[seers[k]] += target - l[e];
      l[e] = target;
    }
  }
}

ExactLagrangian EvaluateExactly(const LagrangianProblem& problem, std::span<const double> lambda) {
  VANTAGE_CHECK(lambda.size() == problem.weights.size());
  uint64_t total_weight = 0;
  for (const uint32_t w : problem.weights) total_weight += w;
  // The chosen rows sum to at most slots * total_weight: keep (slots + 1) * total_weight * 2^bits
  // below 2^63.
  const size_t slots = std::min(problem.slots, problem.rows.size());
  const int used_bits = std::bit_width((static_cast<uint64_t>(slots) + 1) * total_weight);
  ExactLagrangian exact;
  exact.bits = std::clamp(62 - used_bits, 0, 24);
  const auto scale = static_cast<double>(uint64_t{1} << exact.bits);
  // lambda truncated to multiples of 2^-bits: still in [0, w], so still a valid multiplier.
  std::vector<uint64_t> fixed(problem.weights.size());
  uint64_t sum = 0;  // sum_e (w_e - lambda_e), scaled
  for (size_t e = 0; e < fixed.size(); ++e) {
    const uint64_t w = uint64_t{problem.weights[e]} << exact.bits;
    const double scaled = std::floor(lambda[e] * scale);
    fixed[e] = !(scaled > 0)                      ? 0
               : scaled >= static_cast<double>(w) ? w
                                                  : static_cast<uint64_t>(scaled);
    sum += w - fixed[e];
  }
  exact.rows.assign(problem.rows.size(), 0);
  size_t nonzeros = 0;
  for (const std::vector<uint32_t>& row : problem.rows) nonzeros += row.size();
  if (!problem.runs.empty()) {
    // Runs: differences of integer prefix sums (below 2^62, exact), the same r as summing.
    VANTAGE_CHECK(problem.runs.size() == problem.rows.size());
    std::vector<uint64_t> prefix(fixed.size() + 1, 0);
    for (size_t e = 0; e < fixed.size(); ++e) prefix[e + 1] = prefix[e] + fixed[e];
    nonzeros = 0;
    for (const std::vector<uint32_t>& row : problem.runs) nonzeros += row.size();
    ForEachRow(problem.rows.size(), nonzeros, [&](size_t begin, size_t end) {
      for (size_t i = begin; i < end; ++i) {
        const std::vector<uint32_t>& runs = problem.runs[i];
        uint64_t r = 0;
        for (size_t j = 0; j < runs.size(); j += 2) r += prefix[runs[j + 1]] - prefix[runs[j]];
        exact.rows[i] = r;
      }
    });
  } else {
    ForEachRow(problem.rows.size(), nonzeros, [&](size_t begin, size_t end) {
      for (size_t i = begin; i < end; ++i) {
        uint64_t r = 0;
        for (const uint32_t e : problem.rows[i]) r += fixed[e];
        exact.rows[i] = r;
      }
    });
  }
  TopN(std::span<const uint64_t>(exact.rows), slots, &exact.chosen);
  std::sort(exact.chosen.begin(), exact.chosen.end());
  for (const uint32_t i : exact.chosen) sum += exact.rows[i];
  exact.scaled_value = sum;
  // The (slots + 1)-th largest row (0 when there is none): what replaces a chosen row left out.
  std::vector<bool> in(problem.rows.size(), false);
  for (const uint32_t i : exact.chosen) in[i] = true;
  uint64_t smallest_chosen = std::numeric_limits<uint64_t>::max();
  for (const uint32_t i : exact.chosen) smallest_chosen = std::min(smallest_chosen, exact.rows[i]);
  exact.next_row = 0;
  for (size_t i = 0; i < problem.rows.size(); ++i) {
    if (!in[i]) exact.next_row = std::max(exact.next_row, exact.rows[i]);
  }
  // With fewer rows than slots every row is chosen, and one more fits for free.
  exact.last_chosen = slots < problem.slots || exact.chosen.empty() ? 0 : smallest_chosen;
  return exact;
}

Fixing LagrangianFixing(const LagrangianProblem& problem,
                        const ExactLagrangian& exact,
                        uint64_t threshold) {
  Fixing fixing;
  // threshold << bits must fit (it does whenever the threshold is at most the total weight + 1).
  if (std::bit_width(threshold) + exact.bits > 63) return fixing;
  const uint64_t target = threshold << exact.bits;
  std::vector<bool> in(problem.rows.size(), false);
  for (const uint32_t i : exact.chosen) in[i] = true;
  for (uint32_t i = 0; i < problem.rows.size(); ++i) {
    if (in[i]) {
      // x_i = 0: the (slots + 1)-th row takes its place.
      if (exact.scaled_value - exact.rows[i] + exact.next_row < target) {
        fixing.fixed_in.push_back(i);
      }
    } else if (exact.scaled_value - exact.last_chosen + exact.rows[i] < target) {
      fixing.removed.push_back(i);  // x_i = 1: it replaces the smallest chosen row
    }
  }
  return fixing;
}

LagrangianBound LagrangianUpperBound(const CoverageMatrix& matrix,
                                     size_t n,
                                     uint64_t incumbent,
                                     int max_iterations,
                                     double time_limit) {
  VANTAGE_CHECK(n >= 1 && n <= matrix.candidate_count());
  std::vector<uint32_t> weights(matrix.element_count());
  for (uint32_t e = 0; e < weights.size(); ++e) weights[e] = matrix.Weight(e);
  const LagrangianProblem problem{matrix.rows(), weights, n};
  std::vector<double> lambda = StartMultipliers(problem);
  LagrangianBound result;
  result.iterations =
      SubgradientSteps(problem, incumbent, max_iterations, kStartStepScale, time_limit, &lambda)
          .iterations;
  // Only the exact value of a multiplier vector is a proof; the start is always a candidate.
  const ExactLagrangian exact = EvaluateExactly(problem, lambda);
  result.upper_bound = exact.scaled_value >> exact.bits;
  result.value = std::ldexp(static_cast<long double>(exact.scaled_value), -exact.bits);
  result.lambda = std::move(lambda);
  // lambda = w gives L = the n largest rows: never return more than that.
  std::vector<uint64_t> row_weights(matrix.candidate_count());
  for (uint32_t i = 0; i < row_weights.size(); ++i) row_weights[i] = matrix.RowWeight(i);
  std::nth_element(row_weights.begin(), row_weights.begin() + static_cast<std::ptrdiff_t>(n) - 1,
                   row_weights.end(), std::greater<>());
  const uint64_t top_rows = std::accumulate(
      row_weights.begin(), row_weights.begin() + static_cast<std::ptrdiff_t>(n), uint64_t{0});
  if (top_rows < result.upper_bound) {
    result.upper_bound = top_rows;
    result.value = static_cast<long double>(top_rows);
    result.lambda.assign(weights.begin(), weights.end());
  }
  return result;
}

}  // namespace vantage::detail
