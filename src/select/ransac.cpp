// The paper's Algorithm 2 (best-views-estimation.md, "Estimation of the best N sensors views").
#include <numeric>
#include <utility>

#include "select/methods.hpp"
#include "vantage/error.hpp"
#include "vantage/rng.hpp"

namespace vantage::detail {

void RansacDraw(uint64_t seed, uint64_t iteration, size_t n, std::vector<uint32_t>* order,
                std::vector<uint32_t>* drawn) {
  // SelectSensorsRandomly: a partial Fisher–Yates shuffle of the identity, undone after each draw
  // so that iteration i's subset depends on its own stream only.
  const size_t m = order->size();
  VANTAGE_CHECK(n >= 1 && n <= m);
  std::vector<size_t> swapped_with(n);
  drawn->resize(n);
  Rng rng(seed, Stream::kRansac, iteration);
  for (size_t k = 0; k < n; ++k) {
    swapped_with[k] = k + static_cast<size_t>(rng.Below(m - k));
    std::swap((*order)[k], (*order)[swapped_with[k]]);
    (*drawn)[k] = (*order)[k];
  }
  for (size_t k = n; k-- > 0;) std::swap((*order)[k], (*order)[swapped_with[k]]);
}

std::vector<uint32_t> RansacChoice(const CoverageMatrix& matrix,
                                   size_t n,
                                   int iterations,
                                   double stop_coverage,
                                   uint64_t seed,
                                   int k) {
  const size_t m = matrix.candidate_count();
  VANTAGE_CHECK(n >= 1 && n <= m);
  const auto coverage = [&](uint64_t cells) {
    return matrix.reference_size()
               ? static_cast<double>(cells) / static_cast<double>(matrix.reference_size())
               : 0.0;
  };
  std::vector<uint32_t> order(m);
  std::iota(order.begin(), order.end(), 0U);
  std::vector<uint32_t> best;  // s
  uint64_t best_cells = 0;     // c, in cells
  std::vector<uint32_t> drawn(n);
  // `best.empty()`: Algorithm 2 would return nothing when no draw covers anything (or C = 0);
  // keeping the first draw instead changes no other outcome.
  for (int i = 0; i < iterations && (best.empty() || coverage(best_cells) < stop_coverage);) {
    RansacDraw(seed, static_cast<uint64_t>(i), n, &order, &drawn);
    // Merge, filter, coverage (k-coverage: the cells at least k of the draw see).
    const uint64_t cells = k == 1 ? matrix.CoveredWeight(drawn) : KCoveredWeight(matrix, drawn, k);
    ++i;
    if (best.empty() || cells > best_cells) {
      best = drawn;
      best_cells = cells;
    }
  }
  return best;
}

}  // namespace vantage::detail
