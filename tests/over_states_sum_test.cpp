// `--over-states sum` (issue 42): all states' cells counted together, Σ_s covered_s / Σ_s |R_s|,
// on the one selection model. Every method's answer on small random instances (states of
// different sizes) is checked against enumeration of every subset, counted here independently
// of src/select: feasible, scored as enumeration scores it, never above the optimum; exact's is
// the optimum with its proof; every bound is at least the optimum (at most the least cost, for a
// goal). With states of equal size the sum is the mean; with one state it is plain coverage.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdint>
#include <map>
#include <string>
#include <vector>

#include "brute_force.hpp"
#include "select/coverage_matrix.hpp"
#include "select/objective_bounds.hpp"
#include "select/scorer.hpp"
#include "test_util.hpp"
#include "vantage/error.hpp"
#include "vantage/rng.hpp"
#include "vantage/select.hpp"
#include "vantage/select_states.hpp"

namespace vantage {
namespace {

using test::CostOf;
using test::Counted;
using test::MakeStates;
using test::MaskOf;
using test::Members;
using test::RandomInstance;
using test::RandomStates;
using test::Size;

// What each trial asks beside the sum.
enum class Ask { kPlain, kK2, kPoints, kConflictsKept, kCalibration, kBudget, kGoal, kCheapest,
                 kGoalK2 };
constexpr Ask kAsks[] = {Ask::kPlain,       Ask::kK2,     Ask::kPoints, Ask::kConflictsKept,
                         Ask::kCalibration, Ask::kBudget, Ask::kGoal,   Ask::kCheapest,
                         Ask::kGoalK2};

const char* AskName(Ask ask) {
  switch (ask) {
    case Ask::kPlain: return "plain";
    case Ask::kK2: return "k 2";
    case Ask::kPoints: return "min points 3";
    case Ask::kConflictsKept: return "conflicts, kept";
    case Ask::kCalibration: return "calibration";
    case Ask::kBudget: return "budget";
    case Ask::kGoal: return "goal";
    case Ask::kCheapest: return "cheapest goal";
    case Ask::kGoalK2: return "goal, k 2";
  }
  return "";
}

TEST(StatesSum, EveryMethodAndObjectiveMatchesEnumeration) {
  int checked = 0;
  int proven = 0;
  for (uint64_t trial = 0; trial < 27; ++trial) {
    const Ask ask = kAsks[trial % std::size(kAsks)];
    const size_t m = 8 + trial % 5;  // 8 .. 12 candidates
    const size_t state_count = 2 + trial % 2;
    // Sizes far apart, so that the sum and the mean disagree.
    std::vector<size_t> sizes{12, 40, 25};
    sizes.resize(state_count);
    const bool points = ask == Ask::kPoints;
    const RandomStates random = MakeStates(7100 + 10 * trial, sizes, m, 0.3, points);
    const auto& [observed, state_sizes, states] = random;
    size_t all_cells = 0;
    for (const size_t r : sizes) all_cells += r;
    const uint32_t threshold = ask == Ask::kK2 || ask == Ask::kGoalK2 ? 2 : points ? 3 : 1;
    SelectOptions options;
    options.time_limit = test::kSanitized ? 3 : 20;  // see test::kSanitized
    options.seed = 11 + trial;
    options.ransac_iterations = 60;
    if (threshold == 2) options.k = 2;
    if (points) options.min_points = threshold;
    options.n = 3;
    if (ask == Ask::kConflictsKept) {
      options.fixed = {1};
      options.constraints.conflicts = {{0, 2, ConflictKind::kSeparation, 0},
                                       {3, 4, ConflictKind::kSeparation, 0}};
    }
    if (ask == Ask::kCalibration)
      options.constraints.calibration = CalibrationRule{2, std::nullopt};
    Rng rng(7200 + trial, Stream::kTest, 0);
    std::vector<double> costs;
    for (size_t i = 0; i < m; ++i) costs.push_back(1.0 + static_cast<double>(rng.Below(4)));
    const bool is_goal = ask == Ask::kGoal || ask == Ask::kCheapest || ask == Ask::kGoalK2;
    if (ask == Ask::kBudget) {
      options.costs = costs;
      options.budget = 5.0;
    }
    if (ask == Ask::kCheapest) {
      options.costs = costs;
      options.minimize_cost = true;
    }
    const uint32_t all = (1u << m) - 1;
    const uint32_t kept = MaskOf(options.fixed);
    // Covered cells of every state together: the sum's numerator.
    const auto cells = [&](uint32_t mask) {
      size_t total = 0;
      for (size_t s = 0; s < state_count; ++s)
        total += Counted(observed[s], mask, threshold, points);
      return total;
    };
    const auto allowed = [&](uint32_t mask) {
      return (mask & kept) == kept &&
             test::SatisfiesConstraints(observed[0], Members(mask, m), options.constraints);
    };
    const auto value = [&](uint32_t mask) {
      return static_cast<double>(cells(mask)) / static_cast<double>(all_cells);
    };
    const auto price = [&](uint32_t mask) {
      return options.minimize_cost ? CostOf(costs, mask) : static_cast<double>(Size(mask));
    };
    // The goal: three quarters of what all candidates reach, in whole cells of all of R.
    size_t goal_cells = 0;
    if (is_goal) {
      goal_cells = std::max<size_t>(1, cells(all) * 3 / 4);
      options.goal = static_cast<double>(goal_cells) / static_cast<double>(all_cells);
    }
    // The enumerated optima: the most value per count (or within the budget), the least price
    // reaching the goal.
    std::map<int, size_t> best;
    size_t best_in_budget = 0;
    double least_price = 1e300;
    for (uint32_t mask = 0; mask <= all; ++mask) {
      if (!allowed(mask)) continue;
      const size_t c = cells(mask);
      if (is_goal) {
        if (mask != 0 && c >= goal_cells) least_price = std::min(least_price, price(mask));
      } else if (ask == Ask::kBudget) {
        if (CostOf(costs, mask) <= *options.budget + 1e-9)
          best_in_budget = std::max(best_in_budget, c);
      } else if (Size(mask) <= options.n) {
        best[Size(mask)] = std::max(best[Size(mask)], c);
      }
    }
    std::vector<Method> methods{Method::kRansac, Method::kGreedy, Method::kExact};
    if (!is_goal) methods.push_back(Method::kLocal);
    if (trial < 9) methods.push_back(Method::kAll);
    if (ask == Ask::kPlain) methods.push_back(Method::kBest);
    for (const Method method : methods) {
      options.method = method;
      options.n = method == Method::kBest ? 1 : 3;
      SCOPED_TRACE(testing::Message() << "trial " << trial << " " << AskName(ask) << " states "
                                      << state_count << " m " << m << " method "
                                      << MethodName(method));
      const std::vector<StateSelection> results =
          SelectOverStates(states, OverStates::kSum, options);
      ASSERT_FALSE(results.empty());
      for (const StateSelection& r : results) {
        const Selection& s = r.selection;
        SCOPED_TRACE(testing::Message() << s.method << " n " << s.n);
        ++checked;
        const uint32_t mask = MaskOf(s.chosen);
        EXPECT_EQ(Size(mask), s.n);  // distinct
        EXPECT_TRUE(allowed(mask));
        // Scored as enumeration scores it, each state's share too.
        EXPECT_NEAR(s.coverage, value(mask), 1e-12);
        ASSERT_EQ(r.state_coverage.size(), state_count);
        for (size_t st = 0; st < state_count; ++st)
          EXPECT_NEAR(r.state_coverage[st],
                      static_cast<double>(Counted(observed[st], mask, threshold, points)) /
                          static_cast<double>(sizes[st]),
                      1e-12);
        if (is_goal) {
          EXPECT_GE(cells(mask), goal_cells);
          EXPECT_GE(price(mask), least_price - 1e-9);
          if (s.n_lower_bound) {
            EXPECT_LE(*s.n_lower_bound, least_price + 1e-9);
          }
          if (s.cost_lower_bound) {
            EXPECT_LE(*s.cost_lower_bound, least_price + 1e-9);
          }
          if (s.method == "exact" && method == Method::kExact && !test::kSanitized) {
            EXPECT_TRUE(s.proven_optimal);
          }
          if (s.method == "exact" && s.proven_optimal) {
            ++proven;
            EXPECT_NEAR(price(mask), least_price, 1e-9);
          }
          continue;
        }
        const double optimum =
            static_cast<double>(ask == Ask::kBudget ? best_in_budget : best[s.n]) /
            static_cast<double>(all_cells);
        if (ask == Ask::kBudget) {
          EXPECT_LE(CostOf(costs, mask), *options.budget + 1e-9);
        } else {
          EXPECT_LE(s.n, options.n);
          if (method != Method::kAll) {
            EXPECT_EQ(s.n, options.n);
          }
        }
        EXPECT_LE(s.coverage, optimum + 1e-12);
        if (s.upper_bound) {
          EXPECT_GE(*s.upper_bound + 1e-12, optimum);
        }
        if (s.method == "exact" && method == Method::kExact && !test::kSanitized) {
          EXPECT_TRUE(s.proven_optimal);
        }
        if ((s.method == "exact" || s.method == "best") && s.proven_optimal) {
          ++proven;
          EXPECT_NEAR(s.coverage, optimum, 1e-12);
        }
      }
    }
  }
  EXPECT_GT(checked, 150);
  EXPECT_GE(proven, 27);
}

// The bounds exact uses over states, asked directly: the states' Lagrangian bound on the sum is at
// least the enumerated optimum of every n, and the row-sum bound of a goal at most the fewest
// sensors that reach it.
TEST(StatesSum, BoundsHoldTheEnumeratedOptimum) {
  for (uint64_t trial = 0; trial < 12; ++trial) {
    const size_t m = 8 + trial % 4;
    const RandomStates random = MakeStates(7300 + 10 * trial, {10 + trial, 37, 21}, m, 0.3, false);
    std::vector<detail::StateBlock> blocks;
    for (const StateObservations& state : random.states)
      blocks.push_back({state.observations, state.reference_size});
    const detail::CoverageMatrix matrix(blocks);
    const detail::StatesScorer scorer(matrix, OverStates::kSum);
    size_t all_cells = 0;
    for (const size_t r : random.sizes) all_cells += r;
    const auto cells = [&](uint32_t mask) {
      size_t total = 0;
      for (size_t s = 0; s < random.sizes.size(); ++s)
        total += Counted(random.observed[s], mask, 1, false);
      return total;
    };
    std::map<int, size_t> best;
    for (uint32_t mask = 0; mask < (1u << m); ++mask)
      best[Size(mask)] = std::max(best[Size(mask)], cells(mask));
    for (const size_t n : {1, 2, 3, 4}) {
      SCOPED_TRACE(testing::Message() << "trial " << trial << " n " << n);
      std::vector<uint32_t> start(n);
      for (uint32_t i = 0; i < n; ++i) start[i] = i;
      const double bound = detail::StatesLagrangianBound(matrix, OverStates::kSum, n, start, 5);
      const double optimum = static_cast<double>(best[static_cast<int>(n)]) /
                             static_cast<double>(all_cells);
      EXPECT_GE(bound + 1e-12, optimum);
      // The scorer's share is the sum's fraction.
      EXPECT_NEAR(scorer.Fraction(scorer.Covered(start)),
                  static_cast<double>(cells(MaskOf(start))) / static_cast<double>(all_cells),
                  1e-15);
    }
    const size_t goal_cells = std::max<size_t>(1, cells((1u << m) - 1) * 2 / 3);
    const double goal = static_cast<double>(goal_cells) / static_cast<double>(all_cells);
    int fewest = 64;
    for (uint32_t mask = 0; mask < (1u << m); ++mask)
      if (cells(mask) >= goal_cells) fewest = std::min(fewest, Size(mask));
    EXPECT_LE(detail::RowSumGoalBound(scorer, {}, goal, {}), fewest + 1e-9);
  }
}

// Equal sizes: the sum is the mean (Σ c_s / (S·R) = (1/S) Σ c_s / R), so every method gives the
// same answer and value.
TEST(StatesSum, StatesOfEqualSizeGiveTheMeansAnswers) {
  for (uint64_t trial = 0; trial < 6; ++trial) {
    const size_t m = 8 + trial % 3;
    const RandomStates random = MakeStates(7500 + 10 * trial, {24, 24, 24}, m, 0.3, false);
    SelectOptions options;
    options.time_limit = 20;
    options.seed = 3 + trial;
    options.ransac_iterations = 60;
    options.n = 3;
    for (const Method method : {Method::kBest, Method::kRansac, Method::kGreedy, Method::kLocal,
                                Method::kExact, Method::kAll}) {
      options.method = method;
      options.n = method == Method::kBest ? 1 : 3;
      SCOPED_TRACE(testing::Message() << "trial " << trial << " " << MethodName(method));
      const std::vector<StateSelection> sum =
          SelectOverStates(random.states, OverStates::kSum, options);
      const std::vector<StateSelection> mean =
          SelectOverStates(random.states, OverStates::kMean, options);
      ASSERT_EQ(sum.size(), mean.size());
      for (size_t i = 0; i < sum.size(); ++i) {
        EXPECT_EQ(sum[i].selection.method, mean[i].selection.method);
        EXPECT_EQ(sum[i].selection.chosen, mean[i].selection.chosen);
        EXPECT_NEAR(sum[i].selection.coverage, mean[i].selection.coverage, 1e-12);
        EXPECT_EQ(sum[i].selection.proven_optimal, mean[i].selection.proven_optimal);
      }
    }
  }
}

// One state: the sum is the state's plain coverage — the same answers as the mean of one state,
// the evaluator's coverage, and exact's value the plain exact optimum.
TEST(StatesSum, OneStateIsPlainCoverage) {
  for (uint64_t trial = 0; trial < 6; ++trial) {
    const size_t m = 9 + trial % 3;
    const size_t cells = 45;
    const std::vector<Observation> obs = RandomInstance(7700 + trial, m, cells, 0.25, false);
    const StateObservations one{"only", cells, obs};
    SelectOptions options;
    options.time_limit = 20;
    options.seed = 5 + trial;
    options.ransac_iterations = 60;
    options.n = 3;
    const CoverageEvaluator evaluator(obs, cells);
    for (const Method method :
         {Method::kRansac, Method::kGreedy, Method::kLocal, Method::kExact}) {
      options.method = method;
      SCOPED_TRACE(testing::Message() << "trial " << trial << " " << MethodName(method));
      const StateSelection sum = SelectOverStates({&one, 1}, OverStates::kSum, options).at(0);
      const StateSelection mean = SelectOverStates({&one, 1}, OverStates::kMean, options).at(0);
      EXPECT_EQ(sum.selection.chosen, mean.selection.chosen);
      EXPECT_EQ(sum.selection.coverage, evaluator.Coverage(sum.selection.chosen));
      EXPECT_EQ(sum.selection.coverage, mean.selection.coverage);
      if (method == Method::kExact) {
        const Selection plain = Select(obs, cells, options).at(0);
        EXPECT_TRUE(sum.selection.proven_optimal);
        EXPECT_TRUE(plain.proven_optimal);
        EXPECT_EQ(sum.selection.coverage, plain.coverage);
      }
    }
  }
}

TEST(StatesSum, ParsedAndNamed) {
  EXPECT_EQ(ParseOverStates("sum"), OverStates::kSum);
  EXPECT_EQ(OverStatesName(OverStates::kSum), "sum");
  try {
    ParseOverStates("total");
    FAIL() << "no error";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("mean, min or sum"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace vantage
