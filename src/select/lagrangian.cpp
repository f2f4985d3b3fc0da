// A Lagrangian upper bound for maximum coverage with n sensors (issue 14).
//
// The problem on the merged matrix: max sum_e w_e y_e s.t. y_e <= sum_{i sees e} x_i,
// sum_i x_i = n, x binary, y in [0, 1]. Relaxing the coverage rows with multipliers lambda_e >= 0:
//
//   L(lambda) = max_{|S| = n} sum_{i in S} r_i + sum_e max(0, w_e - lambda_e),
//   r_i = sum_{e in row i} lambda_e,
//
// an upper bound on the optimum for every lambda >= 0, and min_lambda L = the LP relaxation's
// optimum (the subproblem's polytope is integral). Multipliers above w_e never help, so lambda
// stays in [0, w]. The minimum is sought by projected subgradient steps (Polyak, towards the
// incumbent); the bound returned is L of the best multipliers re-evaluated exactly in fixed point.
#include <algorithm>
#include <bit>
#include <chrono>
#include <cmath>
#include <numeric>
#include <utility>

#include "select/methods.hpp"
#include "vantage/error.hpp"
#include "vantage/interrupt.hpp"

namespace vantage::detail {
namespace {

// Polyak step scale: starts at kStartStepScale, halved after kPatience steps without a better
// bound, and the search ends once it falls below kMinStepScale.
constexpr double kStartStepScale = 2.0;
constexpr double kMinStepScale = 1e-7;
constexpr int kPatience = 30;

// The indices of the n largest `values` (ties: the lower index), in no particular order.
void TopN(std::span<const double> values, size_t n, std::vector<uint32_t>* order) {
  order->resize(values.size());
  std::iota(order->begin(), order->end(), 0u);
  std::nth_element(order->begin(), order->begin() + static_cast<std::ptrdiff_t>(n) - 1,
                   order->end(), [&](uint32_t a, uint32_t b) {
                     return values[a] > values[b] || (values[a] == values[b] && a < b);
                   });
  order->resize(n);
}

// L(lambda) exactly: lambda is truncated to multiples of 2^-bits (still >= 0, so still a valid
// multiplier) and L is summed in integers. Returns L * 2^bits and bits.
std::pair<uint64_t, int> ExactBound(const CoverageMatrix& matrix,
                                    size_t n,
                                    std::span<const double> lambda) {
  // The n best rows sum to at most n * sum_e lambda_e <= n * seen_weight(): keep
  // (n + 1) * seen_weight() * 2^bits below 2^63.
  const int used_bits = std::bit_width((static_cast<uint64_t>(n) + 1) * matrix.seen_weight());
  const int bits = std::clamp(62 - used_bits, 0, 24);
  const auto scale = static_cast<double>(uint64_t{1} << bits);
  std::vector<uint64_t> fixed(matrix.element_count());
  uint64_t sum = 0;  // sum_e (w_e - lambda_e), scaled
  for (uint32_t e = 0; e < matrix.element_count(); ++e) {
    const uint64_t w = uint64_t{matrix.Weight(e)} << bits;
    const double scaled = std::floor(lambda[e] * scale);
    fixed[e] = !(scaled > 0)                      ? 0
               : scaled >= static_cast<double>(w) ? w
                                                  : static_cast<uint64_t>(scaled);
    sum += w - fixed[e];
  }
  std::vector<uint64_t> rows(matrix.candidate_count(), 0);
  for (uint32_t i = 0; i < matrix.candidate_count(); ++i) {
    for (const uint32_t e : matrix.Row(i)) rows[i] += fixed[e];
  }
  std::nth_element(rows.begin(), rows.begin() + static_cast<std::ptrdiff_t>(n) - 1, rows.end(),
                   std::greater<>());
  for (size_t j = 0; j < n; ++j) sum += rows[j];
  return {sum, bits};
}

}  // namespace

LagrangianBound LagrangianUpperBound(const CoverageMatrix& matrix,
                                     size_t n,
                                     uint64_t incumbent,
                                     int max_iterations,
                                     double time_limit) {
  VANTAGE_CHECK(n >= 1 && n <= matrix.candidate_count());
  const auto start_time = std::chrono::steady_clock::now();
  const size_t m = matrix.candidate_count();
  const size_t elements = matrix.element_count();
  std::vector<uint32_t> seers(elements, 0);
  for (uint32_t i = 0; i < m; ++i) {
    for (const uint32_t e : matrix.Row(i)) ++seers[e];
  }
  // Start: each element's weight shared among its seers (an element seen once keeps all of it).
  std::vector<double> lambda(elements);
  for (uint32_t e = 0; e < elements; ++e)
    lambda[e] = static_cast<double>(matrix.Weight(e)) / seers[e];
  std::vector<double> best_lambda = lambda;
  double best = std::numeric_limits<double>::infinity();
  std::vector<double> rows(m);
  std::vector<uint32_t> chosen;
  std::vector<uint32_t> covered(elements);
  std::vector<double> step(elements);
  double scale = kStartStepScale;
  int stale = 0;
  LagrangianBound result;
  for (int it = 0; it < max_iterations && scale >= kMinStepScale; ++it) {
    ThrowIfInterrupted();
    if (std::chrono::duration<double>(std::chrono::steady_clock::now() - start_time).count() >
        time_limit) {
      break;
    }
    ++result.iterations;
    double value = 0;
    for (uint32_t e = 0; e < elements; ++e) value += matrix.Weight(e) - lambda[e];
    for (uint32_t i = 0; i < m; ++i) {
      double r = 0;
      for (const uint32_t e : matrix.Row(i)) r += lambda[e];
      rows[i] = r;
    }
    TopN(rows, n, &chosen);
    for (const uint32_t i : chosen) value += rows[i];
    if (value < best - 1e-9) {
      best = value;
      best_lambda = lambda;
      stale = 0;
    } else if (++stale >= kPatience) {
      scale /= 2;
      stale = 0;
    }
    // Whole cells: below incumbent + 1 the bound proves the incumbent optimal (half a cell is
    // left for round-off in this estimate; the exact value below decides).
    if (best < static_cast<double>(incumbent) + 0.5) break;
    // Subgradient dL/dlambda_e = (seers of e in the chosen) - 1, projected onto [0, w].
    std::fill(covered.begin(), covered.end(), 0u);
    for (const uint32_t i : chosen) {
      for (const uint32_t e : matrix.Row(i)) ++covered[e];
    }
    double norm = 0;
    for (uint32_t e = 0; e < elements; ++e) {
      double g = static_cast<double>(covered[e]) - 1.0;
      if ((g > 0 && lambda[e] <= 0) || (g < 0 && lambda[e] >= matrix.Weight(e))) g = 0;
      step[e] = g;
      norm += g * g;
    }
    if (norm == 0) break;  // lambda is optimal: L(lambda) is the LP bound
    const double t = scale * (value - static_cast<double>(incumbent)) / norm;
    for (uint32_t e = 0; e < elements; ++e) {
      lambda[e] = std::clamp(lambda[e] - t * step[e], 0.0, static_cast<double>(matrix.Weight(e)));
    }
  }
  // Only the exact value of a multiplier vector is a proof; the start is always a candidate.
  const auto [scaled, bits] = ExactBound(matrix, n, best_lambda);
  result.upper_bound = scaled >> bits;
  result.value = std::ldexp(static_cast<long double>(scaled), -bits);
  // lambda = w gives L = the n largest rows: never return more than that.
  std::vector<uint64_t> row_weights(m);
  for (uint32_t i = 0; i < m; ++i) row_weights[i] = matrix.RowWeight(i);
  std::nth_element(row_weights.begin(), row_weights.begin() + static_cast<std::ptrdiff_t>(n) - 1,
                   row_weights.end(), std::greater<>());
  const uint64_t top_rows = std::accumulate(
      row_weights.begin(), row_weights.begin() + static_cast<std::ptrdiff_t>(n), uint64_t{0});
  if (top_rows < result.upper_bound) {
    result.upper_bound = top_rows;
    result.value = static_cast<long double>(top_rows);
  }
  return result;
}

}  // namespace vantage::detail
