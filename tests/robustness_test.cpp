// Robustness read-outs (issue 9) on hand-made visibility sets whose answers are counted by hand.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <numbers>
#include <optional>
#include <random>

#include "vantage/error.hpp"
#include "vantage/robustness.hpp"

namespace vantage {
namespace {

// R has 10 cells; the five candidates see:
//   0: 0-4   1: 5-7   2: 3-8   3: 8-9   4: 0-2
std::vector<Observation> Sets() {
  const std::vector<std::vector<uint32_t>> cells = {
      {0, 1, 2, 3, 4}, {5, 6, 7}, {3, 4, 5, 6, 7, 8}, {8, 9}, {0, 1, 2}};
  std::vector<Observation> sets;
  for (const auto& c : cells) {
    Observation o;
    o.reference_indices = c;
    sets.push_back(o);
  }
  return sets;
}

TEST(Robustness, EachFailureLeavesTheOthersCoverage) {
  const std::vector<Observation> sets = Sets();
  const CoverageEvaluator evaluator(sets, 10);
  const std::vector<uint32_t> chosen = {0, 1};  // 8 of 10
  const auto failures = SensorFailures(evaluator, chosen);
  ASSERT_EQ(failures.size(), 2u);
  EXPECT_EQ(failures[0].sensor, 0u);
  EXPECT_DOUBLE_EQ(failures[0].coverage, 0.3);  // only 5-7 left
  EXPECT_EQ(failures[1].sensor, 1u);
  EXPECT_DOUBLE_EQ(failures[1].coverage, 0.5);  // only 0-4 left
  // 2-coverage of {0, 2}: cells 3 and 4 are seen twice; losing either sensor loses both.
  const std::vector<uint32_t> pair = {0, 2};
  EXPECT_DOUBLE_EQ(evaluator.Coverage(pair, 2), 0.2);
  for (const SensorFailure& f : SensorFailures(evaluator, pair, 2)) EXPECT_DOUBLE_EQ(f.coverage, 0.0);
}

// Cells a set of candidates covers, counted here from the lists: seen k times, or holding
// min_points hits when given.
double CountedCoverage(const std::vector<Observation>& sets, const std::vector<uint32_t>& chosen,
                       size_t cells, int k, std::optional<uint32_t> min_points) {
  std::map<uint32_t, uint64_t> tally;
  for (const uint32_t c : chosen)
    for (size_t i = 0; i < sets[c].reference_indices.size(); ++i)
      tally[sets[c].reference_indices[i]] += min_points ? sets[c].reference_hits[i] : 1;
  size_t covered = 0;
  for (const auto& [cell, t] : tally) covered += t >= (min_points ? *min_points : k) ? 1 : 0;
  return static_cast<double>(covered) / static_cast<double>(cells);
}

// Each candidate sees each of `cells` cells with chance 1/3, with 1..5 points there.
std::vector<Observation> RandomSets(std::mt19937* rng, size_t cells, uint32_t candidates) {
  std::vector<Observation> sets(candidates);
  for (Observation& o : sets) {
    for (uint32_t cell = 0; cell < cells; ++cell) {
      if ((*rng)() % 3 != 0) continue;
      o.reference_indices.push_back(cell);
      o.reference_hits.push_back(1 + (*rng)() % 5);
    }
  }
  return sets;
}

// Random instances, k = 1..3 and point counts: every slot's best replacement (within any
// tolerance: 1) has the coverage counted here, and no other candidate does better in that slot.
TEST(Robustness, AlternativesMatchCountingEverySwap) {
  std::mt19937 rng(7);
  for (int instance = 0; instance < 60; ++instance) {
    const size_t cells = 5 + rng() % 30;
    const uint32_t candidates = 4 + rng() % 8;
    const std::vector<Observation> sets = RandomSets(&rng, cells, candidates);
    const CoverageEvaluator evaluator(sets, cells);
    const int k = 1 + instance % 3;
    const std::optional<uint32_t> min_points =
        instance % 4 == 3 ? std::optional<uint32_t>(4) : std::nullopt;
    const std::vector<uint32_t> chosen = {0, 1, 2};
    const auto alternatives = NearOptimalAlternatives(
        evaluator, chosen, {.k = k, .min_points = min_points, .within = 1.0});
    ASSERT_EQ(alternatives.size(), chosen.size()) << instance;
    for (const Alternative& a : alternatives) {
      EXPECT_DOUBLE_EQ(a.coverage, CountedCoverage(sets, a.chosen, cells, k, min_points))
          << instance;
      const size_t slot = static_cast<size_t>(
          std::find(chosen.begin(), chosen.end(), a.replaced) - chosen.begin());
      for (uint32_t j = 3; j < candidates; ++j) {
        std::vector<uint32_t> swapped = chosen;
        swapped[slot] = j;
        EXPECT_LE(CountedCoverage(sets, swapped, cells, k, min_points), a.coverage) << instance;
      }
    }
  }
}

TEST(Robustness, AlternativesAreTheBestReplacementPerSensorWithinTheTolerance) {
  const std::vector<Observation> sets = Sets();
  const CoverageEvaluator evaluator(sets, 10);
  const std::vector<uint32_t> chosen = {0, 1};  // 0.8
  // Replacing 1: candidate 2 gives 0-8 = 0.9 (3 gives 0.7, 4 gives 0.5).
  // Replacing 0: candidates 2 and 4 both give 0.6 (tie: the lower index, 2), 3 gives 0.5.
  auto close = NearOptimalAlternatives(evaluator, chosen, {.within = 0.1});
  ASSERT_EQ(close.size(), 1u);
  EXPECT_EQ(close[0].chosen, (std::vector<uint32_t>{0, 2}));
  EXPECT_EQ(close[0].replaced, 1u);
  EXPECT_EQ(close[0].replacement, 2u);
  EXPECT_DOUBLE_EQ(close[0].coverage, 0.9);

  auto wide = NearOptimalAlternatives(evaluator, chosen, {.within = 0.2});  // 0.6 is exactly 0.2 below
  ASSERT_EQ(wide.size(), 2u);
  EXPECT_DOUBLE_EQ(wide[1].coverage, 0.6);
  EXPECT_EQ(wide[1].chosen, (std::vector<uint32_t>{2, 1}));
  EXPECT_EQ(wide[1].replaced, 0u);

  // An installed sensor (--keep-existing) is never replaced: only 1's alternative is left.
  const std::vector<uint32_t> kept = {0};
  auto installed = NearOptimalAlternatives(evaluator, chosen, {.within = 0.2, .kept = kept});
  ASSERT_EQ(installed.size(), 1u);
  EXPECT_EQ(installed[0].replaced, 1u);

  // Set cover: an alternative must still reach the goal.
  EXPECT_EQ(NearOptimalAlternatives(evaluator, chosen, {.within = 0.2, .at_least = 0.85}).size(),
            1u);
  EXPECT_TRUE(
      NearOptimalAlternatives(evaluator, chosen, {.within = 0.2, .at_least = 0.95}).empty());
}

// Priced results, on Sets() with chosen {0, 1} (0.8, cost 3 + 4 = 7) and prices 3 4 10 1 2:
// - a budget of 8: replacing 1 by 2 (0.9) costs 13, out; by 3 (0-4 + 8-9 = 0.7) costs 4, the
//   best within it; replacing 0 by 2 (0.6) costs 14, out; by 4 (0-2 + 5-7 = 0.6) costs 6, by 3
//   (0.5) 5: 4 is best. Within 0.2 points both stay (0.7, 0.6), most coverage first.
// - --cheapest with the goal 0.6 and 0.2 points: replacing 1: 3 (0.7, cost 4) is cheaper than 2
//   (0.9, 13) and reaches it; replacing 0: 3 (0.5) misses the goal, 4 (0.6, cost 6) is cheaper
//   than 2 (0.6, 14). Cheapest first: 1 -> 3 (4), then 0 -> 4 (6).
TEST(Robustness, PricedAlternativesKeepTheBudgetOrRankByCost) {
  const std::vector<Observation> sets = Sets();
  const CoverageEvaluator evaluator(sets, 10);
  const std::vector<uint32_t> chosen = {0, 1};
  const std::vector<double> costs = {3, 4, 10, 1, 2};
  const auto budget =
      NearOptimalAlternatives(evaluator, chosen, {.within = 0.2, .costs = costs, .budget = 8.0});
  ASSERT_EQ(budget.size(), 2u);
  EXPECT_EQ(budget[0].chosen, (std::vector<uint32_t>{0, 3}));
  EXPECT_DOUBLE_EQ(budget[0].coverage, 0.7);
  EXPECT_DOUBLE_EQ(*budget[0].cost, 4);
  EXPECT_EQ(budget[1].chosen, (std::vector<uint32_t>{4, 1}));
  EXPECT_DOUBLE_EQ(budget[1].coverage, 0.6);
  EXPECT_DOUBLE_EQ(*budget[1].cost, 6);
  // A budget of 5 leaves replacing 1 by 3 (4), and 0 by 3 (5) at 0.5: beyond 0.2 points.
  const auto tight =
      NearOptimalAlternatives(evaluator, chosen, {.within = 0.2, .costs = costs, .budget = 5.0});
  ASSERT_EQ(tight.size(), 1u);
  EXPECT_EQ(tight[0].replacement, 3u);

  const auto cheapest = NearOptimalAlternatives(
      evaluator, chosen, {.within = 0.2, .at_least = 0.6, .costs = costs, .cheapest = true});
  ASSERT_EQ(cheapest.size(), 2u);
  EXPECT_EQ(cheapest[0].replaced, 1u);
  EXPECT_EQ(cheapest[0].replacement, 3u);
  EXPECT_DOUBLE_EQ(*cheapest[0].cost, 4);
  EXPECT_EQ(cheapest[1].replaced, 0u);
  EXPECT_EQ(cheapest[1].replacement, 4u);
  EXPECT_DOUBLE_EQ(*cheapest[1].cost, 6);
  // Unpriced, the same rules pick by coverage: 1 -> 2 (0.9) and 0 -> 2 (0.6, the lower index).
  const auto unpriced =
      NearOptimalAlternatives(evaluator, chosen, {.within = 0.2, .at_least = 0.6});
  ASSERT_EQ(unpriced.size(), 2u);
  EXPECT_EQ(unpriced[0].replacement, 2u);
  EXPECT_FALSE(unpriced[0].cost.has_value());
}

// Random priced instances against every single swap counted here: each slot's alternative is
// the best swap that keeps the tolerance, the goal and the budget (most coverage, or with
// --cheapest least cost then most coverage), and no slot without one has a swap that keeps them.
TEST(Robustness, PricedAlternativesMatchEverySwap) {
  std::mt19937 rng(11);
  for (int instance = 0; instance < 80; ++instance) {
    const size_t cells = 5 + rng() % 25;
    const uint32_t candidates = 4 + rng() % 8;
    const std::vector<Observation> sets = RandomSets(&rng, cells, candidates);
    std::vector<double> costs(candidates);
    for (double& c : costs) c = 1 + static_cast<double>(rng() % 9);
    const CoverageEvaluator evaluator(sets, cells);
    const std::vector<uint32_t> chosen = {0, 1, 2};
    const double base = CountedCoverage(sets, chosen, cells, 1, std::nullopt);
    const double chosen_cost = costs[0] + costs[1] + costs[2];
    const bool cheapest = instance % 2 == 1;
    AlternativeRules rules{.within = 0.15, .costs = costs};
    if (cheapest) {
      rules.cheapest = true;
      // Two cells fewer than the chosen: a goal in whole cells, compared exactly.
      rules.at_least = (std::round(base * static_cast<double>(cells)) - 2) /
                       static_cast<double>(cells);
    } else {
      rules.budget = chosen_cost + static_cast<double>(rng() % 4);
    }
    const auto alternatives = NearOptimalAlternatives(evaluator, chosen, rules);
    for (size_t slot = 0; slot < chosen.size(); ++slot) {
      std::optional<std::pair<double, double>> best;  // (cost, coverage) of the best swap
      std::optional<uint32_t> best_j;
      for (uint32_t j = 3; j < candidates; ++j) {
        std::vector<uint32_t> swapped = chosen;
        swapped[slot] = j;
        const double coverage = CountedCoverage(sets, swapped, cells, 1, std::nullopt);
        const double cost = chosen_cost - costs[chosen[slot]] + costs[j];
        if (coverage < base - 0.15 - 1e-9) continue;
        if (rules.at_least && coverage < *rules.at_least) continue;
        if (rules.budget && cost > *rules.budget) continue;
        const bool better =
            !best ||
            (cheapest ? cost < best->first || (cost == best->first && coverage > best->second)
                      : coverage > best->second);
        if (better) {
          best = {cost, coverage};
          best_j = j;
        }
      }
      const auto found =
          std::find_if(alternatives.begin(), alternatives.end(),
                       [&](const Alternative& a) { return a.replaced == chosen[slot]; });
      ASSERT_EQ(found != alternatives.end(), best.has_value()) << instance << " slot " << slot;
      if (!best) continue;
      EXPECT_EQ(found->replacement, *best_j) << instance << " slot " << slot;
      EXPECT_DOUBLE_EQ(*found->cost, best->first) << instance;
      EXPECT_DOUBLE_EQ(found->coverage, best->second) << instance;
    }
    for (size_t i = 1; i < alternatives.size(); ++i) {
      if (cheapest)
        EXPECT_LE(*alternatives[i - 1].cost, *alternatives[i].cost) << instance;
      else
        EXPECT_GE(alternatives[i - 1].coverage, alternatives[i].coverage) << instance;
    }
  }
}


TEST(Robustness, ShrunkFieldOfViewNarrowsBothAxesByTheTolerance) {
  Candidate c;
  c.name = "cam";
  c.sensor = SensorType::FromFov("t", 640, 480, 1.2, 0.9, 0.1, 3);
  const double tol = 3.0;
  const double delta = tol * std::numbers::pi / 180;
  const auto shrunk = ShrinkFov({&c, 1}, tol);
  ASSERT_EQ(shrunk.size(), 1u);
  EXPECT_NEAR(shrunk[0].sensor.HorizontalFov(), 1.2 - delta, 1e-12);
  EXPECT_NEAR(shrunk[0].sensor.VerticalFov(), 0.9 - delta, 1e-12);
  EXPECT_NEAR(shrunk[0].sensor.fx, 320 / std::tan((1.2 - delta) / 2), 1e-9);
  EXPECT_EQ(shrunk[0].sensor.width, 640);
  EXPECT_DOUBLE_EQ(shrunk[0].sensor.cx, 320);
  EXPECT_THROW(ShrinkFov({&c, 1}, 60), InputError);  // above the 51.6 deg vertical view
  EXPECT_THROW(ShrinkFov({&c, 1}, -1), InputError);
}

}  // namespace
}  // namespace vantage
