// The one exact driver (select/exact.cpp, SolveExactModel) on every kind of selection model —
// maximum coverage, k-coverage, point counts, a budget, rules and kept sensors, the mean and the
// min over states, and goals in cells and over states — checked against enumeration of every
// subset of small random instances, counted here independently of src/select: the answer is
// feasible, optimal and proven, and its bound is the optimum.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <functional>
#include <limits>
#include <string>
#include <vector>

#include "brute_force.hpp"
#include "select/constrained.hpp"
#include "select/coverage_matrix.hpp"
#include "select/methods.hpp"
#include "select/model.hpp"
#include "select/scorer.hpp"
#include "vantage/rng.hpp"

namespace vantage {
namespace {

constexpr size_t kCandidates = 8;

std::vector<Observation> RandomObservations(uint64_t seed, size_t cells, double p) {
  Rng rng(seed, Stream::kTest, 0);
  std::vector<Observation> obs(kCandidates);
  for (Observation& o : obs) {
    for (uint32_t c = 0; c < cells; ++c) {
      if (rng.Uniform01() >= p) continue;
      o.reference_indices.push_back(c);
      o.reference_hits.push_back(static_cast<uint16_t>(1 + rng.Below(3)));
    }
  }
  return obs;
}

// Cells of `obs` (R of `cells`) that `set` puts `threshold` seers into, or with `points` that
// many pixel hits.
size_t CountedCells(const std::vector<Observation>& obs,
                    size_t cells,
                    const std::vector<uint32_t>& set,
                    int threshold,
                    bool points) {
  std::vector<int> count(cells, 0);
  for (const uint32_t i : set) {
    for (size_t j = 0; j < obs[i].reference_indices.size(); ++j)
      count[obs[i].reference_indices[j]] += points ? obs[i].reference_hits[j] : 1;
  }
  return static_cast<size_t>(
      std::count_if(count.begin(), count.end(), [&](int c) { return c >= threshold; }));
}

std::vector<std::vector<uint32_t>> AllSubsets() {
  std::vector<std::vector<uint32_t>> subsets;
  for (uint32_t mask = 0; mask < (1U << kCandidates); ++mask) {
    std::vector<uint32_t> set;
    for (uint32_t i = 0; i < kCandidates; ++i)
      if (mask & (1U << i)) set.push_back(i);
    subsets.push_back(std::move(set));
  }
  return subsets;
}

double Cost(const std::vector<double>& costs, const std::vector<uint32_t>& set) {
  double total = 0;
  for (const uint32_t i : set) total += costs.empty() ? 1.0 : costs[i];
  return total;
}

bool Holds(const std::vector<uint32_t>& set, const std::vector<uint32_t>& fixed) {
  return std::all_of(fixed.begin(), fixed.end(),
                     [&](uint32_t f) { return std::find(set.begin(), set.end(), f) != set.end(); });
}

// One question: the model, what enumeration says a set is worth (maximise) or whether it reaches
// the goal, and which sets are allowed.
struct Question {
  std::string name;
  detail::SelectionModel model;
  std::vector<uint32_t> start;
  std::function<double(const std::vector<uint32_t>&)> value;  // maximise: the objective
  std::function<bool(const std::vector<uint32_t>&)> allowed;  // capacity, rules, kept, goal
};

// Checks SolveExactModel's answer to `q` against every subset; counts the questions asked.
void Check(const Question& q, int* asked) {
  ++*asked;
  SCOPED_TRACE(q.name);
  const bool goal = q.model.goal.has_value();
  double best = goal ? std::numeric_limits<double>::infinity() : -1;
  for (const std::vector<uint32_t>& set : AllSubsets()) {
    if (!q.allowed(set)) continue;
    best = goal ? std::min(best, q.value(set)) : std::max(best, q.value(set));
  }
  ASSERT_TRUE(std::isfinite(best) && best >= 0);
  const detail::ExactAnswer answer = detail::SolveExactModel(q.model, q.start, 30);
  SCOPED_TRACE(answer.note);
  EXPECT_TRUE(q.allowed(answer.chosen));
  EXPECT_NEAR(q.value(answer.chosen), best, 1e-9);
  EXPECT_TRUE(answer.proven_optimal);
  EXPECT_NEAR(answer.bound, best, 1e-9);
}

TEST(ExactModel, EveryKindMatchesEnumeration) {
  int asked = 0;
  for (uint64_t trial = 0; trial < 4; ++trial) {
    SCOPED_TRACE(testing::Message() << "trial " << trial);
    const size_t cells = 14;
    const std::vector<Observation> obs = RandomObservations(4200 + trial, cells, 0.3);
    Rng rng(4300 + trial, Stream::kTest, 0);
    std::vector<double> costs(kCandidates);
    for (double& c : costs) c = 1.0 + static_cast<double>(rng.Below(3));
    InstallConstraints constraints;
    for (uint32_t a = 0; a < kCandidates; ++a)
      for (uint32_t b = a + 1; b < kCandidates; ++b)
        if (rng.Below(6) == 0) constraints.conflicts.push_back({a, b});
    const detail::Feasibility rules(obs, constraints);
    const std::vector<uint32_t> kept = {static_cast<uint32_t>(trial % kCandidates)};
    const auto feasible = [&](const std::vector<uint32_t>& set) {
      return test::SatisfiesConstraints(obs, set, constraints);
    };

    const detail::CoverageMatrix plain(obs, cells);
    const detail::CoverageMatrix points(obs, cells, 3);
    const auto cells_of = [&](int threshold, bool with_points) {
      return [&obs, cells, threshold, with_points](const std::vector<uint32_t>& set) {
        return static_cast<double>(CountedCells(obs, cells, set, threshold, with_points));
      };
    };
    const auto at_most = [](size_t n) {
      return [n](const std::vector<uint32_t>& set) { return set.size() <= n; };
    };
    std::vector<Question> questions;
    {
      Question q{"coverage, n = 3", {}, {}, cells_of(1, false), at_most(3)};
      q.model.matrix = &plain;
      q.model.capacity = 3;
      q.start = detail::GreedyComplete(detail::CellScorer(plain), {}, 3);
      questions.push_back(q);
    }
    {
      Question q{"k = 2, n = 3", {}, {}, cells_of(2, false), at_most(3)};
      q.model.matrix = &plain;
      q.model.threshold = 2;
      q.model.capacity = 3;
      q.start = detail::KGreedyComplete(plain, {}, 3, 2);
      questions.push_back(q);
    }
    {
      Question q{"3 points, n = 3", {}, {}, cells_of(3, true), at_most(3)};
      q.model.matrix = &points;
      q.model.threshold = 3;
      q.model.capacity = 3;
      q.start = detail::KGreedyComplete(points, {}, 3, 3);
      questions.push_back(q);
    }
    {
      Question q{"budget 5", {}, {}, cells_of(1, false), [&](const std::vector<uint32_t>& set) {
                   return Cost(costs, set) <= 5;
                 }};
      q.model.matrix = &plain;
      q.model.costs = costs;
      q.model.capacity = 5;
      q.start = detail::GreedyBudget(plain, costs, 5);
      questions.push_back(q);
    }
    for (const int threshold : {1, 2}) {
      Question q{"rules and kept, k = " + std::to_string(threshold) + ", n = 3",
                 {},
                 kept,
                 cells_of(threshold, false),
                 [&](const std::vector<uint32_t>& set) {
                   return set.size() <= 3 && feasible(set) && Holds(set, kept);
                 }};
      q.model.matrix = &plain;
      q.model.threshold = threshold;
      q.model.capacity = 3;
      q.model.fixed = kept;
      q.model.rules = &rules;
      questions.push_back(q);
    }
    {
      Question q{"rules and kept, budget 5",
                 {},
                 kept,
                 cells_of(1, false),
                 [&](const std::vector<uint32_t>& set) {
                   return Cost(costs, set) <= 5 && feasible(set) && Holds(set, kept);
                 }};
      q.model.matrix = &plain;
      q.model.costs = costs;
      q.model.capacity = 5;
      q.model.fixed = kept;
      q.model.rules = &rules;
      questions.push_back(q);
    }
    std::vector<uint32_t> everyone(kCandidates);
    for (uint32_t i = 0; i < kCandidates; ++i) everyone[i] = i;
    for (const bool priced : {false, true}) {
      const double goal = std::ceil(0.8 * cells_of(1, false)(everyone));
      Question q{priced ? "goal in cells, costs" : "goal in cells, the fewest",
                 {},
                 everyone,
                 [&, priced](const std::vector<uint32_t>& set) {
                   return Cost(priced ? costs : std::vector<double>{}, set);
                 },
                 [&, goal](const std::vector<uint32_t>& set) {
                   return static_cast<double>(CountedCells(obs, cells, set, 1, false)) >= goal;
                 }};
      q.model.matrix = &plain;
      if (priced) q.model.costs = costs;
      q.model.goal = goal;
      questions.push_back(q);
    }
    // A goal counted twice or in points on the plain matrix: SolveExactModel's own goal search
    // (orbital branching where it applies, the goal MILP, the cheap bound).
    for (const bool with_points : {false, true}) {
      const int threshold = with_points ? 3 : 2;
      const double goal = std::ceil(0.6 * cells_of(threshold, with_points)(everyone));
      if (goal < 1) continue;
      Question q{with_points ? "goal in cells holding 3 points" : "goal in cells seen twice",
                 {},
                 everyone,
                 [](const std::vector<uint32_t>& set) { return static_cast<double>(set.size()); },
                 [&, goal, threshold, with_points](const std::vector<uint32_t>& set) {
                   return static_cast<double>(
                              CountedCells(obs, cells, set, threshold, with_points)) >= goal;
                 }};
      q.model.matrix = with_points ? &points : &plain;
      q.model.threshold = threshold;
      q.model.goal = goal;
      questions.push_back(q);
    }
    for (const Question& q : questions) Check(q, &asked);

    // Over two states: the second state's own R and candidates' views.
    const size_t cells2 = 11;
    const std::vector<Observation> obs2 = RandomObservations(4400 + trial, cells2, 0.35);
    const std::vector<detail::StateBlock> blocks = {{obs, cells}, {obs2, cells2}};
    const detail::CoverageMatrix stacked(blocks);
    for (const bool by_min : {false, true}) {
      const auto aggregate = [&, by_min](const std::vector<uint32_t>& set) {
        const double a = static_cast<double>(CountedCells(obs, cells, set, 1, false)) /
                         static_cast<double>(cells);
        const double b = static_cast<double>(CountedCells(obs2, cells2, set, 1, false)) /
                         static_cast<double>(cells2);
        return by_min ? std::min(a, b) : (a + b) / 2;
      };
      const std::string over = by_min ? "min" : "mean";
      const detail::StatesScorer scorer(stacked, by_min ? OverStates::kMin : OverStates::kMean);
      std::vector<Question> states;
      {
        Question q{"states " + over + ", n = 3", {}, {}, aggregate, at_most(3)};
        q.model.capacity = 3;
        q.start = detail::GreedyComplete(scorer, {}, 3);
        states.push_back(q);
      }
      {
        Question q{"states " + over + ", rules and kept, n = 3",
                   {},
                   kept,
                   aggregate,
                   [&](const std::vector<uint32_t>& set) {
                     return set.size() <= 3 && feasible(set) && Holds(set, kept);
                   }};
        q.model.capacity = 3;
        q.model.fixed = kept;
        q.model.rules = &rules;
        states.push_back(q);
      }
      {
        Question q{"states " + over + ", budget 5",
                   {},
                   {},
                   aggregate,
                   [&](const std::vector<uint32_t>& set) { return Cost(costs, set) <= 5; }};
        q.model.costs = costs;
        q.model.capacity = 5;
        // A feasible start within the budget: the cheapest candidate.
        q.start = {
            static_cast<uint32_t>(std::min_element(costs.begin(), costs.end()) - costs.begin())};
        states.push_back(q);
      }
      {
        const double goal = 0.8 * aggregate(everyone);
        Question q{"states " + over + ", goal, costs and kept",
                   {},
                   everyone,
                   [&](const std::vector<uint32_t>& set) { return Cost(costs, set); },
                   [&, goal](const std::vector<uint32_t>& set) {
                     return Holds(set, kept) && aggregate(set) >= goal - 1e-9;
                   }};
        q.model.costs = costs;
        q.model.goal = goal;
        q.model.fixed = kept;
        states.push_back(q);
      }
      for (Question& q : states) {
        q.model.matrix = &stacked;
        q.model.over = &AggregationOf(by_min ? OverStates::kMin : OverStates::kMean);
        Check(q, &asked);
      }
    }
  }
  EXPECT_EQ(asked, 4 * (11 + 2 * 4));  // every kind, 4 instances
}

}  // namespace
}  // namespace vantage
