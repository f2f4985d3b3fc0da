// Combinations that issue 42 turns from refusals into runs on the one selection path (kept
// sensors as fixed variables, thresholds, states): every method's answer checked against
// enumeration of every subset of small random instances, counted here independently of
// src/select — feasible (holds the kept sensors, has n sensors), exact's the optimum with its
// proof, and every bound at least the optimum.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <map>
#include <string>
#include <vector>

#include "brute_force.hpp"
#include "test_util.hpp"
#include "vantage/error.hpp"
#include "vantage/rng.hpp"
#include "vantage/select.hpp"
#include "vantage/select_states.hpp"

namespace vantage {
namespace {

using test::CostOf;
using test::Counted;
using test::MaskOf;
using test::RandomInstance;
using test::RandomStates;
using test::Size;

// Random scene states: state s has first_size + size_step·s cells and its candidates drawn by
// RandomInstance(seed + s, ...).
RandomStates MakeRandomStates(uint64_t seed, size_t state_count, size_t candidates,
                              size_t first_size, size_t size_step, double p, bool with_hits) {
  std::vector<size_t> sizes;
  for (size_t s = 0; s < state_count; ++s) sizes.push_back(first_size + size_step * s);
  return test::MakeStates(seed, std::move(sizes), candidates, p, with_hits);
}

// --k and --min-points with kept sensors (`--keep-existing`): the kept are fixed variables of
// the same model, so every method adds the best it finds to them.
TEST(SelectionModel, KeptSensorsWithKCoverageAndMinPointsMatchEnumeration) {
  int checked = 0;
  for (uint64_t trial = 0; trial < 24; ++trial) {
    const size_t m = 7 + trial % 6;
    const size_t cells = 30;
    const bool points = trial % 3 == 2;
    const std::vector<Observation> obs = RandomInstance(2100 + trial, m, cells, 0.3, points);
    SelectOptions options;
    options.time_limit = 20;
    options.seed = 5 + trial;
    options.ransac_iterations = 50;
    const uint32_t threshold = points ? 3 : 2 + static_cast<uint32_t>(trial % 2);
    if (points) {
      options.min_points = threshold;
    } else {
      options.k = static_cast<int>(threshold);
    }
    options.fixed = trial % 2 == 0 ? std::vector<uint32_t>{1} : std::vector<uint32_t>{0, 3};
    options.n = static_cast<int>(std::max<size_t>(options.fixed.size() + 2, threshold));
    const uint32_t kept = MaskOf(options.fixed);
    // The enumerated optimum of every n up to options.n.
    std::map<int, size_t> best;
    for (uint32_t mask = 0; mask < (1u << m); ++mask) {
      if ((mask & kept) != kept || Size(mask) > options.n) continue;
      size_t& b = best[Size(mask)];
      b = std::max(b, Counted(obs, mask, threshold, points));
    }
    for (const Method method :
         {Method::kAll, Method::kRansac, Method::kGreedy, Method::kLocal, Method::kExact}) {
      options.method = method;
      SCOPED_TRACE(testing::Message() << "trial " << trial << " threshold " << threshold
                                      << " points " << points << " method "
                                      << MethodName(method));
      const std::vector<Selection> results = Select(obs, cells, options);
      ASSERT_FALSE(results.empty());
      for (const Selection& s : results) {
        SCOPED_TRACE(testing::Message() << s.method << " n " << s.n);
        const uint32_t mask = MaskOf(s.chosen);
        ++checked;
        EXPECT_EQ(Size(mask), s.n);  // distinct
        EXPECT_EQ(mask & kept, kept);
        EXPECT_LE(s.n, options.n);
        if (method != Method::kAll) {
          EXPECT_EQ(s.n, options.n);
        }
        const size_t covered = Counted(obs, mask, threshold, points);
        EXPECT_NEAR(s.coverage, static_cast<double>(covered) / cells, 1e-12);
        EXPECT_LE(covered, best[s.n]);
        if (s.upper_bound) {
          EXPECT_GE(*s.upper_bound + 1e-12, static_cast<double>(best[s.n]) / cells);
        }
        if (s.method == "exact") {
          EXPECT_TRUE(s.proven_optimal);
          EXPECT_EQ(covered, best[s.n]);
        }
      }
    }
  }
  EXPECT_GT(checked, 150);
}


// --over-states with --k: the states' aggregate (mean, or min) of each state's k-coverage.
TEST(SelectionModel, KCoverageOverStatesMatchesEnumeration) {
  int checked = 0;
  for (uint64_t trial = 0; trial < 8; ++trial) {
    const size_t m = 7 + trial % 3;
    const OverStates over = trial % 2 == 0 ? OverStates::kMean : OverStates::kMin;
    const size_t state_count = 2 + trial % 2;
    const RandomStates random = MakeRandomStates(3100 + 10 * trial, state_count, m, 20, 7, 0.35, false);
    const auto& [observed, sizes, states] = random;
    SelectOptions options;
    options.time_limit = test::kSanitized ? 3 : 20;  // see test::kSanitized
    options.seed = 9 + trial;
    options.ransac_iterations = 50;
    options.k = 2;
    options.n = 3 + static_cast<int>(trial % 2);
    const auto aggregate = [&](uint32_t mask) {
      double sum = 0, least = 1;
      for (size_t s = 0; s < state_count; ++s) {
        const double f = static_cast<double>(Counted(observed[s], mask, 2, false)) /
                         static_cast<double>(sizes[s]);
        sum += f;
        least = std::min(least, f);
      }
      return over == OverStates::kMean ? sum / static_cast<double>(state_count) : least;
    };
    std::map<int, double> best;
    for (uint32_t mask = 0; mask < (1u << m); ++mask)
      if (Size(mask) <= options.n) best[Size(mask)] = std::max(best[Size(mask)], aggregate(mask));
    for (const Method method : {Method::kAll, Method::kRansac, Method::kGreedy, Method::kExact}) {
      if (method == Method::kAll && trial >= 2) continue;  // its table: once for mean, min
      options.method = method;
      SCOPED_TRACE(testing::Message() << "trial " << trial << " over " << OverStatesName(over)
                                      << " method " << MethodName(method));
      const std::vector<StateSelection> results = SelectOverStates(states, over, options);
      ASSERT_FALSE(results.empty());
      for (const StateSelection& r : results) {
        const Selection& s = r.selection;
        SCOPED_TRACE(testing::Message() << s.method << " n " << s.n);
        ++checked;
        const uint32_t mask = MaskOf(s.chosen);
        EXPECT_EQ(Size(mask), s.n);
        EXPECT_GE(s.n, 2);  // n = k ... N
        if (method != Method::kAll) {
          EXPECT_EQ(s.n, options.n);
        }
        EXPECT_EQ(s.k, 2);
        EXPECT_EQ(s.objective, "k-coverage");
        EXPECT_NEAR(s.coverage, aggregate(mask), 1e-12);
        ASSERT_EQ(r.state_coverage.size(), state_count);
        for (size_t st = 0; st < state_count; ++st)
          EXPECT_NEAR(r.state_coverage[st],
                      static_cast<double>(Counted(observed[st], mask, 2, false)) /
                          static_cast<double>(sizes[st]),
                      1e-12);
        EXPECT_LE(s.coverage, best[s.n] + 1e-12);
        if (s.upper_bound) {
          EXPECT_GE(*s.upper_bound + 1e-12, best[s.n]);
        }
        // `--method exact` has the whole limit to prove it; `all` shares at most 6 s among its
        // n's, so there only a proof is checked.
        if (s.method == "exact" && method == Method::kExact && !test::kSanitized) {
          EXPECT_TRUE(s.proven_optimal);
        }
        if (s.method == "exact" && s.proven_optimal) {
          EXPECT_NEAR(s.coverage, best[s.n], 1e-12);
        }
      }
    }
  }
  EXPECT_GT(checked, 40);
}


// RANSAC for a budget and for a goal (fewest, or cheapest), with and without conflicting pairs:
// every answer fits the budget (reaches the goal) and the pairs, is never better than the
// enumerated optimum, and the same seed gives the same answer.
TEST(SelectionModel, RansacForBudgetsAndGoalsIsFeasibleAndRepeatable) {
  int checked = 0;
  for (uint64_t trial = 0; trial < 24; ++trial) {
    const size_t m = 7 + trial % 6;
    const size_t cells = 30;
    const std::vector<Observation> obs = RandomInstance(4100 + trial, m, cells, 0.3, false);
    Rng rng(4200 + trial, Stream::kTest, 0);
    SelectOptions options;
    options.method = Method::kRansac;
    options.seed = 3 + trial;
    options.ransac_iterations = 40;
    for (size_t i = 0; i < m; ++i) options.costs.push_back(1.0 + static_cast<double>(rng.Below(4)));
    if (trial % 3 == 1) options.constraints.conflicts = {{0, 1}, {2, 3}};
    const bool is_budget = trial % 2 == 0;
    const uint32_t all = (1u << m) - 1;
    const auto allowed = [&](uint32_t mask) {
      std::vector<uint32_t> set;
      for (uint32_t i = 0; i < m; ++i)
        if (mask >> i & 1) set.push_back(i);
      return test::SatisfiesConstraints(obs, set, options.constraints);
    };
    size_t goal = 0;
    if (is_budget) {
      options.budget = 2.0 + static_cast<double>(trial % 5);
    } else {
      size_t most = 0;  // what the allowed sets reach together
      for (uint32_t mask = 1; mask <= all; ++mask)
        if (allowed(mask)) most = std::max(most, Counted(obs, mask, 1, false));
      goal = std::max<size_t>(1, most * 3 / 4);
      options.goal = static_cast<double>(goal) / cells;
      // A goal's cost under installation constraints too (trials 1 and 13).
      options.minimize_cost = trial % 4 == 1;
      if (!options.minimize_cost) options.costs.clear();
    }
    const auto price = [&](uint32_t mask) {
      return options.minimize_cost ? CostOf(options.costs, mask) : static_cast<double>(Size(mask));
    };
    double best = is_budget ? 0.0 : 1e300;
    for (uint32_t mask = 1; mask <= all; ++mask) {
      if (!allowed(mask)) continue;
      if (is_budget && CostOf(options.costs, mask) <= *options.budget + 1e-9)
        best = std::max(best, static_cast<double>(Counted(obs, mask, 1, false)));
      if (!is_budget && Counted(obs, mask, 1, false) >= goal) best = std::min(best, price(mask));
    }
    SCOPED_TRACE(testing::Message() << "trial " << trial << " budget " << is_budget << " cost "
                                    << options.minimize_cost << " conflicts "
                                    << options.constraints.conflicts.size());
    const std::vector<Selection> first = Select(obs, cells, options);
    const std::vector<Selection> again = Select(obs, cells, options);
    ASSERT_EQ(first.size(), 1u);
    ASSERT_EQ(again.size(), 1u);
    const Selection& s = first[0];
    EXPECT_EQ(s.method, "ransac");
    EXPECT_EQ(s.chosen, again[0].chosen);
    const uint32_t mask = MaskOf(s.chosen);
    EXPECT_EQ(Size(mask), s.n);
    EXPECT_TRUE(allowed(mask));
    const size_t covered = Counted(obs, mask, 1, false);
    EXPECT_NEAR(s.coverage, static_cast<double>(covered) / cells, 1e-12);
    if (is_budget) {
      EXPECT_LE(CostOf(options.costs, mask), *options.budget + 1e-9);
      EXPECT_LE(static_cast<double>(covered), best);
    } else {
      EXPECT_GE(covered, goal);
      EXPECT_GE(price(mask), best - 1e-9);
    }
    ++checked;
  }
  EXPECT_EQ(checked, 24);
}

// --keep-existing over scene states ("two cameras are installed; the bin fills and empties; add
// two"): the kept sensors are fixed variables of the states' model, for plain coverage, k = 2 and
// point counts, mean and min, with and without a conflicting pair.
TEST(SelectionModel, KeptSensorsOverStatesMatchEnumeration) {
  int checked = 0;
  for (uint64_t trial = 0; trial < 12; ++trial) {
    const size_t m = 7 + trial % 3;
    const OverStates over = trial % 2 == 0 ? OverStates::kMean : OverStates::kMin;
    const size_t state_count = 2 + trial % 2;
    const int mode = static_cast<int>(trial / 2 % 3);  // plain, k = 2, min_points = 3
    const bool points = mode == 2;
    const uint32_t threshold = mode == 0 ? 1 : mode == 1 ? 2 : 3;
    const RandomStates random = MakeRandomStates(4100 + 10 * trial, state_count, m, 18, 5, 0.3, points);
    const auto& [observed, sizes, states] = random;
    SelectOptions options;
    options.time_limit = 20;
    options.seed = 3 + trial;
    options.ransac_iterations = 50;
    if (mode == 1) options.k = 2;
    if (points) options.min_points = threshold;
    options.fixed = trial % 4 < 2 ? std::vector<uint32_t>{1} : std::vector<uint32_t>{0, 3};
    options.n = static_cast<int>(options.fixed.size()) + 2;
    const bool with_conflict = trial >= 6;
    if (with_conflict) options.constraints.conflicts.push_back({2, 5});
    const uint32_t kept = MaskOf(options.fixed);
    const auto allowed = [&](uint32_t mask) {
      return (mask & kept) == kept && !(with_conflict && (mask >> 2 & 1) && (mask >> 5 & 1));
    };
    const auto aggregate = [&](uint32_t mask) {
      double sum = 0, least = 1;
      for (size_t s = 0; s < state_count; ++s) {
        const double f = static_cast<double>(Counted(observed[s], mask, threshold, points)) /
                         static_cast<double>(sizes[s]);
        sum += f;
        least = std::min(least, f);
      }
      return over == OverStates::kMean ? sum / static_cast<double>(state_count) : least;
    };
    std::map<int, double> best;
    for (uint32_t mask = 0; mask < (1u << m); ++mask)
      if (allowed(mask) && Size(mask) <= options.n)
        best[Size(mask)] = std::max(best[Size(mask)], aggregate(mask));
    std::vector<Method> methods{Method::kRansac, Method::kGreedy, Method::kLocal, Method::kExact};
    if (trial < 4) methods.push_back(Method::kAll);
    if (threshold == 1) methods.push_back(Method::kBest);
    for (const Method method : methods) {
      options.method = method;
      // Best is the single addition: n one above the kept.
      options.n = static_cast<int>(options.fixed.size()) + (method == Method::kBest ? 1 : 2);
      SCOPED_TRACE(testing::Message() << "trial " << trial << " over " << OverStatesName(over)
                                      << " threshold " << threshold << " method "
                                      << MethodName(method));
      const std::vector<StateSelection> results = SelectOverStates(states, over, options);
      ASSERT_FALSE(results.empty());
      for (const StateSelection& r : results) {
        const Selection& s = r.selection;
        SCOPED_TRACE(testing::Message() << s.method << " n " << s.n);
        ++checked;
        const uint32_t mask = MaskOf(s.chosen);
        EXPECT_EQ(Size(mask), s.n);
        EXPECT_TRUE(allowed(mask));
        EXPECT_LE(s.n, options.n);
        if (method != Method::kAll) {
          EXPECT_EQ(s.n, options.n);
        }
        EXPECT_NEAR(s.coverage, aggregate(mask), 1e-12);
        EXPECT_LE(s.coverage, best[s.n] + 1e-12);
        if (s.upper_bound) {
          EXPECT_GE(*s.upper_bound + 1e-12, best[s.n]);
        }
        if (s.method == "exact" && method == Method::kExact) {
          EXPECT_TRUE(s.proven_optimal);
        }
        if (s.proven_optimal) {
          EXPECT_NEAR(s.coverage, best[s.n], 1e-12);
        }
      }
    }
  }
  EXPECT_GT(checked, 60);
}


// The rules of one random instance: none, conflicting pairs, a calibration rule, kept sensors,
// or conflicts with a kept sensor (`variant` 0..4).
struct Rules {
  InstallConstraints constraints;
  std::vector<uint32_t> fixed;
};

Rules RandomRules(int variant, size_t m, Rng* rng) {
  Rules rules;
  if (variant == 1 || variant == 4) {
    for (uint32_t a = 0; a < m; ++a)
      for (uint32_t b = a + 1; b < m; ++b)
        if (rng->Uniform01() < 0.25)
          rules.constraints.conflicts.push_back({a, b, ConflictKind::kSeparation, 0});
  }
  if (variant == 2) rules.constraints.calibration = CalibrationRule{2, std::nullopt};
  if (variant == 3) rules.fixed = {0, 3};
  if (variant == 4) {
    rules.fixed = {1};
    std::erase_if(rules.constraints.conflicts, [](const Conflict& c) { return c.a == 1 || c.b == 1; });
  }
  return rules;
}

std::vector<uint32_t> Members(uint32_t mask, size_t m) {
  std::vector<uint32_t> set;
  for (uint32_t i = 0; i < m; ++i)
    if (mask >> i & 1) set.push_back(i);
  return set;
}

// `--budget` with `--k 2` or `--min-points 3` (refused before: "goal, k >= 2 and budget are
// separate objectives"): the most cells seen twice (holding 3 points) for a total cost within the
// budget, with conflicts, a calibration rule or kept sensors. Every method's answer fits the
// budget and the rules and holds the kept sensors; exact's is the enumerated optimum, proven; every
// upper bound is at least the optimum.
TEST(SelectionModel, BudgetCountedKTimesOrInPointsMatchesEnumeration) {
  int checked = 0;
  for (uint64_t trial = 0; trial < 20; ++trial) {
    const size_t m = 8 + trial % 5;  // 8 .. 12 candidates
    const size_t cells = 30;
    const bool points = trial % 2 == 1;
    const uint32_t threshold = points ? 3 : 2;
    const std::vector<Observation> obs = RandomInstance(5100 + trial, m, cells, 0.35, points);
    Rng rng(5200 + trial, Stream::kTest, 0);
    const int variant = static_cast<int>(trial / 2 % 5);
    const Rules rules = RandomRules(variant, m, &rng);
    SelectOptions options;
    options.time_limit = test::kSanitized ? 5 : 20;  // see test::kSanitized
    options.seed = 7 + trial;
    options.ransac_iterations = 60;
    if (points) {
      options.min_points = threshold;
    } else {
      options.k = static_cast<int>(threshold);
    }
    for (size_t i = 0; i < m; ++i) {
      options.costs.push_back(trial % 3 == 2 ? 0.5 + 0.25 * static_cast<double>(rng.Below(9))
                                             : 1.0 + static_cast<double>(rng.Below(4)));
    }
    options.budget = 5.0 + static_cast<double>(trial % 3);
    options.constraints = rules.constraints;
    options.fixed = rules.fixed;
    const uint32_t kept = MaskOf(rules.fixed);
    const auto allowed = [&](uint32_t mask) {
      return (mask & kept) == kept && CostOf(options.costs, mask) <= *options.budget + 1e-9 &&
             test::SatisfiesConstraints(obs, Members(mask, m), rules.constraints);
    };
    size_t optimum = 0;
    for (uint32_t mask = 0; mask < (1u << m); ++mask)
      if (allowed(mask)) optimum = std::max(optimum, Counted(obs, mask, threshold, points));
    for (const Method method :
         {Method::kAll, Method::kRansac, Method::kGreedy, Method::kLocal, Method::kExact}) {
      options.method = method;
      SCOPED_TRACE(testing::Message() << "trial " << trial << " variant " << variant
                                      << " threshold " << threshold << " points " << points
                                      << " method " << MethodName(method));
      const std::vector<Selection> results = Select(obs, cells, options);
      ASSERT_EQ(results.size(), method == Method::kAll ? 3u : 1u);
      if (method == Method::kAll) {
        EXPECT_EQ(results[0].method, "greedy");
        EXPECT_EQ(results[1].method, "local");
        EXPECT_EQ(results[2].method, "exact");
      } else {
        EXPECT_EQ(results[0].method, MethodName(method));
      }
      for (const Selection& s : results) {
        SCOPED_TRACE(testing::Message() << s.method);
        ++checked;
        const uint32_t mask = MaskOf(s.chosen);
        EXPECT_EQ(Size(mask), s.n);
        EXPECT_TRUE(allowed(mask));
        EXPECT_EQ(s.objective, "budget");
        EXPECT_EQ(s.k, points ? 1 : 2);
        EXPECT_EQ(s.min_points, options.min_points);
        ASSERT_TRUE(s.cost.has_value());
        EXPECT_NEAR(*s.cost, CostOf(options.costs, mask), 1e-12);
        const size_t covered = Counted(obs, mask, threshold, points);
        EXPECT_NEAR(s.coverage, static_cast<double>(covered) / cells, 1e-12);
        EXPECT_LE(covered, optimum);
        if (s.upper_bound) {
          EXPECT_GE(*s.upper_bound + 1e-12, static_cast<double>(optimum) / cells);
        }
        if (s.method == "exact") {
          ASSERT_TRUE(s.upper_bound.has_value());
          if (!test::kSanitized) {
            EXPECT_TRUE(s.proven_optimal);
          }
          if (s.proven_optimal) {
            EXPECT_EQ(covered, optimum);
          }
        }
      }
    }
  }
  EXPECT_EQ(checked, 20 * 7);
}

// A goal counted twice (`--k 2`) or in points (`--min-points 3`) with kept sensors, and a goal
// counted so or by cost (`--cheapest`) under installation constraints — each refused before ("does
// not combine with kept sensors yet", "does not combine with installation constraints yet"): the
// fewest (cheapest) sensors that hold the kept ones, keep the rules and reach the goal. Every
// answer reaches it and keeps the rules; exact's is the enumerated optimum, proven; every lower
// bound is at most the optimum. A goal that all candidates reach but no set under the rules does is
// refused, naming what the rules allow.
TEST(SelectionModel, GoalCountedKTimesOrInPointsWithKeptAndRulesMatchesEnumeration) {
  int checked = 0, refused = 0;
  for (uint64_t trial = 0; trial < 24; ++trial) {
    const size_t m = 8 + trial % 5;  // 8 .. 12 candidates
    const size_t cells = 30;
    const int mode = static_cast<int>(trial % 3);  // k = 2, min_points = 3, k = 1 (cheapest)
    const bool points = mode == 1;
    const uint32_t threshold = mode == 0 ? 2 : mode == 1 ? 3 : 1;
    const std::vector<Observation> obs = RandomInstance(6100 + trial, m, cells, 0.35, points);
    Rng rng(6200 + trial, Stream::kTest, 0);
    const int variant = 1 + static_cast<int>(trial / 3 % 4);  // conflicts, calibration, kept, both
    const Rules rules = RandomRules(variant, m, &rng);
    const bool cheapest = mode == 2 || trial % 2 == 1;
    SelectOptions options;
    options.time_limit = test::kSanitized ? 5 : 20;  // see test::kSanitized
    options.seed = 11 + trial;
    options.ransac_iterations = 60;
    if (points) options.min_points = threshold;
    if (mode == 0) options.k = 2;
    options.minimize_cost = cheapest;
    if (cheapest) {
      for (size_t i = 0; i < m; ++i)
        options.costs.push_back(0.5 + 0.5 * static_cast<double>(rng.Below(6)));
    }
    options.constraints = rules.constraints;
    options.fixed = rules.fixed;
    const uint32_t kept = MaskOf(rules.fixed);
    const auto allowed = [&](uint32_t mask) {
      return (mask & kept) == kept &&
             test::SatisfiesConstraints(obs, Members(mask, m), rules.constraints);
    };
    const auto price = [&](uint32_t mask) {
      return cheapest ? CostOf(options.costs, mask) : static_cast<double>(Size(mask));
    };
    size_t most = 0;  // what the sets the rules allow reach
    for (uint32_t mask = 0; mask < (1u << m); ++mask)
      if (allowed(mask)) most = std::max(most, Counted(obs, mask, threshold, points));
    const size_t everyone = Counted(obs, (1u << m) - 1, threshold, points);
    ASSERT_GT(most, 2u);
    SCOPED_TRACE(testing::Message() << "trial " << trial << " variant " << variant
                                    << " threshold " << threshold << " points " << points
                                    << " cheapest " << cheapest);
    if (most < everyone) {  // the rules make the rest unreachable: refused, naming that
      options.goal = static_cast<double>(most + 1) / cells;
      options.method = Method::kGreedy;
      try {
        Select(obs, cells, options);
        ADD_FAILURE() << "a goal above what the rules allow ran";
      } catch (const InputError& e) {
        EXPECT_NE(std::string(e.what()).find("cannot be reached"), std::string::npos) << e.what();
        ++refused;
      }
    }
    const size_t goal_cells = std::max<size_t>(1, most * 3 / 5);
    options.goal = static_cast<double>(goal_cells) / cells;
    double optimum = 1e300;
    for (uint32_t mask = 0; mask < (1u << m); ++mask)
      if (allowed(mask) && Counted(obs, mask, threshold, points) >= goal_cells)
        optimum = std::min(optimum, price(mask));
    for (const Method method : {Method::kAll, Method::kRansac, Method::kGreedy, Method::kExact}) {
      options.method = method;
      SCOPED_TRACE(testing::Message() << "method " << MethodName(method));
      const std::vector<Selection> results = Select(obs, cells, options);
      ASSERT_FALSE(results.empty());
      for (const Selection& s : results) {
        SCOPED_TRACE(testing::Message() << s.method);
        ++checked;
        const uint32_t mask = MaskOf(s.chosen);
        EXPECT_EQ(Size(mask), s.n);
        EXPECT_TRUE(allowed(mask));
        EXPECT_EQ(s.objective, "set-cover");
        EXPECT_EQ(s.k, mode == 0 ? 2 : 1);
        EXPECT_EQ(s.cost.has_value(), cheapest);
        const size_t covered = Counted(obs, mask, threshold, points);
        EXPECT_NEAR(s.coverage, static_cast<double>(covered) / cells, 1e-12);
        EXPECT_GE(covered, goal_cells);
        EXPECT_GE(price(mask), optimum - 1e-9);
        if (s.n_lower_bound) {
          EXPECT_LE(*s.n_lower_bound, optimum + 1e-9);
        }
        if (s.cost_lower_bound) {
          EXPECT_LE(*s.cost_lower_bound, optimum + 1e-9);
        }
        if (s.method == "kept") {  // the kept sensors reach the goal alone: the optimum
          EXPECT_EQ(mask, kept);
          EXPECT_NEAR(price(mask), optimum, 1e-9);
        }
        if (s.method == "exact") {
          EXPECT_TRUE(cheapest ? s.cost_lower_bound.has_value() : s.n_lower_bound.has_value());
          if (!test::kSanitized) {
            EXPECT_TRUE(s.proven_optimal);
          }
          if (s.proven_optimal) {
            EXPECT_NEAR(price(mask), optimum, 1e-9);
          }
        }
      }
    }
  }
  EXPECT_GE(checked, 24 * 4);
  EXPECT_GT(refused, 0);
}

// What stays refused is what has no answer: k above the candidates, a goal above what all of them
// reach (counted as the goal counts), and two thresholds at once.
TEST(SelectionModel, OnlyMeaninglessCombinationsAreRefused) {
  const std::vector<Observation> obs = RandomInstance(7100, 6, 20, 0.4, true);
  const auto message = [&](const SelectOptions& o) {
    try {
      Select(obs, 20, o);
    } catch (const InputError& e) {
      return std::string(e.what());
    }
    return std::string("ran");
  };
  SelectOptions budget;
  budget.budget = 3;
  budget.costs = std::vector<double>(6, 1.0);
  budget.k = 7;
  EXPECT_NE(message(budget).find("k = 7 is above the 6 candidates"), std::string::npos);
  budget.k = 2;
  EXPECT_EQ(message(budget), "ran");
  budget.min_points = 2;
  EXPECT_NE(message(budget).find("give --k or --min-points, not both"), std::string::npos);
  budget.k = 1;
  EXPECT_EQ(message(budget), "ran");
  SelectOptions goal;
  goal.goal = 1.0;
  goal.k = 2;
  goal.fixed = {0};
  EXPECT_NE(message(goal).find("that all 6 candidates reach together"), std::string::npos);
  goal.constraints.conflicts = {{0, 1, ConflictKind::kSeparation, 0}};
  EXPECT_NE(message(goal).find("(cells seen 2 times) that all 6 candidates reach together"),
            std::string::npos)
      << message(goal);
  SelectOptions both = goal;
  both.budget = 3;
  both.costs = budget.costs;
  EXPECT_NE(message(both).find("goal and budget are separate objectives"), std::string::npos);
}

}  // namespace
}  // namespace vantage
