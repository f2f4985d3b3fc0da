// Branch and bound's root warm-started from a smaller n's multipliers (issue 47, `all`'s exact
// runs): every bound still at least the optimum found by enumerating every n-subset here, and the
// answer proven where the search finishes, whatever multipliers it is handed.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdint>
#include <limits>
#include <set>
#include <vector>

#include "select/coverage_matrix.hpp"
#include "select/methods.hpp"
#include "vantage/rng.hpp"
#include "vantage/visibility.hpp"

namespace vantage {
namespace {

// Each of `candidates` sees each of `cells` cells with probability `p`.
std::vector<Observation> RandomInstance(uint64_t seed, size_t candidates, size_t cells, double p) {
  Rng rng(seed, Stream::kTest, 0);
  std::vector<Observation> obs(candidates);
  for (Observation& o : obs) {
    for (uint32_t c = 0; c < cells; ++c) {
      if (rng.Uniform01() < p) o.reference_indices.push_back(c);
    }
  }
  return obs;
}

// The largest union of reference cells over all subsets of at most n candidates (std::set).
size_t EnumeratedOptimum(const std::vector<Observation>& obs, size_t n) {
  size_t best = 0;
  for (uint32_t mask = 0; mask < (1u << obs.size()); ++mask) {
    if (static_cast<size_t>(__builtin_popcount(mask)) > n) continue;
    std::set<uint32_t> cells;
    for (uint32_t i = 0; i < obs.size(); ++i) {
      if (mask >> i & 1u)
        cells.insert(obs[i].reference_indices.begin(), obs[i].reference_indices.end());
    }
    best = std::max(best, cells.size());
  }
  return best;
}

// The first n candidates: a poor start, so that the bound has work to do.
std::vector<uint32_t> FirstN(size_t n) {
  std::vector<uint32_t> start(n);
  for (uint32_t i = 0; i < n; ++i) start[i] = i;
  return start;
}

TEST(RootMultipliers, GivesTheLargestSmallerN) {
  detail::RootMultipliers store;
  EXPECT_TRUE(store.Before(5).empty());
  store.Put(3, {3.0});
  store.Put(5, {5.0});
  EXPECT_TRUE(store.Before(3).empty());
  EXPECT_EQ(store.Before(4), std::vector<double>{3.0});
  EXPECT_EQ(store.Before(5), std::vector<double>{3.0});
  EXPECT_EQ(store.Before(9), std::vector<double>{5.0});
}

TEST(RootMultipliers, WarmStartsProjectOntoTheWeights) {
  const std::vector<std::vector<uint32_t>> rows = {{0, 1}, {1, 2}};
  const std::vector<uint32_t> weights = {2, 1, 3};
  const detail::LagrangianProblem problem{rows, weights, 1};
  const std::vector<double> warm = {-1.0, 0.25, 7.0};
  EXPECT_EQ(detail::StartMultipliers(problem, warm), (std::vector<double>{0.0, 0.25, 3.0}));
  // No warm start: each weight shared among its seers (element 1 is seen twice).
  EXPECT_EQ(detail::StartMultipliers(problem), (std::vector<double>{2.0, 0.5, 3.0}));
}

TEST(RootMultipliers, WarmStartedBranchAndBoundFindsAndBoundsTheEnumeratedOptimum) {
  int warm_runs = 0;
  for (int trial = 0; trial < 24; ++trial) {
    const size_t m = 10 + trial % 5;
    const size_t cells = 30 + 7 * (trial % 4);
    const double p = 0.08 + 0.04 * (trial % 3);
    const std::vector<Observation> obs = RandomInstance(4700 + trial, m, cells, p);
    const detail::CoverageMatrix matrix(obs, cells);
    // One store for the n's in turn, as `all`'s exact runs share one; every third trial starts
    // from hostile multipliers (outside [0, w], and far from any optimum).
    detail::RootMultipliers store;
    if (trial % 3 == 2) {
      std::vector<double> hostile(matrix.element_count());
      for (size_t e = 0; e < hostile.size(); ++e) hostile[e] = e % 2 ? -5.0 : 1e6;
      store.Put(1, hostile);
    }
    for (size_t n = 2; n <= std::min<size_t>(m - 1, 6); ++n) {
      const size_t optimum = EnumeratedOptimum(obs, n);
      detail::BranchAndBoundLimits limits;
      limits.seconds = 60;
      limits.warm = &store;
      // The root alone first (its bound from the warm start), then the whole search.
      limits.max_nodes = 1;
      detail::RootMultipliers root_only;
      if (!store.Before(n).empty()) root_only.Put(1, store.Before(n));
      limits.warm = &root_only;
      const detail::BranchAndBoundResult root =
          detail::BranchAndBound(matrix, n, FirstN(n), cells, limits);
      EXPECT_GE(root.root_bound, optimum) << "trial " << trial << " n " << n;
      EXPECT_GE(root.upper_bound, optimum) << "trial " << trial << " n " << n;
      limits.max_nodes = std::numeric_limits<long>::max();
      limits.warm = &store;
      const detail::BranchAndBoundResult found =
          detail::BranchAndBound(matrix, n, FirstN(n), cells, limits);
      EXPECT_TRUE(found.proven_optimal) << "trial " << trial << " n " << n;
      EXPECT_EQ(found.cells, optimum) << "trial " << trial << " n " << n;
      EXPECT_EQ(found.upper_bound, optimum) << "trial " << trial << " n " << n;
      EXPECT_GE(found.root_bound, optimum) << "trial " << trial << " n " << n;
      // Its root multipliers (one per element) are there for the next n once a root was bounded.
      const std::vector<double> stored = store.Before(n + 1);
      if (!stored.empty()) {
        EXPECT_EQ(stored.size(), matrix.element_count());
      }
      if (found.nodes > 0 && !stored.empty() && trial % 3 != 2) ++warm_runs;
    }
  }
  // The warm path ran, not only the shares (each later n of a trial starts from an earlier one).
  EXPECT_GE(warm_runs, 24);
}

}  // namespace
}  // namespace vantage
