// The paper's Algorithm 2 (best-views-estimation.md, "Estimation of the best N sensors views").
#include <algorithm>
#include <numeric>
#include <unordered_set>
#include <utility>

#include "select/constrained.hpp"
#include "select/methods.hpp"
#include "vantage/error.hpp"
#include "vantage/rng.hpp"
#include "vantage/interrupt.hpp"

namespace vantage::detail {

// Draw `iteration` of SelectSensorsRandomly: n distinct candidates of order->size(), from
// Rng(seed, Stream::kRansac, iteration). `order` must hold the identity permutation: a partial
// Fisher–Yates shuffle of it, undone after the draw so that iteration i's subset depends on its
// own stream only.
void RansacDraw(uint64_t seed,
                uint64_t iteration,
                size_t n,
                std::vector<uint32_t>* order,
                std::vector<uint32_t>* drawn) {
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

namespace {

// Distinct subsets are tracked only up to this many: beyond it the iteration cap ends RANSAC
// long before every subset is seen (a coupon collector needs about C ln C draws).
constexpr uint64_t kMaxTrackedSubsets = 100'000;

// C(m, k) when it is at most kMaxTrackedSubsets, else 0 (no overflow: each step's value is at
// most the result, times m).
uint64_t SmallBinomial(uint64_t m, uint64_t k) {
  if (k > m) return 0;
  k = std::min(k, m - k);
  uint64_t c = 1;
  for (uint64_t j = 0; j < k; ++j) {
    c = c * (m - j) / (j + 1);  // exact: C(m, j + 1)
    if (c > kMaxTrackedSubsets) return 0;
  }
  return c;
}

// The rank of a subset in the combinatorial number system: distinct subsets, distinct ranks,
// each below C(m, n). `sorted` ascending; only called when C(m, n) <= kMaxTrackedSubsets.
uint64_t SubsetRank(const std::vector<uint32_t>& sorted) {
  uint64_t rank = 0;
  for (size_t k = 0; k < sorted.size(); ++k) rank += SmallBinomial(sorted[k], k + 1);
  return rank;
}

}  // namespace

template <MethodScorer Scorer>
std::vector<uint32_t> RansacChoice(
    const Scorer& scorer, size_t n, int iterations, double stop_coverage, uint64_t seed) {
  const size_t m = scorer.matrix().candidate_count();
  VANTAGE_CHECK(n >= 1 && n <= m);
  std::vector<uint32_t> order(m);
  std::iota(order.begin(), order.end(), 0U);
  std::vector<uint32_t> best;  // s
  typename Scorer::Tally best_tally = scorer.Zero();
  typename Scorer::Score best_score{};  // c
  std::vector<uint32_t> drawn(n);
  // Issue 15: 2^31 - 1 iterations over 120 possible subsets ran for hours. Once every subset has
  // been drawn no later draw can be strictly better, so stopping then returns the same subset.
  const uint64_t subsets = SmallBinomial(m, n);
  std::unordered_set<uint64_t> seen;
  std::vector<uint32_t> sorted;
  // `best.empty()`: Algorithm 2 would return nothing when no draw covers anything (or C = 0);
  // keeping the first draw instead changes no other outcome.
  for (int i = 0;
       i < iterations && (best.empty() || scorer.Fraction(best_tally) < stop_coverage);) {
    if (i % 64 == 0) ThrowIfInterrupted();
    RansacDraw(seed, static_cast<uint64_t>(i), n, &order, &drawn);
    if (subsets > 0) {
      sorted = drawn;
      std::sort(sorted.begin(), sorted.end());
      seen.insert(SubsetRank(sorted));
    }
    // Merge, filter, coverage (k-coverage: the cells at least k of the draw see).
    typename Scorer::Tally tally = scorer.Covered(drawn);
    const typename Scorer::Score score = scorer.ScoreOf(tally);
    ++i;
    if (best.empty() || best_score < score) {
      best = drawn;
      best_tally = std::move(tally);
      best_score = score;
    }
    if (subsets > 0 && seen.size() == subsets) break;
  }
  return best;
}

template std::vector<uint32_t> RansacChoice(const CellScorer&, size_t, int, double, uint64_t);
template std::vector<uint32_t> RansacChoice(const StatesScorer&, size_t, int, double, uint64_t);

}  // namespace vantage::detail
