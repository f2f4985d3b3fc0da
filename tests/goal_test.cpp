// The goal objective as one MILP (select/exact.cpp, SolveGoalMilp) and the fewest-sensors search
// that shares its time with it (SolveSetCover): checked against enumeration of every subset of
// small random instances (weights from merged cells, thresholds k, costs), and on Steiner triple
// systems, whose covering numbers are known.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <map>
#include <vector>

#include "select/coverage_matrix.hpp"
#include "select/methods.hpp"
#include "vantage/rng.hpp"
#include "vantage/select.hpp"

namespace vantage {
namespace {

std::vector<Observation> RandomInstance(uint64_t seed, size_t candidates, size_t cells, double p) {
  Rng rng(seed, Stream::kTest, 0);
  std::vector<Observation> obs(candidates);
  for (Observation& o : obs) {
    for (uint32_t c = 0; c < cells; ++c)
      if (rng.Uniform01() < p) o.reference_indices.push_back(c);
  }
  return obs;
}

// Cells of R seen by at least k of `chosen`, by counting (independent of src/select).
size_t KCovered(const std::vector<Observation>& obs, uint32_t mask, int k) {
  std::map<uint32_t, int> seers;
  for (uint32_t i = 0; i < obs.size(); ++i) {
    if (!(mask >> i & 1)) continue;
    for (const uint32_t c : obs[i].reference_indices) ++seers[c];
  }
  return static_cast<size_t>(std::count_if(seers.begin(), seers.end(),
                                            [&](const auto& s) { return s.second >= k; }));
}

std::vector<uint32_t> Members(uint32_t mask) {
  std::vector<uint32_t> chosen;
  for (uint32_t i = 0; i < 32; ++i)
    if (mask >> i & 1) chosen.push_back(i);
  return chosen;
}

double CostOf(const std::vector<double>& costs, uint32_t mask) {
  double total = 0;
  for (const uint32_t i : Members(mask)) total += costs.empty() ? 1.0 : costs[i];
  return total;
}

// The Steiner triple system of order 9 (the affine plane AG(2, 3)) tripled to order 27, as
// bench/covering_instances.py builds it: candidates are points, cells are triples.
std::vector<Observation> SteinerTriples(int order) {
  std::vector<std::vector<int>> triples;
  // AG(2, 3): the 12 lines of Z_3^2.
  for (int a = 0; a < 3; ++a)
    for (int b = 0; b < 3; ++b) {
      triples.push_back({a * 3 + b, a * 3 + (b + 1) % 3, a * 3 + (b + 2) % 3});  // y varies
      triples.push_back({b * 3 + a, ((b + 1) % 3) * 3 + a, ((b + 2) % 3) * 3 + a});
    }
  for (int a = 0; a < 3; ++a)  // slopes 1 and 2: y = x + a, y = 2x + a
    for (const int s : {1, 2}) {
      std::vector<int> line;
      for (int x = 0; x < 3; ++x) line.push_back(x * 3 + (s * x + a) % 3);
      triples.push_back(line);
    }
  // The 6 remaining lines were counted twice above for slope 0/infinity: keep unique ones.
  for (std::vector<int>& t : triples) std::sort(t.begin(), t.end());
  std::sort(triples.begin(), triples.end());
  triples.erase(std::unique(triples.begin(), triples.end()), triples.end());
  EXPECT_EQ(triples.size(), 12u);
  for (int n = 9; n < order; n *= 3) {
    std::vector<std::vector<int>> next;
    for (int x = 0; x < n; ++x) next.push_back({x * 3, x * 3 + 1, x * 3 + 2});
    for (const std::vector<int>& t : triples)
      for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j)
          next.push_back({t[0] * 3 + i, t[1] * 3 + j, t[2] * 3 + (6 - i - j) % 3});
    triples = std::move(next);
  }
  std::vector<Observation> obs(static_cast<size_t>(order));
  for (uint32_t cell = 0; cell < triples.size(); ++cell)
    for (const int p : triples[cell]) obs[p].reference_indices.push_back(cell);
  return obs;
}

TEST(GoalMilp, CheapestAnswerMatchesEnumeration) {
  int proven = 0, attempts = 0;
  for (uint64_t trial = 0; trial < 12; ++trial) {
    const size_t m = 8 + trial % 3;
    const size_t cells = 25;
    const std::vector<Observation> obs = RandomInstance(900 + trial, m, cells, 0.25);
    const detail::CoverageMatrix matrix(obs, cells);
    const int k = 1 + static_cast<int>(trial % 2);
    std::vector<double> costs;
    if (trial % 3 != 0) {
      Rng rng(950 + trial, Stream::kTest, 0);
      for (size_t i = 0; i < m; ++i) costs.push_back(0.5 + static_cast<double>(rng.Below(5)));
    }
    const uint32_t all = (1u << m) - 1;
    const size_t reachable = KCovered(obs, all, k);
    for (const double share : {0.4, 0.75, 1.0}) {
      const auto goal = static_cast<uint64_t>(std::ceil(share * static_cast<double>(reachable)));
      if (goal == 0) continue;
      SCOPED_TRACE(testing::Message() << "trial " << trial << " k " << k << " goal " << goal);
      double cheapest = 1e300;
      for (uint32_t mask = 1; mask <= all; ++mask)
        if (KCovered(obs, mask, k) >= goal) cheapest = std::min(cheapest, CostOf(costs, mask));
      const std::vector<uint32_t> start = Members(all);
      ++attempts;
      const detail::GoalResult result =
          detail::SolveGoalMilp(matrix, k, costs, goal, start, 20.0);
      ASSERT_FALSE(result.chosen.empty()) << result.note;
      uint32_t mask = 0;
      for (const uint32_t i : result.chosen) mask |= 1u << i;
      EXPECT_GE(KCovered(obs, mask, k), goal);  // feasible
      EXPECT_LE(result.lower_bound, cheapest + 1e-9);  // a valid bound
      if (result.proven_optimal) {
        ++proven;
        EXPECT_NEAR(CostOf(costs, mask), cheapest, 1e-9);
      }
    }
  }
  EXPECT_EQ(proven, attempts);  // instances this small are all proved in 20 s
}

TEST(GoalMilp, SetCoverOfSteinerTripleSystemsIsProved) {
  // A point set meeting every triple of STS(9) = AG(2, 3) needs 5 points (its complement holds
  // no line: at most 4 points of AG(2, 3) are line-free, a cap); enumeration checks it below.
  const std::vector<Observation> sts9 = SteinerTriples(9);
  size_t fewest = 9;
  for (uint32_t mask = 1; mask < (1u << 9); ++mask)
    if (KCovered(sts9, mask, 1) == 12) fewest = std::min<size_t>(fewest, Members(mask).size());
  EXPECT_EQ(fewest, 5u);
  const detail::CoverageMatrix matrix9(sts9, 12);
  const detail::SetCoverResult r9 =
      detail::SolveSetCover(matrix9, 12, detail::GreedyToGoal(matrix9, 12), 20.0);
  EXPECT_EQ(r9.chosen.size(), 5u);
  EXPECT_TRUE(r9.proven_optimal) << r9.note;

  // STS(27): 18 (Fulkerson, Nemhauser, Trotter 1974). The search t by t alone found 19 (it gave
  // CBC maximum coverage at t = 12, whose LP reaches every triple); the goal MILP finds 18.
  // Proving it takes CBC longer than this limit: the bound is only checked to be valid.
  const std::vector<Observation> sts27 = SteinerTriples(27);
  const detail::CoverageMatrix matrix27(sts27, 117);
  const std::vector<uint32_t> start = detail::GreedyToGoal(matrix27, 117);
  const detail::SetCoverResult r27 = detail::SolveSetCover(matrix27, 117, start, 20.0);
  EXPECT_EQ(matrix27.CoveredWeight(r27.chosen), 117u);
  EXPECT_EQ(r27.chosen.size(), 18u);
  EXPECT_LE(r27.lower_bound, 18u);
  EXPECT_GE(r27.lower_bound, 9u);  // 117 triples, 13 through each point
}

}  // namespace
}  // namespace vantage
