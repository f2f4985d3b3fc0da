// Local search (issue 47: swaps evaluated incrementally from cover counts) against definitions
// computed here from the observations alone (no merged matrix, no bitsets): every swap's
// coverage recounted from scratch, and a reference search that makes the same moves by those
// recounts (best-improvement 1-swaps with ties to the earlier position and the lower index, an
// added sensor under a budget, then the best 2-swap in LocalOptions' order). And the matrix's
// weighted counts (bit planes of the element weights) against plain sums over the rows.
#include <gtest/gtest.h>

#include <algorithm>
#include <numeric>
#include <optional>
#include <vector>

#include "select/coverage_matrix.hpp"
#include "select/methods.hpp"
#include "select/scorer.hpp"
#include "vantage/rng.hpp"
#include "test_util.hpp"
#include "vantage/select_states.hpp"

namespace vantage {
namespace {


// One state's cells and its observations.
struct State {
  std::vector<Observation> obs;
  size_t cells = 0;
};

// Per state, the cells that at least k of `set` see.
std::vector<uint64_t> CellsSeen(const std::vector<State>& states,
                                const std::vector<uint32_t>& set,
                                int k) {
  std::vector<uint64_t> cells(states.size(), 0);
  for (size_t s = 0; s < states.size(); ++s) {
    std::vector<int> seers(states[s].cells, 0);
    for (const uint32_t c : set) {
      for (const uint32_t cell : states[s].obs[c].reference_indices) ++seers[cell];
    }
    cells[s] = static_cast<uint64_t>(
        std::count_if(seers.begin(), seers.end(), [&](int x) { return x >= k; }));
  }
  return cells;
}

// The cells whose capped points (min(hits, k) per sensor) from `set` add up to k (one state).
uint64_t CellsWithPoints(const State& state, const std::vector<uint32_t>& set, int k) {
  std::vector<int> points(state.cells, 0);
  for (const uint32_t c : set) {
    const Observation& o = state.obs[c];
    for (size_t j = 0; j < o.reference_indices.size(); ++j)
      points[o.reference_indices[j]] += std::min<int>(o.reference_hits[j], k);
  }
  return static_cast<uint64_t>(
      std::count_if(points.begin(), points.end(), [&](int x) { return x >= k; }));
}

// a < b for the aggregate of the fractions cells[s] / |R_s| (test::AggregateLess).
bool Less(const std::vector<uint64_t>& a,
          const std::vector<uint64_t>& b,
          const std::vector<State>& states,
          bool by_min) {
  std::vector<size_t> sizes;
  for (const State& s : states) sizes.push_back(s.cells);
  return test::AggregateLess(a, b, sizes, by_min);
}

struct Reference {
  std::vector<State> states;
  int k = 1;
  bool by_min = false;
  std::vector<double> costs;  // a budget when not empty
  double budget = 0;
  bool two_swap = true;
};

// The local search by its definition: every move recounted from the observations.
std::vector<uint32_t> ReferenceLocalSearch(const Reference& ref, std::vector<uint32_t> chosen) {
  const size_t m = ref.states.front().obs.size();
  const size_t n = chosen.size();
  if (n == 0 || n >= m) return chosen;
  const bool has_budget = !ref.costs.empty();
  const auto used = [&](uint32_t j) {
    return std::find(chosen.begin(), chosen.end(), j) != chosen.end();
  };
  const auto fits = [&](size_t p, uint32_t j) {
    if (!has_budget) return true;
    double total = 0;
    for (size_t s = 0; s < chosen.size(); ++s) total += ref.costs[s == p ? j : chosen[s]];
    if (p == chosen.size()) total += ref.costs[j];
    return total <= ref.budget;
  };
  while (true) {
    std::vector<uint64_t> best = CellsSeen(ref.states, chosen, ref.k);
    std::optional<std::pair<size_t, uint32_t>> move;
    const size_t positions = has_budget ? n + 1 : n;
    for (size_t p = 0; p < positions; ++p) {
      for (uint32_t j = 0; j < m; ++j) {
        if (used(j)) continue;
        std::vector<uint32_t> swapped = chosen;
        if (p == chosen.size()) {
          swapped.push_back(j);
        } else {
          swapped[p] = j;
        }
        const std::vector<uint64_t> cells = CellsSeen(ref.states, swapped, ref.k);
        if (Less(best, cells, ref.states, ref.by_min) && fits(p, j)) {
          best = cells;
          move = {p, j};
        }
      }
    }
    if (move) {
      if (move->first == chosen.size()) {
        chosen.push_back(move->second);
      } else {
        chosen[move->first] = move->second;
      }
      continue;
    }
    // 2-swaps: plain cells, k = 1, no budget only.
    if (!ref.two_swap || ref.states.size() != 1 || ref.k != 1 || has_budget || n < 2 || m - n < 2)
      break;
    const State& state = ref.states.front();
    const int64_t now = static_cast<int64_t>(CellsSeen(ref.states, chosen, 1)[0]);
    int64_t best_delta = 0;
    size_t best_p = 0, best_q = 0;
    uint32_t best_x = 0, best_y = 0;
    for (size_t p = 0; p < n; ++p) {
      for (size_t q = p + 1; q < n; ++q) {
        // The cells that only chosen[p] and chosen[q] see, and what each unused one sees of them
        // or of the uncovered cells (a_j).
        std::vector<int> others(state.cells, 0);
        for (size_t s = 0; s < n; ++s) {
          if (s == p || s == q) continue;
          for (const uint32_t cell : state.obs[chosen[s]].reference_indices) ++others[cell];
        }
        std::vector<uint64_t> bring(m, 0);
        std::vector<uint32_t> order;
        for (uint32_t j = 0; j < m; ++j) {
          if (used(j)) continue;
          for (const uint32_t cell : state.obs[j].reference_indices) bring[j] += others[cell] == 0;
          if (bring[j] > 0) order.push_back(j);
        }
        std::sort(order.begin(), order.end(), [&](uint32_t u, uint32_t v) {
          return bring[u] != bring[v] ? bring[u] > bring[v] : u < v;
        });
        for (size_t s = 0; s < order.size(); ++s) {
          for (size_t t = s + 1; t < order.size(); ++t) {
            std::vector<uint32_t> swapped = chosen;
            swapped[p] = order[s];
            swapped[q] = order[t];
            const int64_t delta = static_cast<int64_t>(CellsSeen(ref.states, swapped, 1)[0]) - now;
            if (delta > best_delta) {
              best_delta = delta;
              best_p = p;
              best_q = q;
              best_x = order[s];
              best_y = order[t];
            }
          }
        }
      }
    }
    if (best_delta <= 0) break;
    chosen[best_p] = best_x;
    chosen[best_q] = best_y;
  }
  return chosen;
}

// Min-points 1-swaps by their definition (one state).
std::vector<uint32_t> ReferencePointsLocalSearch(const State& state,
                                                 std::vector<uint32_t> chosen,
                                                 int k) {
  const size_t m = state.obs.size();
  const size_t n = chosen.size();
  if (n == 0 || n >= m) return chosen;
  while (true) {
    const auto now = static_cast<int64_t>(CellsWithPoints(state, chosen, k));
    int64_t best_delta = 0;
    size_t best_p = 0;
    uint32_t best_in = 0;
    for (size_t p = 0; p < n; ++p) {
      for (uint32_t j = 0; j < m; ++j) {
        if (std::find(chosen.begin(), chosen.end(), j) != chosen.end()) continue;
        std::vector<uint32_t> swapped = chosen;
        swapped[p] = j;
        const int64_t delta = static_cast<int64_t>(CellsWithPoints(state, swapped, k)) - now;
        if (delta > best_delta) {
          best_delta = delta;
          best_p = p;
          best_in = j;
        }
      }
    }
    if (best_delta <= 0) break;
    chosen[best_p] = best_in;
  }
  return chosen;
}

// A start of n distinct candidates drawn from `seed` (often poor, so the search moves).
std::vector<uint32_t> RandomStart(uint64_t seed, size_t m, size_t n) {
  std::vector<uint32_t> all(m);
  std::iota(all.begin(), all.end(), 0U);
  Rng rng(seed, Stream::kTest, 999);
  for (size_t i = 0; i < n; ++i) std::swap(all[i], all[i + rng.Below(m - i)]);
  all.resize(n);
  return all;
}

TEST(LocalSearchKernels, WeightedCountsMatchSumsOverTheRows) {
  // Elements of 1 to ~100 cells (weights of up to 7 bit planes) over several words; sets dense,
  // sparse, and empty outside a few words.
  for (const uint64_t seed : {1, 2, 3}) {
    const std::vector<Observation> obs = test::PatchInstance(seed, 30, 700);
    const detail::CoverageMatrix matrix(obs, 700);
    ASSERT_TRUE(matrix.is_dense());
    ASSERT_GT(matrix.word_count(), 2U);
    Rng rng(seed, Stream::kTest, 77);
    for (int trial = 0; trial < 20; ++trial) {
      detail::Bitset set = matrix.EmptySet();
      std::vector<uint32_t> words;
      const double density = trial % 2 ? 0.5 : 0.05;
      for (uint32_t e = 0; e < matrix.element_count(); ++e) {
        if (rng.Uniform01() < density) set[e >> 6] |= uint64_t{1} << (e & 63);
      }
      for (uint32_t w = 0; w < matrix.word_count(); ++w) {
        if (rng.Uniform01() < (trial % 4 < 2 ? 0.1 : 0.9)) {
          words.push_back(w);
        }
      }
      detail::Bitset few = matrix.EmptySet();
      for (const uint32_t w : words) few[w] = set[w];
      for (uint32_t c = 0; c < matrix.candidate_count(); ++c) {
        uint64_t in = 0, out = 0, in_few = 0;
        for (const uint32_t e : matrix.Row(c)) {
          const bool member = (set[e >> 6] >> (e & 63)) & 1;
          (member ? in : out) += matrix.Weight(e);
          if ((few[e >> 6] >> (e & 63)) & 1) in_few += matrix.Weight(e);
        }
        EXPECT_EQ(matrix.WeightIn(c, set), in);
        EXPECT_EQ(matrix.Gain(c, set), out);
        EXPECT_EQ(matrix.WeightInWords(c, few, words), in_few);
      }
    }
  }
}

TEST(LocalSearch, OneSwapTalliesAreTheCoverageRecounted) {
  // Every 1-swap (and addition) of random sets, plain cells k = 1..3 and three states k = 1, 2:
  // the incremental tally against the cells recounted from the observations.
  const std::vector<size_t> sizes{130, 70, 257};
  int checked = 0;
  for (const uint64_t seed : {51, 52, 53}) {
    std::vector<State> states;
    std::vector<detail::StateBlock> blocks;
    for (size_t s = 0; s < sizes.size(); ++s)
      states.push_back({test::PatchInstance(seed * 5 + s, 20, sizes[s]), sizes[s]});
    for (const State& s : states) blocks.push_back({s.obs, s.cells});
    const detail::CoverageMatrix stacked(blocks);
    const std::vector<State> first{states[0]};
    const detail::CoverageMatrix plain(states[0].obs, sizes[0]);
    for (const int k : {1, 2, 3}) {
      for (const size_t n : {1, 3, 6}) {
        const std::vector<uint32_t> chosen = RandomStart(seed + n + k, 20, n);
        const auto recount = [&](const std::vector<State>& of, size_t p, uint32_t j) {
          std::vector<uint32_t> set = chosen;
          if (p == n) {
            set.push_back(j);
          } else {
            set[p] = j;
          }
          return CellsSeen(of, set, k);
        };
        const std::vector<uint64_t> cells =
            detail::OneSwapTallies(detail::CellScorer(plain, k), chosen);
        std::vector<detail::StateTally> tallies;
        if (k <= 2)
          tallies =
              detail::OneSwapTallies(detail::StatesScorer(stacked, OverStates::kMean, k), chosen);
        for (size_t p = 0; p <= n; ++p) {
          for (uint32_t j = 0; j < 20; ++j) {
            if (std::find(chosen.begin(), chosen.end(), j) != chosen.end()) continue;
            SCOPED_TRACE(testing::Message()
                         << "seed " << seed << " k " << k << " p " << p << " j " << j);
            EXPECT_EQ(cells[p * 20 + j], recount(first, p, j)[0]);
            if (k <= 2) {
              const std::vector<uint64_t> want = recount(states, p, j);
              for (size_t s = 0; s < sizes.size(); ++s) EXPECT_EQ(tallies[p * 20 + j][s], want[s]);
            }
            ++checked;
          }
        }
      }
    }
  }
  EXPECT_GT(checked, 500);
}

TEST(LocalSearch, SwapsAsTheirDefinitionOnPlainCells) {
  // k = 1 with 2-swaps, k = 2 and 3 with 1-swaps; weighted elements; random starts and greedy's.
  int moved = 0;
  for (const uint64_t seed : {1, 2, 3, 4, 5, 6}) {
    const size_t m = 14 + seed;
    Reference ref;
    ref.states.push_back({test::PatchInstance(seed, m, 150), 150});
    const detail::CoverageMatrix matrix(ref.states[0].obs, 150);
    for (const int k : {1, 2, 3}) {
      ref.k = k;
      const detail::CellScorer scorer(matrix, k);
      for (const size_t n : {2, 3, 5}) {
        for (const bool two_swap : {true, false}) {
          ref.two_swap = two_swap;
          detail::LocalOptions options;
          options.two_swap = two_swap;
          const std::vector<uint32_t> start = RandomStart(seed * 10 + n, m, n);
          SCOPED_TRACE(testing::Message()
                       << "seed " << seed << " k " << k << " n " << n << " 2-swaps " << two_swap);
          const std::vector<uint32_t> got = detail::LocalSearch(scorer, start, options);
          EXPECT_EQ(got, ReferenceLocalSearch(ref, start));
          moved += got != start;
        }
      }
    }
  }
  EXPECT_GT(moved, 20);  // the instances exercise the moves
}

TEST(LocalSearch, TwoSwapsAsTheirDefinition) {
  // Instances where 1-swaps get stuck: a random start, then greedy + local's own answer; the
  // reference makes the 2-swaps by recounting every pair of every pair out.
  for (const uint64_t seed : {11, 12, 13, 14, 15, 16, 17, 18}) {
    const size_t m = 16;
    Reference ref;
    ref.states.push_back({test::PatchInstance(seed, m, 200), 200});
    const detail::CoverageMatrix matrix(ref.states[0].obs, 200);
    const detail::CellScorer scorer(matrix);
    for (const size_t n : {2, 4, 6}) {
      SCOPED_TRACE(testing::Message() << "seed " << seed << " n " << n);
      const std::vector<uint32_t> start = RandomStart(seed, m, n);
      EXPECT_EQ(detail::LocalSearch(scorer, start), ReferenceLocalSearch(ref, start));
      const std::vector<uint32_t> greedy = detail::GreedyComplete(scorer, {}, n);
      EXPECT_EQ(detail::LocalSearch(scorer, greedy), ReferenceLocalSearch(ref, greedy));
    }
  }
}

TEST(LocalSearch, SwapsAndAdditionsUnderABudgetAsTheirDefinition) {
  for (const uint64_t seed : {21, 22, 23, 24}) {
    const size_t m = 15;
    Reference ref;
    ref.states.push_back({test::PatchInstance(seed, m, 160), 160});
    const detail::CoverageMatrix matrix(ref.states[0].obs, 160);
    Rng rng(seed, Stream::kTest, 5);
    ref.costs.resize(m);
    for (double& c : ref.costs) c = 100.0 + static_cast<double>(rng.Below(400));
    for (const int k : {1, 2}) {
      ref.k = k;
      const detail::CellScorer scorer(matrix, k);
      for (const size_t n : {1, 2, 3}) {
        ref.budget = 450.0 * static_cast<double>(n) + 30;
        std::vector<uint32_t> start;
        double total = 0;
        for (const uint32_t c : RandomStart(seed + n, m, m)) {
          if (start.size() < n && total + ref.costs[c] <= ref.budget) {
            start.push_back(c);
            total += ref.costs[c];
          }
        }
        detail::LocalOptions options;
        options.costs = ref.costs;
        options.budget = ref.budget;
        SCOPED_TRACE(testing::Message() << "seed " << seed << " k " << k << " n " << n);
        EXPECT_EQ(detail::LocalSearch(scorer, start, options), ReferenceLocalSearch(ref, start));
      }
    }
  }
}

TEST(LocalSearch, OverStatesAsTheirDefinition) {
  // Three states whose elements share words of the stacked bitsets; the mean and the minimum,
  // k = 1 and 2 (1-swaps).
  const std::vector<size_t> sizes{130, 70, 257};
  for (const uint64_t seed : {31, 32, 33}) {
    Reference ref;
    std::vector<detail::StateBlock> blocks;
    for (size_t s = 0; s < sizes.size(); ++s)
      ref.states.push_back({test::PatchInstance(seed * 7 + s, 18, sizes[s]), sizes[s]});
    for (const State& s : ref.states) blocks.push_back({s.obs, s.cells});
    const detail::CoverageMatrix matrix(blocks);
    for (const OverStates over : {OverStates::kMean, OverStates::kMin}) {
      ref.by_min = over == OverStates::kMin;
      for (const int k : {1, 2}) {
        ref.k = k;
        const detail::StatesScorer scorer(matrix, over, k);
        for (const size_t n : {2, 4}) {
          SCOPED_TRACE(testing::Message()
                       << "seed " << seed << " min " << ref.by_min << " k " << k << " n " << n);
          const std::vector<uint32_t> start = RandomStart(seed + n, 18, n);
          EXPECT_EQ(detail::LocalSearch(scorer, start), ReferenceLocalSearch(ref, start));
        }
      }
    }
  }
}

TEST(LocalSearch, PointThresholdsAsTheirDefinition) {
  // Points of 1 to 5 per seen cell, thresholds 2 to 7 (elements of several counts and weights).
  int moved = 0;
  for (const uint64_t seed : {41, 42, 43, 44, 45, 46}) {
    const size_t m = 16;
    const State state{test::PatchInstance(seed, m, 180, true), 180};
    for (const int k : {2, 3, 4, 7}) {
      const detail::CoverageMatrix matrix(state.obs, 180, static_cast<uint32_t>(k));
      for (const size_t n : {2, 3, 5, 8}) {
        SCOPED_TRACE(testing::Message() << "seed " << seed << " k " << k << " n " << n);
        const std::vector<uint32_t> start = RandomStart(seed + n, m, n);
        const std::vector<uint32_t> got = detail::PointsLocalSearch(matrix, start, k);
        EXPECT_EQ(got, ReferencePointsLocalSearch(state, start, k));
        moved += got != start;
      }
    }
    // A matrix without counts: every sensor brings one point (k seers).
    State ones = state;
    for (Observation& o : ones.obs) std::fill(o.reference_hits.begin(), o.reference_hits.end(), 1);
    const detail::CoverageMatrix plain(ones.obs, 180);
    for (const int k : {1, 2, 3}) {
      const std::vector<uint32_t> start = RandomStart(seed + 7, m, 4);
      SCOPED_TRACE(testing::Message() << "seed " << seed << " k " << k << " (no counts)");
      EXPECT_EQ(detail::PointsLocalSearch(plain, start, k),
                ReferencePointsLocalSearch(ones, start, k));
    }
  }
  EXPECT_GT(moved, 40);
}

}  // namespace
}  // namespace vantage
