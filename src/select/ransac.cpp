// The paper's Algorithm 2 (best-views-estimation.md, "Estimation of the best N sensors views").
#include <numeric>
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
  // `best.empty()`: Algorithm 2 would return nothing when no draw covers anything (or C = 0);
  // keeping the first draw instead changes no other outcome.
  for (int i = 0;
       i < iterations && (best.empty() || scorer.Fraction(best_tally) < stop_coverage);) {
    if (i % 64 == 0) ThrowIfInterrupted();
    RansacDraw(seed, static_cast<uint64_t>(i), n, &order, &drawn);
    // Merge, filter, coverage (k-coverage: the cells at least k of the draw see).
    typename Scorer::Tally tally = scorer.Covered(drawn);
    const typename Scorer::Score score = scorer.ScoreOf(tally);
    ++i;
    if (best.empty() || best_score < score) {
      best = drawn;
      best_tally = std::move(tally);
      best_score = score;
    }
  }
  return best;
}

template std::vector<uint32_t> RansacChoice(const CellScorer&, size_t, int, double, uint64_t);
template std::vector<uint32_t> RansacChoice(const StatesScorer&, size_t, int, double, uint64_t);

}  // namespace vantage::detail
