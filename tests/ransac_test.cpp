// RANSAC (the paper's Algorithm 2) against its definition computed here: the same draws
// (RansacDraw), each scored by counting the reference cells that at least k drawn observations
// contain, straight from the observations (no merged matrix, no bitsets), the first strictly best
// draw kept. And `--method all`'s stated share of iterations.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <numeric>
#include <vector>

#include "select/constrained.hpp"
#include "select/coverage_matrix.hpp"
#include "select/methods.hpp"
#include "vantage/rng.hpp"
#include "vantage/select.hpp"
#include "test_util.hpp"
#include "vantage/select_states.hpp"

namespace vantage {
namespace {

// Per state, the cells at least k of `drawn` see.
std::vector<uint64_t> CellsSeen(const std::vector<std::vector<Observation>>& states,
                                const std::vector<size_t>& sizes,
                                const std::vector<uint32_t>& drawn, int k) {
  std::vector<uint64_t> cells(states.size(), 0);
  for (size_t s = 0; s < states.size(); ++s) {
    std::vector<int> seers(sizes[s], 0);
    for (const uint32_t c : drawn) {
      for (const uint32_t cell : states[s][c].reference_indices) ++seers[cell];
    }
    cells[s] = static_cast<uint64_t>(std::count_if(seers.begin(), seers.end(),
                                                   [&](int x) { return x >= k; }));
  }
  return cells;
}

std::vector<uint32_t> DefinitionRansac(const std::vector<std::vector<Observation>>& states,
                                       const std::vector<size_t>& sizes, size_t n, int k,
                                       int iterations, double stop, uint64_t seed, bool by_min) {
  std::vector<uint32_t> order(states.front().size());
  std::iota(order.begin(), order.end(), 0U);
  std::vector<uint32_t> best, drawn;
  std::vector<uint64_t> best_cells;
  for (int i = 0; i < iterations; ++i) {
    detail::RansacDraw(seed, static_cast<uint64_t>(i), n, &order, &drawn);
    const std::vector<uint64_t> cells = CellsSeen(states, sizes, drawn, k);
    if (best.empty() || test::AggregateLess(best_cells, cells, sizes, by_min)) {
      best = drawn;
      best_cells = cells;
    }
    double aggregate = by_min ? 1.0 : 0.0;
    for (size_t s = 0; s < sizes.size(); ++s) {
      const double f = static_cast<double>(best_cells[s]) / static_cast<double>(sizes[s]);
      aggregate = by_min ? std::min(aggregate, f) : aggregate + f / static_cast<double>(sizes.size());
    }
    if (aggregate >= stop) break;
  }
  return best;
}

TEST(Ransac, KeepsTheFirstStrictlyBestDrawOfItsDefinition) {
  // 300 cells over 40 candidates: elements of 1 to ~100 cells, across several 64-bit words.
  for (const uint64_t seed : {1, 2, 3}) {
    const std::vector<Observation> obs = test::PatchInstance(seed, 40, 300);
    const detail::CoverageMatrix matrix(obs, 300);
    ASSERT_LT(matrix.element_count(), 300U);  // merged: weighted elements
    for (const int k : {1, 2, 3}) {
      const detail::CellScorer scorer(matrix, k);
      for (const size_t n : {1, 3, 6}) {
        for (const int iterations : {1, 7, 200}) {
          for (const double stop : {1.0, 0.6}) {
            SCOPED_TRACE(testing::Message() << "seed " << seed << " k " << k << " n " << n
                                            << " I " << iterations << " stop " << stop);
            EXPECT_EQ(detail::RansacChoice(scorer, n, iterations, stop, seed + 10),
                      DefinitionRansac({obs}, {300}, n, k, iterations, stop, seed + 10, false));
          }
        }
      }
    }
  }
}

TEST(Ransac, OverStatesKeepsTheFirstStrictlyBestDrawOfItsDefinition) {
  // Three states of 130, 70 and 257 cells: their elements share words of the stacked bitsets.
  const std::vector<size_t> sizes{130, 70, 257};
  std::vector<std::vector<Observation>> states;
  std::vector<detail::StateBlock> blocks;
  for (size_t s = 0; s < sizes.size(); ++s)
    states.push_back(test::PatchInstance(20 + s, 30, sizes[s]));
  for (size_t s = 0; s < sizes.size(); ++s) blocks.push_back({states[s], sizes[s]});
  const detail::CoverageMatrix matrix(blocks);
  for (const OverStates over : {OverStates::kMean, OverStates::kMin}) {
    for (const int k : {1, 2}) {
      const detail::StatesScorer scorer(matrix, over, k);
      for (const size_t n : {2, 5}) {
        SCOPED_TRACE(testing::Message() << "min " << (over == OverStates::kMin) << " k " << k
                                        << " n " << n);
        EXPECT_EQ(detail::RansacChoice(scorer, n, 300, 1.0, 5),
                  DefinitionRansac(states, sizes, n, k, 300, 1.0, 5, over == OverStates::kMin));
      }
    }
  }
}

TEST(Ransac, AllSharesItsDrawnSensorsAmongTheSmallerN) {
  using detail::AllRansacShare;
  // The n asked keeps the iterations asked, whatever they are.
  EXPECT_EQ(AllRansacShare::Iterations(1'000'000, 10, 10), 1'000'000);
  EXPECT_EQ(AllRansacShare::Iterations(2'000'000'000, 4, 4), 2'000'000'000);
  // The paper's 1000 iterations fit every share of a 10-sensor table: unchanged.
  for (int n = 1; n <= 10; ++n) EXPECT_EQ(AllRansacShare::Iterations(1000, n, 10), 1000);
  // 10^6 asked at N = 10: n < 10 get floor(5e5 / (9 n)).
  EXPECT_EQ(AllRansacShare::Iterations(1'000'000, 1, 10), 55'555);
  EXPECT_EQ(AllRansacShare::Iterations(1'000'000, 9, 10), 6'172);
  // Whatever is asked, the n below N draw at most kDrawnSensors sensors together.
  for (const int last_n : {2, 3, 10, 40}) {
    double drawn = 0;
    for (int n = 1; n < last_n; ++n) drawn += double(n) * AllRansacShare::Iterations(2'000'000'000, n, last_n);
    EXPECT_LE(drawn, AllRansacShare::kDrawnSensors) << last_n;
    EXPECT_GE(drawn, AllRansacShare::kDrawnSensors - last_n * last_n) << last_n;
  }
}

TEST(AllExactTime, LanesShareTheirWallTime) {
  using detail::AllExactTime;
  // At most kMaxLanes, never more than the threads allowed or the runs, at least one.
  EXPECT_EQ(AllExactTime::Lanes(1, 10), 1u);
  EXPECT_EQ(AllExactTime::Lanes(0, 10), 1u);
  EXPECT_EQ(AllExactTime::Lanes(16, 10), AllExactTime::kMaxLanes);
  EXPECT_EQ(AllExactTime::Lanes(16, 1), 1u);
  // One lane is the rule of one n after another: n gets what is left / (last_n - n + 1).
  AllExactTime by_n(450, 60.0, 10), one_lane(60.0);
  for (int n = 1; n <= 10; ++n) {
    EXPECT_DOUBLE_EQ(by_n.Share(n), one_lane.Share(static_cast<size_t>(10 - n + 1), 1)) << n;
    const double took = 0.1 * n;
    by_n.Spend(took);
    one_lane.Spend(took);
  }
  // Two lanes, 10 runs not started: each lane expects 5, so the first run gets kSeconds / 5; a
  // lane starting the 9th run (2 left in all) expects 1 and gets all it has left.
  EXPECT_DOUBLE_EQ(AllExactTime(60.0).Share(10, 2), AllExactTime::kSeconds / 5);
  EXPECT_DOUBLE_EQ(AllExactTime(60.0).Share(3, 2), AllExactTime::kSeconds / 2);
  EXPECT_DOUBLE_EQ(AllExactTime(2.0).Share(2, 2), 2.0);  // the time limit below kSeconds
  // Runs that each take their whole share: two lanes taking runs in turn never exceed kSeconds.
  for (const size_t runs : {1, 2, 3, 7, 10, 25}) {
    AllExactTime lanes[2] = {AllExactTime(60.0), AllExactTime(60.0)};
    double spent[2] = {0, 0};
    for (size_t j = 0; j < runs; ++j) {
      const size_t lane = spent[0] <= spent[1] ? 0 : 1;  // the lane free first takes the next
      const double share = lanes[lane].Share(runs - j, 2);
      lanes[lane].Spend(share);
      spent[lane] += share;
    }
    EXPECT_LE(std::max(spent[0], spent[1]), AllExactTime::kSeconds + 1e-9) << runs;
  }
}

TEST(Ransac, MethodAllRunsTheSharedIterations) {
  // 5000 candidates each seeing its own cell; the two of RANSAC's draw 800 000 at n = 2 see 10
  // more cells each, so the best pair is that draw (or a rarer earlier one): found with I = 10^6,
  // not with the 125 000 iterations `all` shares to n = 2 of a table up to N = 3.
  constexpr size_t kCandidates = 5000;
  constexpr uint64_t kSeed = 11;
  std::vector<uint32_t> order(kCandidates), best_pair;
  std::iota(order.begin(), order.end(), 0U);
  detail::RansacDraw(kSeed, 800'000, 2, &order, &best_pair);
  std::vector<Observation> obs(kCandidates);
  for (uint32_t c = 0; c < kCandidates; ++c) obs[c].reference_indices.push_back(c);
  for (size_t j = 0; j < 2; ++j) {
    for (uint32_t e = 0; e < 10; ++e)
      obs[best_pair[j]].reference_indices.push_back(static_cast<uint32_t>(kCandidates + 10 * j + e));
  }
  constexpr size_t kCells = kCandidates + 20;
  const detail::CoverageMatrix matrix(obs, kCells);
  const detail::CellScorer scorer(matrix);
  const int shared = detail::AllRansacShare::Iterations(1'000'000, 2, 3);
  ASSERT_EQ(shared, 125'000);
  const std::vector<uint32_t> with_i = detail::RansacChoice(scorer, 2, 1'000'000, 1.0, kSeed);
  const std::vector<uint32_t> with_share = detail::RansacChoice(scorer, 2, shared, 1.0, kSeed);
  ASSERT_NE(with_i, with_share);  // the instance is as designed

  SelectOptions options;
  options.method = Method::kAll;
  options.n = 3;
  options.ransac_iterations = 1'000'000;
  options.ransac_stop_coverage = 1.0;
  options.time_limit = 1;
  options.seed = kSeed;
  int checked = 0;
  for (const Selection& s : Select(obs, kCells, options)) {
    if (s.method != "ransac" || s.n != 2) continue;
    EXPECT_EQ(std::vector<uint32_t>(s.chosen.begin(), s.chosen.end()), with_share);
    ++checked;
  }
  EXPECT_EQ(checked, 1);
}

}  // namespace
}  // namespace vantage
