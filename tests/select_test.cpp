// Selection methods against answers derived here: hand-worked instances, and brute force over
// every n-subset of tiny random instances (SYSTEM.md, Select and the coverage metric).
#include "vantage/select.hpp"

#include <coin/Clp_C_Interface.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <atomic>
#include <bit>
#include <chrono>
#include <cmath>
#include <iterator>
#include <limits>
#include <map>
#include <numeric>
#include <set>
#include <string>

#include <coin/Clp_C_Interface.h>

#include <tbb/task_arena.h>

#include "brute_force.hpp"
#include "pipeline/common.hpp"
#include "select/coverage_matrix.hpp"
#include "select/lp_bound.hpp"
#include "select/methods.hpp"
#include "select/model.hpp"
#include "select/objective_bounds.hpp"
#include "test_util.hpp"
#include "vantage/error.hpp"
#include "vantage/interrupt.hpp"
#include "vantage/rng.hpp"

namespace vantage {
namespace {

// The selection model's exact answer for k-coverage and for a budget, in cells.
detail::ExactResult InCells(detail::ExactAnswer answer) {
  return {std::move(answer.chosen), static_cast<uint64_t>(answer.bound), answer.proven_optimal,
          std::move(answer.note)};
}

detail::ExactResult ExactK(const detail::CoverageMatrix& matrix, size_t n, int k,
                           const std::vector<uint32_t>& start, double time_limit,
                           bool may_enumerate) {
  detail::SelectionModel model;
  model.matrix = &matrix;
  model.threshold = k;
  model.capacity = static_cast<double>(n);
  detail::ExactHints hints;
  hints.may_enumerate = may_enumerate;
  return InCells(detail::SolveExactModel(model, start, time_limit, hints));
}

detail::ExactResult ExactBudget(const detail::CoverageMatrix& matrix,
                                std::span<const double> costs, double budget,
                                const std::vector<uint32_t>& start, double time_limit) {
  detail::SelectionModel model;
  model.matrix = &matrix;
  model.costs = costs;
  model.capacity = budget;
  return InCells(detail::SolveExactModel(model, start, time_limit));
}

Observation Obs(std::vector<uint32_t> cells, std::vector<uint64_t> outside = {}) {
  Observation o;
  o.reference_indices = std::move(cells);
  o.outside_keys = std::move(outside);
  return o;
}

// Each candidate sees each of `cells` reference cells with probability `p`, and a few keys
// outside R.
std::vector<Observation> RandomInstance(uint64_t seed, size_t candidates, size_t cells, double p) {
  Rng rng(seed, Stream::kTest, 0);
  std::vector<Observation> obs(candidates);
  for (Observation& o : obs) {
    for (uint32_t c = 0; c < cells; ++c) {
      if (rng.Uniform01() < p) o.reference_indices.push_back(c);
    }
    for (uint64_t k = 0; k < 8; ++k) {
      if (rng.Uniform01() < 0.3) o.outside_keys.push_back(1000 + k);
    }
  }
  return obs;
}

// |∪ reference_indices| computed independently of the library.
size_t UnionSize(const std::vector<Observation>& obs, const std::vector<uint32_t>& chosen) {
  std::set<uint32_t> cells;
  for (uint32_t c : chosen)
    cells.insert(obs[c].reference_indices.begin(), obs[c].reference_indices.end());
  return cells.size();
}

// Largest union over all n-subsets.
size_t BruteForceOptimum(const std::vector<Observation>& obs, size_t n) {
  const size_t m = obs.size();
  std::vector<bool> pick(m, false);
  std::fill(pick.begin(), pick.begin() + static_cast<std::ptrdiff_t>(n), true);
  size_t best = 0;
  do {
    std::vector<uint32_t> chosen;
    for (uint32_t i = 0; i < m; ++i) {
      if (pick[i]) chosen.push_back(i);
    }
    best = std::max(best, UnionSize(obs, chosen));
  } while (std::prev_permutation(pick.begin(), pick.end()));
  return best;
}

// Textbook greedy (no laziness): largest gain, ties to the lower index, then lowest-index fill.
std::vector<uint32_t> PlainGreedy(const std::vector<Observation>& obs, size_t n) {
  std::vector<uint32_t> chosen;
  std::vector<bool> used(obs.size(), false);
  while (chosen.size() < n) {
    const size_t base = UnionSize(obs, chosen);
    size_t best_gain = 0;
    int best = -1;
    for (uint32_t i = 0; i < obs.size(); ++i) {
      if (used[i]) continue;
      std::vector<uint32_t> with = chosen;
      with.push_back(i);
      const size_t gain = UnionSize(obs, with) - base;
      if (best < 0 || gain > best_gain) {
        best_gain = gain;
        best = static_cast<int>(i);
      }
    }
    used[best] = true;
    chosen.push_back(static_cast<uint32_t>(best));
  }
  return chosen;
}

std::vector<uint32_t> Sorted(std::vector<uint32_t> v) {
  std::sort(v.begin(), v.end());
  return v;
}

SelectOptions Options(Method method, int n) {
  SelectOptions options;
  options.method = method;
  options.n = n;
  return options;
}

Selection SelectOne(const std::vector<Observation>& obs,
                    size_t reference_size,
                    Method method,
                    int n) {
  const std::vector<Selection> results = Select(obs, reference_size, Options(method, n));
  EXPECT_EQ(results.size(), 1u);
  return results.at(0);
}

// ---------------------------------------------------------------------------------------------
// Names and options

TEST(Select, MethodNamesRoundTrip) {
  for (const Method m : {Method::kBest, Method::kRansac, Method::kGreedy, Method::kLocal,
                         Method::kExact, Method::kAll}) {
    EXPECT_EQ(ParseMethod(MethodName(m)), m);
  }
  EXPECT_EQ(MethodName(Method::kGreedy), "greedy");
  EXPECT_EQ(ParseMethod("exact"), Method::kExact);
}

TEST(Select, UnknownMethodListsTheNames) {
  try {
    ParseMethod("fastest");
    FAIL() << "no InputError";
  } catch (const InputError& e) {
    EXPECT_EQ(std::string(e.what()),
              "unknown method 'fastest' — use one of best, ransac, greedy, local, exact, all");
  }
}

TEST(Select, ValidateRejectsBadOptions) {
  EXPECT_NO_THROW(SelectOptions{}.Validate(1));
  SelectOptions o;
  o.n = 0;
  EXPECT_THROW(o.Validate(5), InputError);
  o.n = 6;
  try {
    o.Validate(5);
    FAIL() << "no InputError";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("5 candidates"), std::string::npos) << e.what();
  }
  o.n = 5;
  EXPECT_NO_THROW(o.Validate(5));
  EXPECT_THROW(SelectOptions{}.Validate(0), InputError);

  SelectOptions it;
  it.ransac_iterations = 0;
  EXPECT_THROW(it.Validate(3), InputError);
  for (double c : {-0.1, 1.5, std::numeric_limits<double>::quiet_NaN()}) {
    SelectOptions s;
    s.ransac_stop_coverage = c;
    EXPECT_THROW(s.Validate(3), InputError) << c;
  }
  for (double c : {0.0, 1.0}) {
    SelectOptions s;
    s.ransac_stop_coverage = c;
    EXPECT_NO_THROW(s.Validate(3)) << c;
  }
  for (double t : {0.0, -1.0, std::numeric_limits<double>::quiet_NaN(), 1e-300, 0.999e-3,
                   1.001e6}) {
    SelectOptions s;
    s.time_limit = t;
    EXPECT_THROW(s.Validate(3), InputError) << t;
  }
  for (double t : {1e-3, 1e6}) {
    SelectOptions s;
    s.time_limit = t;
    EXPECT_NO_THROW(s.Validate(3)) << t;
  }
}

// The kind of each combination of the model's terms, written out here from select.hpp's
// contract (what a cell needs, how an answer is scored and named, what bounds it, which methods
// apply), against KindFor and against what Validate accepts.
TEST(SelectionModel, KindOfEveryCombination) {
  using Limit = detail::SelectionKind::Limit;
  struct Case {
    const char* name;
    std::optional<double> goal;
    std::optional<double> budget;
    int k;
    std::optional<uint32_t> min_points;
    const char* objective;
    int threshold, scored_k;
    Limit limit;
    bool on_one_state;
    std::vector<Method> methods;
  };
  const std::vector<Method> coverage_methods = {Method::kBest,  Method::kRansac, Method::kGreedy,
                                                Method::kLocal, Method::kExact,  Method::kAll};
  const std::vector<Method> no_best = {Method::kRansac, Method::kGreedy, Method::kLocal,
                                       Method::kExact, Method::kAll};
  const std::vector<Method> goal_methods = {Method::kRansac, Method::kGreedy, Method::kExact,
                                            Method::kAll};
  const std::vector<Case> cases = {
      {"coverage", {}, {}, 1, {}, "coverage", 1, 1, Limit::kSensors, false, coverage_methods},
      {"k 2", {}, {}, 2, {}, "k-coverage", 2, 2, Limit::kSensors, false, no_best},
      {"points 3", {}, {}, 1, 3u, "min-points", 3, 1, Limit::kSensors, false, no_best},
      {"points 1", {}, {}, 1, 1u, "min-points", 1, 1, Limit::kSensors, false, no_best},
      {"goal", 0.5, {}, 1, {}, "set-cover", 1, 1, Limit::kGoal, true, goal_methods},
      {"goal k 2", 0.5, {}, 2, {}, "set-cover", 2, 2, Limit::kGoal, true, goal_methods},
      {"goal points 2", 0.5, {}, 1, 2u, "set-cover", 2, 1, Limit::kGoal, true, goal_methods},
      {"budget", {}, 2.0, 1, {}, "budget", 1, 1, Limit::kBudget, false, no_best},
      {"budget k 2", {}, 2.0, 2, {}, "budget", 2, 2, Limit::kBudget, true, no_best},
      {"budget points 1", {}, 2.0, 1, 1u, "budget", 1, 1, Limit::kBudget, true, no_best},
  };
  for (const Case& c : cases) {
    SelectOptions o;
    o.n = 3;
    o.goal = c.goal;
    o.budget = c.budget;
    o.k = c.k;
    o.min_points = c.min_points;
    o.costs.assign(5, 1.0);
    const detail::SelectionKind kind = detail::KindFor(o);
    EXPECT_EQ(ObjectiveName(kind.objective), c.objective) << c.name;
    EXPECT_EQ(kind.threshold, c.threshold) << c.name;
    EXPECT_EQ(detail::Threshold(o), c.threshold) << c.name;
    EXPECT_EQ(kind.k, c.scored_k) << c.name;
    EXPECT_EQ(kind.min_points, c.min_points) << c.name;
    EXPECT_EQ(kind.limit, c.limit) << c.name;
    EXPECT_EQ(kind.on_one_state, c.on_one_state) << c.name;
    for (const Method m : coverage_methods) {
      o.method = m;
      o.n = m == Method::kBest ? 1 : 3;  // best is the n = 1 answer
      const bool applies = std::find(c.methods.begin(), c.methods.end(), m) != c.methods.end();
      EXPECT_EQ(kind.Applies(m), applies) << c.name << " " << MethodName(m);
      if (applies) {
        EXPECT_NO_THROW(o.Validate(5)) << c.name << " " << MethodName(m);
      } else {
        EXPECT_THROW(o.Validate(5), InputError) << c.name << " " << MethodName(m);
      }
    }
  }
}

TEST(Select, MoreSensorsThanCandidatesIsInputError) {
  const std::vector<Observation> obs = {Obs({0}), Obs({1})};
  const CoverageEvaluator evaluator(obs, 2);
  for (const Method m : {Method::kBest, Method::kRansac, Method::kGreedy, Method::kLocal,
                         Method::kExact, Method::kAll}) {
    EXPECT_THROW(Select(obs, 2, Options(m, 3)), InputError) << MethodName(m);
  }
  EXPECT_THROW(SelectGreedy(evaluator, 3), InputError);
  EXPECT_THROW(SelectGreedy(evaluator, 0), InputError);
  EXPECT_THROW(SelectRansac(evaluator, Options(Method::kRansac, 3)), InputError);
  const std::vector<Observation> none;
  EXPECT_THROW(SelectBest(CoverageEvaluator(none, 2)), InputError);
}

// ---------------------------------------------------------------------------------------------
// Coverage

TEST(CoverageEvaluator, UnionAndPaperCoverage) {
  // R has 10 cells. A sees cells 0-2 and outside keys 100, 200; B sees 2-3 and 200, 300.
  const std::vector<Observation> obs = {Obs({0, 1, 2}, {100, 200}), Obs({2, 3}, {200, 300})};
  const CoverageEvaluator evaluator(obs, 10);
  const std::vector<uint32_t> a{0}, ab{0, 1}, aa{0, 0};
  EXPECT_EQ(evaluator.CoveredCount(ab), 4u);
  EXPECT_DOUBLE_EQ(evaluator.Coverage(a), 0.3);
  EXPECT_DOUBLE_EQ(evaluator.Coverage(ab), 0.4);
  EXPECT_DOUBLE_EQ(evaluator.Coverage(aa), 0.3);
  EXPECT_DOUBLE_EQ(evaluator.PaperCoverage(a), 0.5);
  // 4 cells of R plus 100, 200, 300: key 200, seen by both, counts once.
  EXPECT_DOUBLE_EQ(evaluator.PaperCoverage(ab), 0.7);
  EXPECT_DOUBLE_EQ(evaluator.Coverage({}), 0.0);
}

TEST(CoverageEvaluator, EmptyReferenceGivesZero) {
  const std::vector<Observation> obs = {Obs({}, {5, 6}), Obs({}, {7})};
  const CoverageEvaluator evaluator(obs, 0);
  const std::vector<uint32_t> both{0, 1};
  EXPECT_EQ(evaluator.Coverage(both), 0.0);
  EXPECT_EQ(evaluator.PaperCoverage(both), 0.0);
}

TEST(Select, EmptyReferenceRunsEveryMethod) {
  const std::vector<Observation> obs = {Obs({}, {5, 6}), Obs({}, {7}), Obs({})};
  SelectOptions options;
  options.n = 2;
  const std::vector<Selection> results = Select(obs, 0, options);
  ASSERT_EQ(results.size(), 1u + 2 * 4);
  for (const Selection& s : results) {
    EXPECT_EQ(s.coverage, 0.0);
    EXPECT_EQ(s.paper_coverage, 0.0);
    EXPECT_EQ(static_cast<int>(s.chosen.size()), s.n);
  }
}

TEST(Select, PaperCoverageOfTheUnion) {
  // Both candidates see the same outside key 9; the union sees cells 0-3 and key 9 once.
  const std::vector<Observation> obs = {Obs({0, 1}, {9}), Obs({2, 3}, {9})};
  const Selection s = SelectOne(obs, 8, Method::kGreedy, 2);
  EXPECT_DOUBLE_EQ(s.coverage, 4.0 / 8);
  EXPECT_DOUBLE_EQ(s.paper_coverage, 5.0 / 8);
}

// ---------------------------------------------------------------------------------------------
// The merged matrix

TEST(CoverageMatrix, PartitionRefinement) {
  const std::vector<uint32_t> a{0, 1, 2}, b{1, 2, 3};
  const std::vector<std::span<const uint32_t>> sets{a, b};
  const std::vector<int64_t> classes = detail::RefinePartition(6, sets);
  EXPECT_EQ(classes, (std::vector<int64_t>{0, 1, 1, 2, -1, -1}));
}

TEST(CoverageMatrix, MergesCellsSeenBySameCandidates) {
  // Cells 0, 5: only c0; 1, 2: both; 3: only c1; 4, 6: nobody (dropped).
  const std::vector<Observation> obs = {Obs({0, 1, 2, 5}), Obs({1, 2, 3})};
  const detail::CoverageMatrix matrix(obs, 7);
  ASSERT_EQ(matrix.element_count(), 3u);
  EXPECT_EQ(matrix.seen_weight(), 5u);
  EXPECT_EQ(matrix.Weight(0), 2u);  // {0, 5}
  EXPECT_EQ(matrix.Weight(1), 2u);  // {1, 2}
  EXPECT_EQ(matrix.Weight(2), 1u);  // {3}
  EXPECT_EQ(matrix.Row(0), (std::vector<uint32_t>{0, 1}));
  EXPECT_EQ(matrix.Row(1), (std::vector<uint32_t>{1, 2}));
  const std::vector<uint32_t> both{0, 1}, second{1};
  EXPECT_EQ(matrix.CoveredWeight(both), 5u);
  EXPECT_EQ(matrix.CoveredWeight(second), 3u);
}

TEST(CoverageMatrix, StacksStatesWithoutMixingTheirCells) {
  // State 0 (R = 4): c0 {0, 1}, c1 {1, 2}: elements {0} (c0), {1} (both), {2} (c1); cell 3 unseen.
  // State 1 (R = 3): c0 {0}, c1 {0, 2}: elements {0} (both), {2} (c1); cell 1 unseen. Cell 0 of
  // each state is its own element although c0 and c1 see both.
  const std::vector<Observation> first = {Obs({0, 1}), Obs({1, 2})};
  const std::vector<Observation> second = {Obs({0}), Obs({0, 2})};
  const std::vector<detail::StateBlock> states = {{first, 4}, {second, 3}};
  const detail::CoverageMatrix matrix(states);
  ASSERT_EQ(matrix.state_count(), 2u);
  EXPECT_EQ(matrix.reference_size(), 7u);
  EXPECT_EQ(matrix.StateReferenceSize(1), 3u);
  EXPECT_EQ(matrix.StateBegin(0), 0u);
  EXPECT_EQ(matrix.StateBegin(1), 3u);
  EXPECT_EQ(matrix.StateBegin(2), 5u);
  EXPECT_EQ(matrix.Row(0), (std::vector<uint32_t>{0, 1, 3}));
  EXPECT_EQ(matrix.Row(1), (std::vector<uint32_t>{1, 2, 3, 4}));
  EXPECT_EQ(matrix.RowWeight(1), 4u);
  EXPECT_EQ(matrix.seen_weight(), 5u);
  const std::vector<uint32_t> both{0, 1};
  EXPECT_EQ(matrix.CoveredWeight(both), 5u);
}

TEST(CoverageMatrix, CoveredWeightMatchesTheUnion) {
  const std::vector<Observation> obs = RandomInstance(7, 20, 300, 0.15);
  const detail::CoverageMatrix matrix(obs, 300);
  EXPECT_LT(matrix.element_count(), 300u);
  Rng rng(7, Stream::kTest, 1);
  for (int trial = 0; trial < 50; ++trial) {
    std::vector<uint32_t> chosen;
    for (uint32_t i = 0; i < 20; ++i) {
      if (rng.Uniform01() < 0.25) chosen.push_back(i);
    }
    EXPECT_EQ(matrix.CoveredWeight(chosen), UnionSize(obs, chosen));
  }
}

// ---------------------------------------------------------------------------------------------
// Hand-worked instances

// X = cells 0-5 (c0), Y = cells 6-11 (c1), G = {0, 1, 2, 6, 7, 8, 12} (c2); R = 13 cells.
// Greedy takes G (7 cells) first; then X and Y each add 3 and the tie goes to X (c0): 10 cells.
// The optimum is X + Y: 12 cells. Local search swaps G (alone sees 6, 7, 8, 12: loses 4) for Y
// (adds 6-11: gains 6) in place: [1, 0].
std::vector<Observation> ClassicInstance() {
  return {Obs({0, 1, 2, 3, 4, 5}), Obs({6, 7, 8, 9, 10, 11}), Obs({0, 1, 2, 6, 7, 8, 12})};
}

TEST(Select, GreedyIsSuboptimalOnTheClassicInstance) {
  const std::vector<Observation> obs = ClassicInstance();
  const Selection greedy = SelectOne(obs, 13, Method::kGreedy, 2);
  EXPECT_EQ(greedy.method, "greedy");
  EXPECT_EQ(greedy.n, 2);
  EXPECT_EQ(greedy.chosen, (std::vector<uint32_t>{2, 0}));
  EXPECT_DOUBLE_EQ(greedy.coverage, 10.0 / 13);
  EXPECT_FALSE(greedy.upper_bound.has_value());

  const Selection local = SelectOne(obs, 13, Method::kLocal, 2);
  EXPECT_EQ(local.method, "local");
  EXPECT_EQ(local.chosen, (std::vector<uint32_t>{1, 0}));
  EXPECT_DOUBLE_EQ(local.coverage, 12.0 / 13);

  const Selection exact = SelectOne(obs, 13, Method::kExact, 2);
  EXPECT_EQ(exact.method, "exact");
  EXPECT_EQ(Sorted(exact.chosen), (std::vector<uint32_t>{0, 1}));
  EXPECT_DOUBLE_EQ(exact.coverage, 12.0 / 13);
  EXPECT_TRUE(exact.proven_optimal);
  ASSERT_TRUE(exact.upper_bound.has_value());
  EXPECT_NEAR(*exact.upper_bound, 12.0 / 13, 1e-12);
}

TEST(Select, TwoSwapsAndExactEscapeWhereOneSwapIsStuck) {
  // R = 12 cells, n = 2:
  //   c0 = {0,1,2,3,6,7,8,9}  (8)   c1 = {4,5}   c2 = {10,11}
  //   c3 = {0,...,5}          (6)   c4 = {6,...,11}  (6)
  // Greedy: c0, then c1, c2, c3, c4 all add 2 -> c1: 10 cells. From [c0, c1] no 1-swap helps:
  // dropping c0 loses 8 and the best newcomer (c4) brings back 6; dropping c1 loses 2 and any
  // newcomer adds 2. The 2-swap {c0, c1} -> {c3, c4} covers all 12 (c3 to position 0: on equal
  // bring, 6 and 6, the lower index goes first). Exact from the stuck start finds it too.
  const std::vector<Observation> obs = {Obs({0, 1, 2, 3, 6, 7, 8, 9}), Obs({4, 5}), Obs({10, 11}),
                                        Obs({0, 1, 2, 3, 4, 5}), Obs({6, 7, 8, 9, 10, 11})};
  const Selection greedy = SelectOne(obs, 12, Method::kGreedy, 2);
  EXPECT_EQ(greedy.chosen, (std::vector<uint32_t>{0, 1}));
  const detail::CoverageMatrix matrix(obs, 12);
  detail::LocalOptions one_swap;
  one_swap.two_swap = false;
  EXPECT_EQ(detail::LocalSearch(detail::CellScorer(matrix), greedy.chosen, one_swap),
            (std::vector<uint32_t>{0, 1}));
  EXPECT_EQ(detail::LocalSearch(detail::CellScorer(matrix), greedy.chosen),
            (std::vector<uint32_t>{3, 4}));
  const Selection local = SelectOne(obs, 12, Method::kLocal, 2);
  EXPECT_EQ(local.chosen, (std::vector<uint32_t>{3, 4}));
  EXPECT_DOUBLE_EQ(local.coverage, 1.0);

  const detail::ExactResult exact = detail::SolveExact(matrix, 2, {0, 1}, 60);
  EXPECT_EQ(Sorted(exact.chosen), (std::vector<uint32_t>{3, 4}));
  EXPECT_TRUE(exact.proven_optimal);
  EXPECT_EQ(exact.upper_bound, 12u);
  const Selection via_select = SelectOne(obs, 12, Method::kExact, 2);
  EXPECT_EQ(Sorted(via_select.chosen), (std::vector<uint32_t>{3, 4}));
  EXPECT_TRUE(via_select.proven_optimal);
}

TEST(Select, TiesGoToTheLowerIndex) {
  // c0 and c1 see the same 2 cells, c3 also 2: best is c0. After c0, c2 and c3 each add cell 2.
  const std::vector<Observation> obs = {Obs({0, 1}), Obs({0, 1}), Obs({2}), Obs({1, 2})};
  const Selection best = SelectOne(obs, 3, Method::kBest, 1);
  EXPECT_EQ(best.chosen, (std::vector<uint32_t>{0}));
  EXPECT_EQ(best.n, 1);
  const Selection greedy = SelectOne(obs, 3, Method::kGreedy, 2);
  EXPECT_EQ(greedy.chosen, (std::vector<uint32_t>{0, 2}));
  EXPECT_EQ(SelectGreedy(CoverageEvaluator(obs, 3), 2).chosen, greedy.chosen);
}

TEST(Select, GreedyFillsUpToNWithTheLowestUnusedCandidates) {
  // c0 sees 4 cells, c4 adds cell 5, then nothing adds anything: c1, c2 fill up to n = 4.
  const std::vector<Observation> obs = {Obs({0, 1, 2, 3}), Obs({0, 1}), Obs({}), Obs({2}),
                                        Obs({5})};
  const Selection greedy = SelectOne(obs, 6, Method::kGreedy, 4);
  EXPECT_EQ(greedy.n, 4);
  EXPECT_EQ(greedy.chosen, (std::vector<uint32_t>{0, 4, 1, 2}));
  EXPECT_DOUBLE_EQ(greedy.coverage, 5.0 / 6);
  for (const Method m : {Method::kLocal, Method::kExact, Method::kRansac}) {
    const Selection s = SelectOne(obs, 6, m, 4);
    EXPECT_EQ(s.n, 4) << MethodName(m);
    EXPECT_EQ(std::set<uint32_t>(s.chosen.begin(), s.chosen.end()).size(), 4u) << MethodName(m);
  }
}

TEST(Select, ExactReturnsNSensorsWhenFewerSuffice) {
  // c1 and c2 are subsets of c0: c0 alone is optimal, but n = 2 sensors are reported.
  const std::vector<Observation> obs = {Obs({0, 1, 2}), Obs({0, 1}), Obs({1})};
  const Selection exact = SelectOne(obs, 4, Method::kExact, 2);
  EXPECT_EQ(exact.n, 2);
  ASSERT_EQ(exact.chosen.size(), 2u);
  EXPECT_NE(exact.chosen[0], exact.chosen[1]);
  EXPECT_DOUBLE_EQ(exact.coverage, 0.75);
  EXPECT_TRUE(exact.proven_optimal);
  EXPECT_DOUBLE_EQ(*exact.upper_bound, 0.75);
}

// ---------------------------------------------------------------------------------------------
// Random instances against brute force

TEST(Select, EveryMethodAgainstBruteForce) {
  const double greedy_factor = 1.0 - 1.0 / std::exp(1.0);
  for (uint64_t trial = 0; trial < 24; ++trial) {
    const size_t m = 6 + trial % 8;                                // 6-13 candidates
    const size_t r = 20 + 5 * (trial % 5);                         // 20-40 cells
    const double p = 0.1 + 0.05 * static_cast<double>(trial % 4);  // sparse to dense
    const std::vector<Observation> obs = RandomInstance(100 + trial, m, r, p);
    SelectOptions options;
    options.n = static_cast<int>(std::min<size_t>(4, m));
    options.ransac_iterations = 30;
    options.seed = trial;
    const std::vector<Selection> results = Select(obs, r, options);
    std::vector<size_t> optimum(options.n + 1), greedy_cells(options.n + 1);
    for (int n = 1; n <= options.n; ++n) optimum[n] = BruteForceOptimum(obs, n);

    ASSERT_EQ(results.size(), 1u + 4u * options.n);
    for (const Selection& s : results) {
      SCOPED_TRACE(testing::Message() << "trial " << trial << " " << s.method << " n=" << s.n);
      ASSERT_EQ(static_cast<int>(s.chosen.size()), s.n);
      EXPECT_EQ(std::set<uint32_t>(s.chosen.begin(), s.chosen.end()).size(), s.chosen.size());
      for (uint32_t c : s.chosen) EXPECT_LT(c, m);
      const size_t cells = UnionSize(obs, s.chosen);
      EXPECT_DOUBLE_EQ(s.coverage, static_cast<double>(cells) / r);
      EXPECT_LE(s.coverage, 1.0);
      EXPECT_GE(s.paper_coverage, s.coverage);
      EXPECT_LE(cells, optimum[s.n]);
      EXPECT_GE(s.seconds, 0.0);
      if (s.upper_bound) {
        EXPECT_GE(*s.upper_bound, s.coverage);
        EXPECT_GE(*s.upper_bound + 1e-12, static_cast<double>(optimum[s.n]) / r);
      }
      if (s.method == "best") {
        EXPECT_EQ(s.n, 1);
        EXPECT_EQ(cells, optimum[1]);
      } else if (s.method == "greedy") {
        EXPECT_EQ(s.chosen, PlainGreedy(obs, s.n));
        EXPECT_GE(static_cast<double>(cells), greedy_factor * optimum[s.n] - 1e-9);
        greedy_cells[s.n] = cells;
      } else if (s.method == "local") {
        EXPECT_GE(cells, greedy_cells[s.n]);
      } else if (s.method == "exact") {
        ASSERT_TRUE(s.upper_bound.has_value());  // >= the optimum: checked above
        // Under the sanitizers a proof may stop at its time limit (test::kSanitized).
        if (!test::kSanitized || s.proven_optimal) {
          EXPECT_EQ(cells, optimum[s.n]);
          EXPECT_TRUE(s.proven_optimal);
          EXPECT_NEAR(*s.upper_bound, static_cast<double>(optimum[s.n]) / r, 1e-12);
        }
      } else {
        EXPECT_EQ(s.method, "ransac");
      }
    }
  }
}

// The coverage-versus-n curve (issue 16): greedy and local at every n the results lack, up to
// max(6, the results' n), each scored as the union of its sets (counted here), greedy the plain
// greedy of PlainGreedy, local never below greedy nor above the enumerated optimum.
TEST(CoverageCurve, FillsEveryMissingNUpToSixWithGreedyAndLocal) {
  const std::vector<Observation> obs = RandomInstance(21, 10, 40, 0.2);
  SelectOptions options;
  options.n = 2;
  options.method = Method::kGreedy;
  const std::vector<Selection> results = Select(obs, 40, options);  // greedy n = 2 only
  const std::vector<Selection> curve = CoverageCurve(obs, 40, options, results);
  std::set<std::pair<std::string, int>> seen;
  for (const Selection& s : curve) {
    SCOPED_TRACE(testing::Message() << s.method << " n=" << s.n);
    EXPECT_TRUE(seen.insert({s.method, s.n}).second);
    ASSERT_EQ(static_cast<int>(s.chosen.size()), s.n);
    EXPECT_DOUBLE_EQ(s.coverage, static_cast<double>(UnionSize(obs, s.chosen)) / 40);
    EXPECT_LE(UnionSize(obs, s.chosen), BruteForceOptimum(obs, static_cast<size_t>(s.n)));
    EXPECT_FALSE(s.upper_bound.has_value());
    if (s.method == "greedy") {
      EXPECT_EQ(s.chosen, PlainGreedy(obs, s.n));
    }
  }
  std::set<std::pair<std::string, int>> expected;
  for (int n = 1; n <= 6; ++n) {
    if (n != 2) expected.insert({"greedy", n});
    expected.insert({"local", n});
  }
  EXPECT_EQ(seen, expected);
  for (const Selection& s : curve) {
    if (s.method != "local") continue;
    const std::vector<uint32_t> greedy = PlainGreedy(obs, s.n);
    EXPECT_GE(UnionSize(obs, s.chosen), UnionSize(obs, greedy));
  }

  // A run of n = 8 with every method: the curve adds nothing below 8; with 4 candidates it
  // stops at 4; set cover and budget have no curve.
  options.method = Method::kAll;
  options.n = 8;
  EXPECT_TRUE(CoverageCurve(obs, 40, options, Select(obs, 40, options)).empty());
  const std::vector<Observation> four(obs.begin(), obs.begin() + 4);
  options.n = 1;
  int largest = 0;
  for (const Selection& s : CoverageCurve(four, 40, options, Select(four, 40, options)))
    largest = std::max(largest, s.n);
  EXPECT_EQ(largest, 4);
  options.goal = 0.3;
  EXPECT_TRUE(CoverageCurve(obs, 40, options, {}).empty());
}

TEST(Select, AllGivesBestThenEachMethodPerNAndIsDeterministic) {
  const std::vector<Observation> obs = RandomInstance(3, 12, 60, 0.2);
  SelectOptions options;
  options.n = 3;
  options.ransac_iterations = 20;
  const std::vector<Selection> a = Select(obs, 60, options);
  const std::vector<Selection> b = Select(obs, 60, options);
  ASSERT_EQ(a.size(), 1u + 3 * 4);
  EXPECT_EQ(a[0].method, "best");
  EXPECT_EQ(a[0].n, 1);
  const char* order[] = {"ransac", "greedy", "local", "exact"};
  for (int n = 1; n <= 3; ++n) {
    for (int k = 0; k < 4; ++k) {
      const Selection& s = a[1 + 4 * (n - 1) + k];
      EXPECT_EQ(s.method, order[k]);
      EXPECT_EQ(s.n, n);
    }
  }
  ASSERT_EQ(a.size(), b.size());
  for (size_t i = 0; i < a.size(); ++i) {
    EXPECT_EQ(a[i].method, b[i].method);
    EXPECT_EQ(a[i].n, b[i].n);
    EXPECT_EQ(a[i].chosen, b[i].chosen);
    EXPECT_EQ(a[i].coverage, b[i].coverage);
    EXPECT_EQ(a[i].paper_coverage, b[i].paper_coverage);
    EXPECT_EQ(a[i].upper_bound, b[i].upper_bound);
    EXPECT_EQ(a[i].proven_optimal, b[i].proven_optimal);
  }
}

// ---------------------------------------------------------------------------------------------
// RANSAC

TEST(Select, RansacIsReproducibleAndDependsOnTheSeed) {
  const std::vector<Observation> obs = RandomInstance(11, 30, 100, 0.1);
  const CoverageEvaluator evaluator(obs, 100);
  SelectOptions options = Options(Method::kRansac, 3);
  options.ransac_iterations = 5;
  std::set<std::vector<uint32_t>> answers;
  for (uint64_t seed = 1; seed <= 10; ++seed) {
    options.seed = seed;
    const Selection first = SelectRansac(evaluator, options);
    const std::vector<Selection> via_select = Select(obs, 100, options);
    EXPECT_EQ(first.method, "ransac");
    EXPECT_EQ(first.chosen, via_select.at(0).chosen);
    EXPECT_EQ(first.chosen, SelectRansac(evaluator, options).chosen);
    EXPECT_EQ(std::set<uint32_t>(first.chosen.begin(), first.chosen.end()).size(), 3u);
    answers.insert(first.chosen);
  }
  EXPECT_GT(answers.size(), 1u);
}

TEST(Select, RansacKeepsTheBestDrawAndStopsAtTheThreshold) {
  const std::vector<Observation> obs = RandomInstance(12, 40, 200, 0.05);
  const CoverageEvaluator evaluator(obs, 200);
  SelectOptions one = Options(Method::kRansac, 2);
  one.ransac_iterations = 1;
  one.seed = 5;
  const Selection first_draw = SelectRansac(evaluator, one);

  // Iteration 0 draws the same subset whatever the cap; more iterations can only do better.
  SelectOptions many = one;
  many.ransac_iterations = 300;
  const Selection best_of_many = SelectRansac(evaluator, many);
  EXPECT_GE(best_of_many.coverage, first_draw.coverage);
  EXPECT_LE(best_of_many.coverage, static_cast<double>(BruteForceOptimum(obs, 2)) / 200 + 1e-12);

  // A threshold the first draw already meets stops the search after it.
  SelectOptions stop = many;
  stop.ransac_stop_coverage = first_draw.coverage;
  EXPECT_EQ(SelectRansac(evaluator, stop).chosen, first_draw.chosen);
  stop.ransac_stop_coverage = 0.0;
  EXPECT_EQ(SelectRansac(evaluator, stop).chosen, first_draw.chosen);
}

TEST(Select, RansacWithNEqualToTheCandidatesTakesThemAll) {
  const std::vector<Observation> obs = RandomInstance(13, 5, 30, 0.3);
  const Selection s = SelectOne(obs, 30, Method::kRansac, 5);
  EXPECT_EQ(Sorted(s.chosen), (std::vector<uint32_t>{0, 1, 2, 3, 4}));
  EXPECT_DOUBLE_EQ(s.coverage, static_cast<double>(UnionSize(obs, s.chosen)) / 30);
}

TEST(Select, RansacWhenNothingIsSeenStillReturnsNSensors) {
  const std::vector<Observation> obs = {Obs({}), Obs({}), Obs({})};
  const Selection s = SelectOne(obs, 4, Method::kRansac, 2);
  EXPECT_EQ(s.chosen.size(), 2u);
  EXPECT_EQ(s.coverage, 0.0);
}

// ---------------------------------------------------------------------------------------------
// Bounds and the solver's fallback

TEST(Select, SimpleUpperBoundIsAtLeastTheOptimum) {
  for (uint64_t trial = 0; trial < 10; ++trial) {
    const std::vector<Observation> obs = RandomInstance(200 + trial, 9, 30, 0.15);
    const detail::CoverageMatrix matrix(obs, 30);
    for (size_t n = 1; n <= 4; ++n) {
      const std::vector<uint32_t> greedy =
          detail::GreedyComplete(detail::CellScorer(matrix), {}, n);
      EXPECT_GE(detail::SimpleUpperBound(matrix, greedy, n), BruteForceOptimum(obs, n));
      EXPECT_LE(detail::SimpleUpperBound(matrix, greedy, n), 30u);
      EXPECT_GE(detail::GreedyUpperBound(matrix, greedy, n), BruteForceOptimum(obs, n));
      EXPECT_LE(detail::GreedyUpperBound(matrix, greedy, n),
                detail::SimpleUpperBound(matrix, greedy, n));
      const std::vector<uint32_t> none;
      EXPECT_LE(detail::GreedyUpperBound(matrix, greedy, n),
                detail::SimpleUpperBound(matrix, none, n));
    }
  }
}

TEST(Select, ExactFallsBackToItsStartWhenTheModelIsTooLargeForTheTimeLimit) {
  // 60 random candidates over 2,000 cells: nearly every cell has its own set of seers, so the
  // MILP has tens of thousands of nonzeros, beyond what a 1 ms time limit allows.
  const std::vector<Observation> obs = RandomInstance(17, 60, 2000, 0.3);
  const detail::CoverageMatrix matrix(obs, 2000);
  const std::vector<uint32_t> start = detail::GreedyComplete(detail::CellScorer(matrix), {}, 3);
  const detail::ExactResult result = detail::SolveExact(matrix, 3, start, 0.001);
  EXPECT_EQ(result.chosen, start);
  EXPECT_FALSE(result.note.empty());
  EXPECT_GE(result.upper_bound, matrix.CoveredWeight(start));
  EXPECT_EQ(result.upper_bound,
            std::max(detail::GreedyUpperBound(matrix, start, 3), matrix.CoveredWeight(start)));
  EXPECT_FALSE(result.proven_optimal);
}

// ---------------------------------------------------------------------------------------------
// Lagrangian bound (issue 14)

// Random instances with weights: cells that the same candidates see merge into one weighted
// element, and a few candidates are exact copies of others (duplicate rows).
std::vector<Observation> WeightedRandomInstance(uint64_t seed, size_t m, size_t cells, double p) {
  std::vector<Observation> obs = RandomInstance(seed, m - m / 4, cells, p);
  for (size_t j = 0; obs.size() < m; j += 3) obs.push_back(obs[j % obs.size()]);
  return obs;
}

// Trial t of a sweep over small weighted instances: m_min + t % m_count candidates, 20..60 cells
// (r_stride apart from one trial to the next, modulo 41), p_min + p_step * (t % p_count) density.
struct Sweep {
  size_t m_min, m_count, r_stride;
  double p_min, p_step;
  int p_count;
  uint64_t seed;
};
struct SweepTrial {
  size_t m, r;
  std::vector<Observation> obs;
};
SweepTrial SweepInstance(const Sweep& sweep, int t) {
  SweepTrial trial;
  trial.m = sweep.m_min + static_cast<size_t>(t) % sweep.m_count;
  trial.r = 20 + (static_cast<size_t>(t) * sweep.r_stride) % 41;
  const double p = sweep.p_min + sweep.p_step * (t % sweep.p_count);
  trial.obs = WeightedRandomInstance(sweep.seed + static_cast<uint64_t>(t), trial.m, trial.r, p);
  return trial;
}

TEST(Lagrangian, BoundIsAtLeastTheEnumeratedOptimumAndAtMostTheLargestRows) {
  for (int trial = 0; trial < 30; ++trial) {
    // 6..16 candidates, sparse to dense.
    const auto [m, r, obs] = SweepInstance({6, 11, 7, 0.08, 0.04, 6, 900}, trial);
    const detail::CoverageMatrix matrix(obs, r);
    for (size_t n = 1; n <= std::min<size_t>(m, 8); ++n) {
      const size_t optimum = BruteForceOptimum(obs, n);
      // Incumbent 0: no early stop, the steps run their course.
      const detail::LagrangianBound bound = detail::LagrangianUpperBound(matrix, n, 0, 500, 1e9);
      EXPECT_GE(bound.upper_bound, optimum) << "trial " << trial << " n " << n;
      EXPECT_EQ(static_cast<long double>(bound.upper_bound), std::floor(bound.value));
      // The n largest rows (lambda = w), counted independently of the library.
      std::vector<size_t> sizes;
      for (const Observation& o : obs) sizes.push_back(o.reference_indices.size());
      std::sort(sizes.rbegin(), sizes.rend());
      EXPECT_LE(bound.upper_bound, std::accumulate(sizes.begin(), sizes.begin() + n, size_t{0}));
      // With the enumerated optimum as the incumbent the steps may stop early: still valid.
      EXPECT_GE(detail::LagrangianUpperBound(matrix, n, optimum, 500, 1e9).upper_bound, optimum);
      // exact with any time limit: a bound >= the optimum, never looser than the cheap one.
      const std::vector<uint32_t> start = detail::GreedyComplete(detail::CellScorer(matrix), {}, n);
      const detail::ExactResult exact = detail::SolveExact(matrix, n, start, 60);
      EXPECT_GE(exact.upper_bound, optimum);
      EXPECT_LE(exact.upper_bound,
                std::max(detail::GreedyUpperBound(matrix, start, n), matrix.CoveredWeight(start)));
    }
  }
}

// Cells: the 10 edges of K5 and one cell `c` that all candidates see; candidate v (5 of them)
// sees the 4 edges at vertex v and c. N = 2: two vertices see 4 + 4 - 1 edges and c, 8 cells.
// LP relaxation: the objective is concave and symmetric under permuting the vertices, so the
// uniform x_v = 2/5 is optimal: every edge is covered 4/5, c fully, LP = 10 * 4/5 + 1 = 9.
// The cheap bounds are looser: the 2 largest rows 5 + 5 = 10, all cells 11.
std::vector<Observation> CompleteGraphInstance() {
  std::vector<Observation> obs(5);
  uint32_t edge = 0;
  for (uint32_t u = 0; u < 5; ++u) {
    for (uint32_t v = u + 1; v < 5; ++v, ++edge) {
      obs[u].reference_indices.push_back(edge);
      obs[v].reference_indices.push_back(edge);
    }
  }
  for (Observation& o : obs) {
    o.reference_indices.push_back(10);
    std::sort(o.reference_indices.begin(), o.reference_indices.end());
  }
  return obs;
}

TEST(Lagrangian, ConvergesToTheLpBoundOfAHandWorkedInstance) {
  const std::vector<Observation> obs = CompleteGraphInstance();
  ASSERT_EQ(BruteForceOptimum(obs, 2), 8u);
  const detail::CoverageMatrix matrix(obs, 11);
  const detail::LagrangianBound bound = detail::LagrangianUpperBound(matrix, 2, 8, 3000, 1e9);
  EXPECT_NEAR(static_cast<double>(bound.value), 9.0, 1e-6);
  EXPECT_EQ(bound.upper_bound, 9u);
  EXPECT_GT(bound.iterations, 0);
  // Deterministic.
  const detail::LagrangianBound again = detail::LagrangianUpperBound(matrix, 2, 8, 3000, 1e9);
  EXPECT_EQ(again.value, bound.value);
  EXPECT_EQ(again.iterations, bound.iterations);
  // No steps: the start multipliers (each cell's weight shared among its seers: edges 1/2, c 1/5)
  // give L = 10 * 1/2 + 4/5 + 2 * (4 * 1/2 + 1/5) = 10.2, then the 2 largest rows, 10, is less.
  const detail::LagrangianBound none = detail::LagrangianUpperBound(matrix, 2, 8, 0, 1e9);
  EXPECT_EQ(none.iterations, 0);
  EXPECT_EQ(none.upper_bound, 10u);
}

TEST(Lagrangian, ProvesTheIncumbentOptimalWhenTheLpHasNoGap) {
  // Disjoint rows of 5, 4 and 3 cells: with N = 2, L at lambda = w is 9 = the optimum.
  const std::vector<Observation> obs = {Obs({0, 1, 2, 3, 4}), Obs({5, 6, 7, 8}), Obs({9, 10, 11})};
  const detail::CoverageMatrix matrix(obs, 12);
  EXPECT_EQ(detail::LagrangianUpperBound(matrix, 2, 9, 3000, 1e9).upper_bound, 9u);
}

// Cells of R (at most 64) seen by the candidates of each mask (bit i = candidate i), counted
// independently of the library: the union of each candidate's cells as a 64-bit set.
std::vector<size_t> MaskUnions(const std::vector<Observation>& obs) {
  std::vector<uint64_t> sets(size_t{1} << obs.size(), 0);
  std::vector<size_t> cells(sets.size(), 0);
  for (uint32_t mask = 1; mask < sets.size(); ++mask) {
    const int i = std::countr_zero(mask);
    uint64_t own = 0;
    for (const uint32_t c : obs[i].reference_indices) own |= uint64_t{1} << c;
    sets[mask] = sets[mask & (mask - 1)] | own;
    cells[mask] = static_cast<size_t>(std::popcount(sets[mask]));
  }
  return cells;
}

// The weight of every merged element.
std::vector<uint32_t> ElementWeights(const detail::CoverageMatrix& matrix) {
  std::vector<uint32_t> weights;
  for (uint32_t e = 0; e < matrix.element_count(); ++e) weights.push_back(matrix.Weight(e));
  return weights;
}

// The most cells of at most n candidates, from MaskUnions' table.
size_t MaskOptimum(const std::vector<size_t>& cells, size_t n) {
  size_t optimum = 0;
  for (uint32_t mask = 0; mask < cells.size(); ++mask) {
    if (std::popcount(mask) <= static_cast<int>(n)) optimum = std::max(optimum, cells[mask]);
  }
  return optimum;
}

// Every selection of at most n candidates that reaches `threshold` cells contains each of
// fixing.fixed_in and none of fixing.removed (checked against MaskUnions' table).
void ExpectFixingKeepsThem(const std::vector<size_t>& cells, size_t n, size_t threshold,
                           const detail::Fixing& fixing, const std::string& where) {
  for (uint32_t mask = 0; mask < cells.size(); ++mask) {
    if (std::popcount(mask) > static_cast<int>(n) || cells[mask] < threshold) continue;
    for (const uint32_t i : fixing.removed) {
      EXPECT_FALSE(mask & (1u << i)) << where << " removed " << i;
    }
    for (const uint32_t i : fixing.fixed_in) {
      EXPECT_TRUE(mask & (1u << i)) << where << " fixed " << i;
    }
  }
}

TEST(Lagrangian, FixingKeepsEverySelectionThatReachesTheThreshold) {
  int fixed_in = 0, removed = 0;
  for (int trial = 0; trial < 40; ++trial) {
    const auto [m, r, obs] = SweepInstance({6, 11, 7, 0.08, 0.04, 6, 1300}, trial);
    const detail::CoverageMatrix matrix(obs, r);
    const std::vector<uint32_t> weights = ElementWeights(matrix);
    const std::vector<size_t> cells = MaskUnions(obs);
    for (size_t n = 1; n <= std::min<size_t>(m - 1, 6); ++n) {
      const size_t optimum = MaskOptimum(cells, n);
      // Thresholds: the optimum (fixing then keeps every optimum) and one cell below it.
      for (const size_t threshold : {optimum, optimum - 1}) {
        const detail::LagrangianBound bound =
            detail::LagrangianUpperBound(matrix, n, threshold - 1, 500, 1e9);
        const detail::LagrangianProblem problem{matrix.rows(), weights, n};
        const detail::Fixing fixing = detail::LagrangianFixing(
            problem, detail::EvaluateExactly(problem, bound.lambda), threshold);
        fixed_in += static_cast<int>(fixing.fixed_in.size());
        removed += static_cast<int>(fixing.removed.size());
        ExpectFixingKeepsThem(cells, n, threshold, fixing,
                              "trial " + std::to_string(trial) + " n " + std::to_string(n));
      }
    }
  }
  // The bound is tight enough here to fix many candidates both ways.
  EXPECT_GT(fixed_in, 20);
  EXPECT_GT(removed, 100);
}

// The LP relaxation of maximum coverage on the cells themselves (no merging), solved by CLP:
// max sum_c y_c s.t. y_c <= sum_{i sees c} x_i, sum_i x_i <= n, 0 <= x, y <= 1.
double ClpLpBound(const std::vector<Observation>& obs, size_t cells, size_t n) {
  const int m = static_cast<int>(obs.size());
  const int columns = m + static_cast<int>(cells);
  const int rows = static_cast<int>(cells) + 1;  // a row per cell, then the cardinality row
  std::vector<CoinBigIndex> starts{0};
  std::vector<int> index;
  std::vector<double> value;
  for (const Observation& o : obs) {
    for (const uint32_t c : o.reference_indices) {
      index.push_back(static_cast<int>(c));
      value.push_back(-1.0);
    }
    index.push_back(static_cast<int>(cells));
    value.push_back(1.0);
    starts.push_back(static_cast<CoinBigIndex>(index.size()));
  }
  for (size_t c = 0; c < cells; ++c) {
    index.push_back(static_cast<int>(c));
    value.push_back(1.0);
    starts.push_back(static_cast<CoinBigIndex>(index.size()));
  }
  std::vector<double> lower(columns, 0.0), upper(columns, 1.0), objective(columns, 0.0);
  std::fill(objective.begin() + m, objective.end(), 1.0);
  std::vector<double> row_lower(rows, -1e30), row_upper(rows, 0.0);
  row_upper.back() = static_cast<double>(n);
  Clp_Simplex* model = Clp_newModel();
  Clp_setLogLevel(model, 0);
  Clp_loadProblem(model, columns, rows, starts.data(), index.data(), value.data(), lower.data(),
                  upper.data(), objective.data(), row_lower.data(), row_upper.data());
  Clp_setObjSense(model, -1);
  Clp_initialSolve(model);
  EXPECT_EQ(Clp_status(model), 0);
  const double lp = Clp_objectiveValue(model);
  Clp_deleteModel(model);
  return lp;
}

// The weighted random instances of the LP tests: 12 of 8-19 candidates over 30-52 cells, each
// with n = 2..5; body(trial, obs, cells, matrix, weights, n).
template <typename Body>
void ForEachLpInstance(uint64_t seed, Body body) {
  for (int trial = 0; trial < 12; ++trial) {
    const size_t m = 8 + trial;
    const size_t r = 30 + 2 * trial;
    const std::vector<Observation> obs = WeightedRandomInstance(seed + trial, m, r, 0.15);
    const detail::CoverageMatrix matrix(obs, r);
    const std::vector<uint32_t> weights = ElementWeights(matrix);
    for (size_t n = 2; n <= 5; ++n) body(trial, obs, r, matrix, weights, n);
  }
}

TEST(Lagrangian, IsNeverBelowClpsLpOptimumAndConvergesToIt) {
  ForEachLpInstance(2100, [](int trial, const std::vector<Observation>& obs, size_t r,
                             const detail::CoverageMatrix& matrix,
                             const std::vector<uint32_t>& /*weights*/, size_t n) {
    const double lp = ClpLpBound(obs, r, n);
    const detail::LagrangianBound bound = detail::LagrangianUpperBound(matrix, n, 0, 3000, 1e9);
    // Weak duality: L(lambda) >= the LP optimum for every lambda, exactly.
    EXPECT_GE(static_cast<double>(bound.value), lp - 1e-7) << "trial " << trial << " n " << n;
    EXPECT_GE(bound.upper_bound, static_cast<uint64_t>(std::floor(lp + 1e-7)));
    // 3,000 subgradient steps reach the LP optimum here (to about 1e-6 cells).
    EXPECT_LE(static_cast<double>(bound.value), lp + 0.01) << "trial " << trial << " n " << n;
  });
}

// L at CLP's multipliers, exactly (EvaluateExactly's fixed point back in cells).
long double ExactValue(const detail::LagrangianProblem& problem, std::span<const double> lambda) {
  const detail::ExactLagrangian exact = detail::EvaluateExactly(problem, lambda);
  return std::ldexp(static_cast<long double>(exact.scaled_value), -exact.bits);
}

// Coordinate descent is a descent method on L: from any multipliers (the start ones, or a few
// subgradient steps' ones) L never rises, and stays at or above CLP's LP optimum and the
// enumerated optimum (weak duality, independently computed).
TEST(Lagrangian, CoordinateDescentNeverRaisesLAndStaysABound) {
  int lowered = 0;
  ForEachLpInstance(4100, [&lowered](int trial, const std::vector<Observation>& obs, size_t r,
                                     const detail::CoverageMatrix& matrix,
                                     const std::vector<uint32_t>& weights, size_t n) {
    const double lp = ClpLpBound(obs, r, n);
    const auto optimum = static_cast<long double>(BruteForceOptimum(obs, n));
    const detail::LagrangianProblem problem{matrix.rows(), weights, n};
    for (const int steps : {0, 5}) {
      std::vector<double> lambda = detail::StartMultipliers(problem);
      detail::SubgradientSteps(problem, 0, steps, detail::kStartStepScale, 1e9, &lambda);
      long double before = ExactValue(problem, lambda);
      for (int pass = 0; pass < 3; ++pass) {
        detail::CoordinateDescent(problem, 1, &lambda);
        for (size_t e = 0; e < lambda.size(); ++e) {
          ASSERT_GE(lambda[e], 0.0);
          ASSERT_LE(lambda[e], weights[e]);
        }
        const long double after = ExactValue(problem, lambda);
        const std::string where = "trial " + std::to_string(trial) + " n " + std::to_string(n) +
                                  " steps " + std::to_string(steps) + " pass " +
                                  std::to_string(pass);
        EXPECT_LE(after, before + 1e-6L) << where;
        EXPECT_GE(after, static_cast<long double>(lp) - 1e-7L) << where;
        EXPECT_GE(after, optimum) << where;
        if (after < before - 1e-3L) ++lowered;
        before = after;
      }
    }
  });
  // It moves: most first passes lower L by more than round-off.
  EXPECT_GT(lowered, 48);
}

TEST(LpBound, ClpsMultipliersProveTheLpOptimumColdOrWarmStarted) {
  ForEachLpInstance(3100, [](int trial, const std::vector<Observation>& obs, size_t r,
                             const detail::CoverageMatrix& matrix,
                             const std::vector<uint32_t>& weights, size_t n) {
    const double lp = ClpLpBound(obs, r, n);  // on the cells, no merging: independent
    const size_t optimum = BruteForceOptimum(obs, n);
    const detail::LagrangianProblem problem{matrix.rows(), weights, n};
    const detail::LagrangianBound subgradient = detail::LagrangianUpperBound(matrix, n, 0, 50, 1e9);
    for (const bool warm : {false, true}) {
      detail::ClpCoverageLp model(problem);
      const detail::ClpLpSolution solution =
          warm ? model.Solve(60, subgradient.lambda) : model.Solve(60);
      ASSERT_TRUE(solution.optimal) << "trial " << trial << " n " << n << " warm " << warm;
      EXPECT_NEAR(solution.objective, lp, 1e-6) << "trial " << trial << " n " << n;
      const long double value = ExactValue(problem, solution.lambda);
      // A proof (weak duality holds for any multipliers) ...
      EXPECT_GE(value, static_cast<long double>(lp) - 1e-7) << "trial " << trial << " n " << n;
      EXPECT_GE(std::floor(value), static_cast<long double>(optimum));
      // ... equal to the LP optimum up to the truncation of lambda to 2^-24 (60 elements).
      EXPECT_LE(value, static_cast<long double>(lp) + 1e-5) << "trial " << trial << " n " << n;
      // The LP's x: in [0, 1], at most n in all.
      double total = 0;
      for (const double x : solution.x) {
        EXPECT_GE(x, -1e-9);
        EXPECT_LE(x, 1 + 1e-9);
        total += x;
      }
      EXPECT_LE(total, static_cast<double>(n) + 1e-6);
    }
  });
}

TEST(LpBound, ReducedCostFixingNeverRemovesAnOptimalCandidate) {
  int removed = 0, fixed_in = 0;
  for (int trial = 0; trial < 40; ++trial) {
    const auto [m, r, obs] = SweepInstance({6, 11, 7, 0.08, 0.04, 6, 4100}, trial);
    const detail::CoverageMatrix matrix(obs, r);
    const std::vector<uint32_t> weights = ElementWeights(matrix);
    const std::vector<size_t> cells = MaskUnions(obs);
    for (size_t n = 1; n <= std::min<size_t>(m - 1, 6); ++n) {
      const size_t optimum = MaskOptimum(cells, n);
      const detail::LagrangianProblem problem{matrix.rows(), weights, n};
      detail::ClpCoverageLp model(problem);
      const detail::ClpLpSolution solution = model.Solve(60);
      ASSERT_TRUE(solution.optimal);
      const detail::Fixing fixing = detail::LagrangianFixing(
          problem, detail::EvaluateExactly(problem, solution.lambda), optimum);
      removed += static_cast<int>(fixing.removed.size());
      fixed_in += static_cast<int>(fixing.fixed_in.size());
      ExpectFixingKeepsThem(cells, n, optimum, fixing,
                            "trial " + std::to_string(trial) + " n " + std::to_string(n));
    }
  }
  EXPECT_GT(removed, 100);  // the LP bound is tight enough here to remove many
  EXPECT_GT(fixed_in, 10);
}

// CLP stops at its time limit on an LP it cannot finish, and what it has is still a valid bound.
TEST(LpBound, KeepsItsTimeLimit) {
  const std::vector<Observation> obs = RandomInstance(29, 400, 4000, 0.02);
  const detail::CoverageMatrix matrix(obs, 4000);
  const std::vector<uint32_t> weights = ElementWeights(matrix);
  const detail::LagrangianProblem problem{matrix.rows(), weights, 25};
  detail::ClpCoverageLp model(problem);
  const auto begin = std::chrono::steady_clock::now();
  const detail::ClpLpSolution solution = model.Solve(0.1);
  const double seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - begin).count();
  EXPECT_LE(seconds, 0.3);
  const std::vector<uint32_t> greedy = detail::GreedyComplete(detail::CellScorer(matrix), {}, 25);
  EXPECT_GE(std::floor(ExactValue(problem, solution.lambda)),
            static_cast<long double>(matrix.CoveredWeight(greedy)));
}

// An interrupt stops CLP at the end of an iteration, not at its time limit or its optimum, and
// Solve reports it as Interrupted: in a small part of the time the same LP takes to solve.
TEST(LpBound, StopsOnAnInterrupt) {
  const std::vector<Observation> obs = RandomInstance(29, 400, 8000, 0.02);
  const detail::CoverageMatrix matrix(obs, 8000);
  const std::vector<uint32_t> weights = ElementWeights(matrix);
  const detail::LagrangianProblem problem{matrix.rows(), weights, 25};
  const auto seconds_of = [](auto&& solve) {
    const auto begin = std::chrono::steady_clock::now();
    solve();
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - begin).count();
  };
  detail::ClpCoverageLp solved(problem);
  const double full = seconds_of([&] { solved.Solve(60); });
  ASSERT_GT(full, 0.2) << "the LP is too easy to see the difference";
  detail::ClpCoverageLp stopped(problem);
  RequestInterrupt();
  const double interrupted =
      seconds_of([&] { EXPECT_THROW(stopped.Solve(60), Interrupted); });
  ClearInterrupt();
  EXPECT_LT(interrupted, 0.25 * full);
}

TEST(BranchAndBound, FindsAndProvesTheEnumeratedOptimum) {
  for (int trial = 0; trial < 40; ++trial) {
    // 8..20 candidates, sparse to dense.
    const auto [m, r, obs] = SweepInstance({8, 13, 11, 0.06, 0.03, 7, 1700}, trial);
    const detail::CoverageMatrix matrix(obs, r);
    const std::vector<size_t> cells = MaskUnions(obs);
    for (size_t n = 2; n <= std::min<size_t>(m - 1, 6); n += 2) {
      size_t optimum = 0;
      for (uint32_t mask = 0; mask < cells.size(); ++mask) {
        if (std::popcount(mask) <= static_cast<int>(n)) optimum = std::max(optimum, cells[mask]);
      }
      // From the plain greedy answer (often not optimal here) and the trivial bound: all cells.
      const std::vector<uint32_t> start = PlainGreedy(obs, n);
      detail::BranchAndBoundLimits limits;
      limits.seconds = 60;
      const detail::BranchAndBoundResult found =
          detail::BranchAndBound(matrix, n, start, r, limits);
      EXPECT_TRUE(found.proven_optimal) << "trial " << trial << " n " << n;
      EXPECT_EQ(found.cells, optimum) << "trial " << trial << " n " << n;
      EXPECT_EQ(found.upper_bound, optimum);
      EXPECT_GE(found.root_bound, optimum);
      EXPECT_EQ(found.chosen.size(), n);
      EXPECT_EQ(UnionSize(obs, found.chosen), optimum);
      // Stopped after the root (no time to branch): still a valid bound, never below the start.
      limits.seconds = 0;
      const detail::BranchAndBoundResult stopped =
          detail::BranchAndBound(matrix, n, start, r, limits);
      EXPECT_GE(stopped.upper_bound, optimum);
      EXPECT_EQ(stopped.chosen, start);
      // Stopped after a few nodes (the root's rounds of steps and fixing, the nodes' problems
      // over their own elements, dive children built from their parents): every bound on the
      // way is still a proof, and the answer is what it claims.
      limits.seconds = 60;
      for (const long nodes : {1L, 2L, 3L, 5L, 8L}) {
        limits.max_nodes = nodes;
        const detail::BranchAndBoundResult partial =
            detail::BranchAndBound(matrix, n, start, r, limits);
        EXPECT_GE(partial.upper_bound, optimum) << "trial " << trial << " n " << n;
        EXPECT_GE(partial.root_bound, optimum) << "trial " << trial << " n " << n;
        EXPECT_LE(partial.nodes, nodes);
        EXPECT_EQ(UnionSize(obs, partial.chosen), partial.cells);
        EXPECT_LE(partial.cells, optimum);
        EXPECT_EQ(partial.proven_optimal, partial.upper_bound == partial.cells);
      }
      limits.max_nodes = std::numeric_limits<long>::max();
    }
  }
}

TEST(BranchAndBound, ForEachRowVisitsEveryRowOnce) {
  for (const size_t count : {size_t{0}, size_t{1}, size_t{7}, size_t{16}, size_t{1000}}) {
    for (const size_t nonzeros : {size_t{10}, size_t{10000000}}) {
      std::vector<std::atomic<int>> visits(count);
      detail::ForEachRow(count, nonzeros, [&](size_t begin, size_t end) {
        ASSERT_LE(begin, end);
        ASSERT_LE(end, count);
        for (size_t i = begin; i < end; ++i) ++visits[i];
      });
      for (size_t i = 0; i < count; ++i) EXPECT_EQ(visits[i].load(), 1) << count << " " << i;
    }
  }
}

// Parallel passes (ForEachRow: each row's sum is one thread's, in element order) leave the
// search unchanged: the same nodes, bounds and answer on 1 thread as on 2, stopped after a fixed
// number of nodes. 500 candidates over 25,000 cells: about 2.5 M nonzeros, above the size at
// which the passes go parallel (few root steps keep it quick).
TEST(BranchAndBound, SameResultWhateverTheThreadCount) {
  const std::vector<Observation> obs = RandomInstance(41, 500, 25000, 0.2);
  const detail::CoverageMatrix matrix(obs, 25000);
  size_t nonzeros = 0;
  for (const std::vector<uint32_t>& row : matrix.rows()) nonzeros += row.size();
  ASSERT_GT(nonzeros, 2000000u);
  for (const size_t n : {size_t{4}, size_t{8}}) {
    const std::vector<uint32_t> start = detail::GreedyComplete(detail::CellScorer(matrix), {}, n);
    detail::BranchAndBoundLimits limits;
    limits.seconds = 600;  // never reached: the node limit stops it
    limits.max_nodes = 6;
    limits.root_steps = 40;
    // CLP stops at its clock on this size: keep the stopping point clock-free.
    limits.root_lp = false;
    const auto run = [&](int threads) {
      tbb::task_arena arena(threads);
      detail::BranchAndBoundResult result;
      arena.execute(
          [&] { result = detail::BranchAndBound(matrix, n, start, matrix.seen_weight(), limits); });
      return result;
    };
    const detail::BranchAndBoundResult one = run(1);
    const detail::BranchAndBoundResult two = run(2);
    EXPECT_EQ(one.chosen, two.chosen);
    EXPECT_EQ(one.cells, two.cells);
    EXPECT_EQ(one.upper_bound, two.upper_bound);
    EXPECT_EQ(one.nodes, two.nodes);
    EXPECT_EQ(one.root_bound, two.root_bound);
    EXPECT_EQ(one.root_steps, two.root_steps);
    EXPECT_EQ(one.root_removed, two.root_removed);
    EXPECT_EQ(one.root_subgradient_bound, two.root_subgradient_bound);
    EXPECT_EQ(one.root_lp_bound, two.root_lp_bound);
    EXPECT_GE(one.upper_bound, one.cells);
    EXPECT_GT(one.nodes, 1);
  }
}

// Candidates that each see one interval of the cells, a few of them missing: merged elements
// then follow the cells, so every row is a few runs of consecutive elements (as in the generated
// 1,000 x 100,000 benchmark instance).
std::vector<Observation> IntervalInstance(uint64_t seed, size_t m, size_t cells) {
  std::vector<Observation> obs(m);
  for (size_t i = 0; i < m; ++i) {
    Rng rng(seed, Stream::kTest, i);
    const size_t length = cells / 4 + rng.Below(cells / 3);
    const size_t first = rng.Below(cells - length);
    for (size_t c = first; c < first + length; ++c) {
      if (rng.Uniform01() >= 0.05) obs[i].reference_indices.push_back(static_cast<uint32_t>(c));
    }
  }
  return obs;
}

TEST(Lagrangian, RunsGiveTheSameRowsAsTheElements) {
  EXPECT_EQ(std::vector<uint32_t>({}), [] {
    std::vector<uint32_t> runs;
    detail::AppendRuns({}, &runs);
    return runs;
  }());
  std::vector<uint32_t> runs;
  const std::vector<uint32_t> row = {0, 1, 2, 5, 7, 8};
  detail::AppendRuns(row, &runs);
  EXPECT_EQ(runs, std::vector<uint32_t>({0, 3, 5, 6, 7, 9}));
  for (uint64_t trial = 0; trial < 20; ++trial) {
    const size_t m = 8 + trial % 5;
    const std::vector<Observation> obs = IntervalInstance(900 + trial, m, 60);
    const detail::CoverageMatrix matrix(obs, 60);
    const std::vector<uint32_t> weights = ElementWeights(matrix);
    std::vector<std::vector<uint32_t>> row_runs(m);
    for (uint32_t i = 0; i < m; ++i) detail::AppendRuns(matrix.Row(i), &row_runs[i]);
    const std::vector<size_t> cells = MaskUnions(obs);
    for (size_t n = 1; n <= 4; ++n) {
      const detail::LagrangianProblem plain{matrix.rows(), weights, n};
      const detail::LagrangianProblem by_runs{matrix.rows(), weights, n, row_runs};
      // The same multipliers: the same exact L, rows and choice (integers either way).
      std::vector<double> lambda = detail::StartMultipliers(plain);
      detail::SubgradientSteps(by_runs, 0, 200, detail::kStartStepScale, 1e9, &lambda);
      const detail::ExactLagrangian a = detail::EvaluateExactly(plain, lambda);
      const detail::ExactLagrangian b = detail::EvaluateExactly(by_runs, lambda);
      EXPECT_EQ(a.scaled_value, b.scaled_value);
      EXPECT_EQ(a.rows, b.rows);
      EXPECT_EQ(a.chosen, b.chosen);
      EXPECT_EQ(a.next_row, b.next_row);
      // Steps over runs still give a bound (every multiplier does), near the plain steps'.
      const size_t optimum = MaskOptimum(cells, n);
      EXPECT_GE(b.scaled_value >> b.bits, optimum) << "trial " << trial << " n " << n;
      std::vector<double> plain_lambda = detail::StartMultipliers(plain);
      detail::SubgradientSteps(plain, 0, 200, detail::kStartStepScale, 1e9, &plain_lambda);
      const detail::ExactLagrangian c = detail::EvaluateExactly(plain, plain_lambda);
      EXPECT_NEAR(static_cast<double>(c.scaled_value >> c.bits),
                  static_cast<double>(b.scaled_value >> b.bits), 2.0);
    }
  }
}

// Branch and bound on interval rows takes the runs path (the passes as prefix sums) and still
// finds and proves the enumerated optimum; stopped early, its bounds hold.
TEST(BranchAndBound, FindsTheEnumeratedOptimumOnRowsOfRuns) {
  int by_runs = 0;
  for (uint64_t trial = 0; trial < 20; ++trial) {
    const size_t m = 10 + trial % 6;
    const std::vector<Observation> obs = IntervalInstance(700 + trial, m, 64);
    const detail::CoverageMatrix matrix(obs, 64);
    const std::vector<size_t> cells = MaskUnions(obs);
    for (size_t n = 2; n <= 5; ++n) {
      const size_t optimum = MaskOptimum(cells, n);
      const std::vector<uint32_t> start = PlainGreedy(obs, n);
      detail::BranchAndBoundLimits limits;
      limits.seconds = 60;
      const detail::BranchAndBoundResult found =
          detail::BranchAndBound(matrix, n, start, 64, limits);
      by_runs += found.profile.runs;
      EXPECT_TRUE(found.proven_optimal) << "trial " << trial << " n " << n;
      EXPECT_EQ(found.cells, optimum) << "trial " << trial << " n " << n;
      EXPECT_EQ(UnionSize(obs, found.chosen), optimum);
      for (const long nodes : {1L, 3L}) {
        limits.max_nodes = nodes;
        const detail::BranchAndBoundResult partial =
            detail::BranchAndBound(matrix, n, start, 64, limits);
        EXPECT_GE(partial.upper_bound, optimum) << "trial " << trial << " n " << n;
      }
    }
  }
  EXPECT_GT(by_runs, 40) << by_runs;  // most of the 80 searches took the runs path
}

// A hard instance: 400 random candidates over 4,000 cells, n = 25 (no proof in seconds): exact
// returns within its time limit (+10 %) with a valid bound.
TEST(BranchAndBound, ExactKeepsItsTimeLimitOnAHardInstance) {
  const std::vector<Observation> obs = RandomInstance(23, 400, 4000, 0.02);
  const detail::CoverageMatrix matrix(obs, 4000);
  const std::vector<uint32_t> start = detail::GreedyComplete(detail::CellScorer(matrix), {}, 25);
  const auto begin = std::chrono::steady_clock::now();
  const detail::ExactResult exact = detail::SolveExact(matrix, 25, start, 1.5);
  const double seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - begin).count();
  EXPECT_LE(seconds, 1.65);
  const uint64_t cells = matrix.CoveredWeight(exact.chosen);
  EXPECT_GE(cells, matrix.CoveredWeight(start));
  EXPECT_GE(exact.upper_bound, cells);
  EXPECT_LE(exact.upper_bound,
            std::max(detail::GreedyUpperBound(matrix, start, 25), matrix.CoveredWeight(start)));
  EXPECT_FALSE(exact.proven_optimal);
}

// ---------------------------------------------------------------------------------------------
// Further objectives: set cover, k-coverage, budget

// Cells of R seen by at least k of `chosen`, counted independently of the library.
size_t KUnionSize(const std::vector<Observation>& obs, const std::vector<uint32_t>& chosen, int k) {
  std::map<uint32_t, int> seen;
  for (uint32_t c : chosen) {
    for (uint32_t cell : obs[c].reference_indices) ++seen[cell];
  }
  return static_cast<size_t>(
      std::count_if(seen.begin(), seen.end(), [&](const auto& p) { return p.second >= k; }));
}

// Every subset of the m candidates, as index lists (m <= 14).
std::vector<std::vector<uint32_t>> AllSubsets(size_t m) {
  std::vector<std::vector<uint32_t>> subsets;
  for (uint32_t mask = 1; mask < (1u << m); ++mask) {
    std::vector<uint32_t> s;
    for (uint32_t i = 0; i < m; ++i) {
      if (mask & (1u << i)) s.push_back(i);
    }
    subsets.push_back(std::move(s));
  }
  return subsets;
}

// With kept sensors (fixed variables of the model) every point of the curve holds them: it starts
// one past them, each answer is the kept sensors plus n - |kept| others, and no answer beats the
// enumerated best n-set that contains them.
TEST(CoverageCurve, HoldsTheKeptSensorsAtEveryN) {
  const std::vector<Observation> obs = RandomInstance(22, 10, 40, 0.2);
  SelectOptions options;
  options.n = 3;
  options.method = Method::kGreedy;
  options.fixed = {4, 7};
  const std::vector<Selection> curve =
      CoverageCurve(obs, 40, options, Select(obs, 40, options));
  ASSERT_FALSE(curve.empty());
  int smallest = 100;
  for (const Selection& s : curve) {
    SCOPED_TRACE(testing::Message() << s.method << " n=" << s.n);
    smallest = std::min(smallest, s.n);
    ASSERT_EQ(static_cast<int>(s.chosen.size()), s.n);
    EXPECT_EQ(std::count(s.chosen.begin(), s.chosen.end(), 4u), 1);
    EXPECT_EQ(std::count(s.chosen.begin(), s.chosen.end(), 7u), 1);
    uint64_t best = 0;
    for (const std::vector<uint32_t>& set : AllSubsets(10)) {
      if (static_cast<int>(set.size()) != s.n || !std::count(set.begin(), set.end(), 4u) ||
          !std::count(set.begin(), set.end(), 7u))
        continue;
      best = std::max<uint64_t>(best, UnionSize(obs, set));
    }
    EXPECT_LE(UnionSize(obs, s.chosen), best);
    EXPECT_DOUBLE_EQ(s.coverage, static_cast<double>(UnionSize(obs, s.chosen)) / 40);
  }
  EXPECT_EQ(smallest, 3);
}

double SumOfCosts(const std::vector<double>& costs, const std::vector<uint32_t>& chosen) {
  double total = 0;
  for (uint32_t c : chosen) total += costs[c];  // the order Selection::cost sums in
  return total;
}

SelectOptions GoalOptions(Method method, double goal) {
  SelectOptions options = Options(method, 1);
  options.goal = goal;
  return options;
}

SelectOptions KOptions(Method method, int n, int k) {
  SelectOptions options = Options(method, n);
  options.k = k;
  return options;
}

SelectOptions BudgetOptions(Method method, double budget, std::vector<double> costs) {
  SelectOptions options = Options(method, 1);
  options.budget = budget;
  options.costs = std::move(costs);
  return options;
}

TEST(Objectives, NamesAndWhichObjectiveIsActive) {
  SelectOptions o;
  EXPECT_EQ(o.objective(), Objective::kCoverage);
  o.k = 2;
  EXPECT_EQ(o.objective(), Objective::kKCoverage);
  o.k = 1;
  o.goal = 0.5;
  EXPECT_EQ(o.objective(), Objective::kSetCover);
  o.goal.reset();
  o.budget = 3;
  EXPECT_EQ(o.objective(), Objective::kBudget);
  EXPECT_EQ(ObjectiveName(Objective::kCoverage), "coverage");
  EXPECT_EQ(ObjectiveName(Objective::kSetCover), "set-cover");
  EXPECT_EQ(ObjectiveName(Objective::kKCoverage), "k-coverage");
  EXPECT_EQ(ObjectiveName(Objective::kBudget), "budget");
}

TEST(Objectives, ValidateRejectsBadObjectives) {
  const auto message = [](const SelectOptions& o, size_t m) {
    try {
      o.Validate(m);
    } catch (const InputError& e) {
      return std::string(e.what());
    }
    return std::string("no InputError");
  };
  for (double goal : {0.0, -0.5, 1.01, std::numeric_limits<double>::quiet_NaN()}) {
    EXPECT_NE(message(GoalOptions(Method::kAll, goal), 4).find("goal"), std::string::npos) << goal;
  }
  EXPECT_NO_THROW(GoalOptions(Method::kAll, 1.0).Validate(4));
  SelectOptions both = GoalOptions(Method::kAll, 0.5);
  both.budget = 3;
  both.costs = {1, 1, 1, 1};
  EXPECT_NE(message(both, 4).find("only one of"), std::string::npos);
  // A goal counts k times, or in points — not both; k above the candidates counts nothing.
  SelectOptions counted = GoalOptions(Method::kAll, 0.5);
  counted.k = 2;
  EXPECT_NO_THROW(counted.Validate(4));
  counted.min_points = 3;
  EXPECT_NE(message(counted, 4).find("give --k or --min-points, not both"), std::string::npos);
  counted.min_points.reset();
  counted.k = 5;
  EXPECT_NE(message(counted, 4).find("k = 5 is above the 4 candidates"), std::string::npos);
  SelectOptions cheapest;
  cheapest.minimize_cost = true;
  cheapest.costs = {1, 1, 1, 1};
  EXPECT_NE(message(cheapest, 4).find("give --goal with --cheapest"), std::string::npos);
  EXPECT_NE(message(KOptions(Method::kAll, 1, 2), 4).find("raise -n to at least 2"),
            std::string::npos);
  EXPECT_NE(message(KOptions(Method::kAll, 2, 0), 4).find("k = 0"), std::string::npos);
  EXPECT_NE(message(KOptions(Method::kBest, 2, 2), 4).find("method 'best' does not apply"),
            std::string::npos);
  EXPECT_NE(message(GoalOptions(Method::kLocal, 0.5), 4).find("use one of ransac, greedy, exact, all"),
            std::string::npos);
  EXPECT_NE(message(BudgetOptions(Method::kBest, 5, {1, 1, 1, 1}), 4).find("method 'best'"),
            std::string::npos);
  EXPECT_NE(message(BudgetOptions(Method::kAll, 5, {1, 1}), 4).find("2 costs for 4"),
            std::string::npos);
  EXPECT_NE(message(BudgetOptions(Method::kAll, 5, {1, -1, 1, 1}), 4).find("cost -1"),
            std::string::npos);
  EXPECT_NE(message(BudgetOptions(Method::kAll, 2, {3, 4, 5, 6}), 4)
                .find("budget 2 is below the cheapest candidate's cost 3"),
            std::string::npos);
  EXPECT_NO_THROW(BudgetOptions(Method::kAll, 3, {3, 4, 5, 6}).Validate(4));
}

TEST(CoverageEvaluator, KCoverageCountsCellsSeenKTimes) {
  // A sees 0-2 and keys 100, 200; B sees 2-3 and 200, 300; C sees 0, 3 and 200.
  const std::vector<Observation> obs = {Obs({0, 1, 2}, {100, 200}), Obs({2, 3}, {200, 300}),
                                        Obs({0, 3}, {200})};
  const CoverageEvaluator evaluator(obs, 10);
  const std::vector<uint32_t> ab{0, 1}, abc{0, 1, 2};
  EXPECT_EQ(evaluator.CoveredCount(ab, 2), 1u);   // cell 2
  EXPECT_EQ(evaluator.CoveredCount(abc, 2), 3u);  // cells 0, 2, 3
  EXPECT_EQ(evaluator.CoveredCount(abc, 3), 0u);
  EXPECT_DOUBLE_EQ(evaluator.Coverage(abc, 2), 0.3);
  // Cells 0, 2, 3 and key 200 (seen 3 times); 100 and 300 only once.
  EXPECT_DOUBLE_EQ(evaluator.PaperCoverage(abc, 2), 0.4);
  EXPECT_DOUBLE_EQ(evaluator.PaperCoverage(abc, 3), 0.1);
  EXPECT_DOUBLE_EQ(evaluator.PaperCoverage(abc, 1), evaluator.PaperCoverage(abc));
}

// X = c0 = cells 0-5, Y = c1 = cells 6-11, G = c2 = {0, 1, 2, 3, 6, 7, 8}; R = 12 cells.
std::vector<Observation> SetCoverInstance() {
  return {Obs({0, 1, 2, 3, 4, 5}), Obs({6, 7, 8, 9, 10, 11}), Obs({0, 1, 2, 3, 6, 7, 8})};
}

TEST(Objectives, SetCoverByHand) {
  const std::vector<Observation> obs = SetCoverInstance();
  // Goal 1.0 = 12 cells. Greedy: G (7), then Y adds 9-11 (3) over X's 4-5 (2), then X adds 4, 5:
  // three sensors [2, 1, 0]. X + Y alone cover all 12: two sensors, and no single row has 12
  // cells, so at least two are needed: exact proves 2.
  const std::vector<Selection> all = Select(obs, 12, GoalOptions(Method::kAll, 1.0));
  ASSERT_EQ(all.size(), 2u);
  const Selection& greedy = all[0];
  EXPECT_EQ(greedy.method, "greedy");
  EXPECT_EQ(greedy.objective, "set-cover");
  EXPECT_EQ(greedy.goal, 1.0);
  EXPECT_EQ(greedy.chosen, (std::vector<uint32_t>{2, 1, 0}));
  EXPECT_EQ(greedy.n, 3);
  EXPECT_DOUBLE_EQ(greedy.coverage, 1.0);
  EXPECT_FALSE(greedy.n_lower_bound.has_value());
  const Selection& exact = all[1];
  EXPECT_EQ(exact.method, "exact");
  EXPECT_EQ(Sorted(exact.chosen), (std::vector<uint32_t>{0, 1}));
  EXPECT_EQ(exact.n, 2);
  EXPECT_DOUBLE_EQ(exact.coverage, 1.0);
  EXPECT_EQ(exact.n_lower_bound, 2);
  EXPECT_TRUE(exact.proven_optimal);
  EXPECT_FALSE(exact.upper_bound.has_value());

  // Goal 0.75 = 9 cells: G (7) then Y (+3) = 10 >= 9: [2, 1]. One sensor sees at most 7 < 9.
  const std::vector<Selection> q = Select(obs, 12, GoalOptions(Method::kAll, 0.75));
  EXPECT_EQ(q[0].chosen, (std::vector<uint32_t>{2, 1}));
  EXPECT_EQ(q[1].n, 2);
  EXPECT_TRUE(q[1].proven_optimal);
  // Goal 0.5 = 6 cells: G alone (7 cells).
  const std::vector<Selection> half = Select(obs, 12, GoalOptions(Method::kGreedy, 0.5));
  ASSERT_EQ(half.size(), 1u);
  EXPECT_EQ(half[0].chosen, (std::vector<uint32_t>{2}));
  EXPECT_DOUBLE_EQ(half[0].coverage, 7.0 / 12);
  // A goal that is not a whole number of cells rounds up: 0.51 of 12 = 6.12 -> 7 cells.
  EXPECT_EQ(Select(obs, 12, GoalOptions(Method::kGreedy, 0.51))[0].n, 1);
  EXPECT_EQ(Select(obs, 12, GoalOptions(Method::kGreedy, 7.01 / 12))[0].n, 2);
}

TEST(Objectives, InfeasibleGoalIsInputErrorNamingTheReachableMaximum) {
  // Three candidates see 9 of 12 cells together: 0.75 at most.
  const std::vector<Observation> obs = {Obs({0, 1, 2}), Obs({3, 4, 5}), Obs({6, 7, 8})};
  EXPECT_NO_THROW(Select(obs, 12, GoalOptions(Method::kAll, 0.75)));
  for (const Method m : {Method::kGreedy, Method::kExact, Method::kAll}) {
    try {
      Select(obs, 12, GoalOptions(m, 0.8));
      FAIL() << "no InputError for " << MethodName(m);
    } catch (const InputError& e) {
      EXPECT_EQ(std::string(e.what()),
                "--goal: goal 0.8 is above the 0.7500 that all 3 candidates reach together — "
                "lower --goal");
    }
  }
  // Nothing seen at all: any goal is infeasible (and no empty answer is returned).
  const std::vector<Observation> blind = {Obs({}), Obs({})};
  EXPECT_THROW(Select(blind, 5, GoalOptions(Method::kAll, 0.01)), InputError);
  EXPECT_THROW(Select(blind, 0, GoalOptions(Method::kAll, 0.01)), InputError);
}

// R = 10 cells. c0 = {0..5} is the largest but shares only cell 0 with c1 = {0, 6, 7, 8};
// c2 = {6, 7, 8, 9}; c3 = {1}.
std::vector<Observation> KCoverageInstance() {
  return {Obs({0, 1, 2, 3, 4, 5}), Obs({0, 6, 7, 8}), Obs({6, 7, 8, 9}), Obs({1})};
}

TEST(Objectives, KCoverageByHand) {
  const std::vector<Observation> obs = KCoverageInstance();
  // k = 2, n = 2. Greedy, first step: no cell can reach 2 seers, so the level-1 gains decide:
  // c0 (6 cells). Second step: cells brought to 2 seers: c1 {0} = 1, c2 0, c3 {1} = 1; the tie
  // goes to level 1 (cells brought to 1 seer): c1 {6, 7, 8} = 3, c3 0 -> c1. [0, 1]: cell 0 only,
  // 1/10. Local: swapping c0 out for c2 loses cell 0 (1) and completes 6, 7, 8 (3): [2, 1] = 3/10,
  // the optimum (the best pair overlap: c1 and c2 share 6, 7, 8).
  const std::vector<Selection> g = Select(obs, 10, KOptions(Method::kGreedy, 2, 2));
  ASSERT_EQ(g.size(), 1u);
  EXPECT_EQ(g[0].objective, "k-coverage");
  EXPECT_EQ(g[0].k, 2);
  EXPECT_EQ(g[0].chosen, (std::vector<uint32_t>{0, 1}));
  EXPECT_DOUBLE_EQ(g[0].coverage, 0.1);
  const Selection local = Select(obs, 10, KOptions(Method::kLocal, 2, 2)).at(0);
  EXPECT_EQ(local.chosen, (std::vector<uint32_t>{2, 1}));
  EXPECT_DOUBLE_EQ(local.coverage, 0.3);
  const Selection exact = Select(obs, 10, KOptions(Method::kExact, 2, 2)).at(0);
  EXPECT_EQ(Sorted(exact.chosen), (std::vector<uint32_t>{1, 2}));
  EXPECT_DOUBLE_EQ(exact.coverage, 0.3);
  EXPECT_TRUE(exact.proven_optimal);
  ASSERT_TRUE(exact.upper_bound.has_value());
  EXPECT_NEAR(*exact.upper_bound, 0.3, 1e-12);

  // "all" runs n = k..N only: for N = 3, n = 2 and 3, four methods each, no `best`.
  const std::vector<Selection> all = Select(obs, 10, KOptions(Method::kAll, 3, 2));
  ASSERT_EQ(all.size(), 8u);
  for (const Selection& s : all) {
    EXPECT_GE(s.n, 2);
    EXPECT_NE(s.method, "best");
    EXPECT_EQ(s.k, 2);
  }
  // n = 3 (hand): {c0, c1, c2} 2-covers 0, 6, 7, 8 = 4 cells; {c0, c1, c3}: 0, 1 = 2;
  // {c0, c2, c3}: 1 only; {c1, c2, c3}: 6, 7, 8 = 3. Optimum 4/10.
  EXPECT_EQ(all.back().method, "exact");
  EXPECT_DOUBLE_EQ(all.back().coverage, 0.4);
}

TEST(Objectives, KGreedyPrefersDeepeningAtEveryLevel) {
  // k = 3, n = 3, R = 8. c0 = {0..4} (5) first. Second step, nothing reaches 3; cells brought to
  // 2 seers: c1 {0, 1, 2} = 3, c2 {3, 4} = 2, c3 0 -> c1. Third: cells brought to 3: c2 {} = 0,
  // c3 {0, 1} = 2 -> c3: [0, 1, 3], cells 0 and 1 seen 3 times.
  const std::vector<Observation> obs = {Obs({0, 1, 2, 3, 4}), Obs({0, 1, 2, 5}), Obs({3, 4, 6}),
                                        Obs({0, 1, 7})};
  const Selection greedy = Select(obs, 8, KOptions(Method::kGreedy, 3, 3)).at(0);
  EXPECT_EQ(greedy.chosen, (std::vector<uint32_t>{0, 1, 3}));
  EXPECT_DOUBLE_EQ(greedy.coverage, 2.0 / 8);
}

// R = 10. c0 = {0..5} costs 10; c1 = {0, 1, 2} costs 2; c2 = {6, 7} costs 1; c3 = {3, 4, 5, 8, 9}
// costs 8.
std::vector<Observation> BudgetInstance() {
  return {Obs({0, 1, 2, 3, 4, 5}), Obs({0, 1, 2}), Obs({6, 7}), Obs({3, 4, 5, 8, 9})};
}
const std::vector<double> kBudgetCosts = {10, 2, 1, 8};

TEST(Objectives, BudgetByHand) {
  const std::vector<Observation> obs = BudgetInstance();
  // Budget 10. Gain per cost: c2 2/1 = 2 -> take (spent 1); then c1 3/2 = 1.5 (spent 3); then
  // c0 (3 more for 10) and c3 (5 for 8) no longer fit. [2, 1] covers 5 cells; the best single
  // affordable candidate, c0, covers 6: greedy answers [0]. Local: nothing fits beside c0, and
  // swapping c0 for c3 (5 cells) or c1 or c2 loses. The optimum: c1 + c3 (cost exactly 10) cover
  // 0-5, 8, 9 = 8 cells; {c2, c3} (cost 9) 7; {c1, c2} 5.
  const std::vector<Selection> all = Select(obs, 10, BudgetOptions(Method::kAll, 10, kBudgetCosts));
  ASSERT_EQ(all.size(), 3u);
  EXPECT_EQ(all[0].method, "greedy");
  EXPECT_EQ(all[0].objective, "budget");
  EXPECT_EQ(all[0].chosen, (std::vector<uint32_t>{0}));
  EXPECT_DOUBLE_EQ(all[0].coverage, 0.6);
  EXPECT_EQ(all[0].budget, 10.0);
  EXPECT_EQ(all[0].cost, 10.0);
  EXPECT_EQ(all[1].method, "local");
  EXPECT_EQ(all[1].chosen, (std::vector<uint32_t>{0}));
  EXPECT_EQ(all[2].method, "exact");
  EXPECT_EQ(Sorted(all[2].chosen), (std::vector<uint32_t>{1, 3}));
  EXPECT_DOUBLE_EQ(all[2].coverage, 0.8);
  EXPECT_EQ(all[2].cost, 10.0);
  EXPECT_TRUE(all[2].proven_optimal);
  EXPECT_NEAR(*all[2].upper_bound, 0.8, 1e-12);

  // Budget 3: greedy's [2, 1] (5 cells, cost 3) beats the best single affordable (c1, 3 cells).
  const Selection three = Select(obs, 10, BudgetOptions(Method::kGreedy, 3, kBudgetCosts)).at(0);
  EXPECT_EQ(three.chosen, (std::vector<uint32_t>{2, 1}));
  EXPECT_EQ(three.cost, 3.0);
  // Budget 9: local starts from greedy's [2, 1] (cost 3; c3 no longer fits beside it), swaps c1
  // for c3 (+5 -3 = +2, cost 9): [2, 3] = 7 cells.
  const Selection nine = Select(obs, 10, BudgetOptions(Method::kLocal, 9, kBudgetCosts)).at(0);
  EXPECT_EQ(nine.chosen, (std::vector<uint32_t>{2, 3}));
  EXPECT_EQ(nine.cost, 9.0);
  EXPECT_DOUBLE_EQ(nine.coverage, 0.7);
}

TEST(Objectives, ZeroCostSensorsComeFirstAndFreeOnesStillCount) {
  // c1 costs nothing: the greedy takes it first, then the best ratio that fits.
  const std::vector<Observation> obs = {Obs({0, 1, 2}), Obs({3}), Obs({4, 5})};
  const Selection s = Select(obs, 6, BudgetOptions(Method::kGreedy, 1, {1, 0, 1})).at(0);
  EXPECT_EQ(s.chosen, (std::vector<uint32_t>{1, 0}));
  EXPECT_EQ(s.cost, 1.0);
}

// Cells in which `chosen` together put at least `min_points` hits, counted from the hits alone.
size_t PointUnionSize(const std::vector<Observation>& obs, const std::vector<uint32_t>& chosen,
                      uint32_t min_points) {
  std::map<uint32_t, uint64_t> points;
  for (const uint32_t c : chosen) {
    for (size_t j = 0; j < obs[c].reference_indices.size(); ++j)
      points[obs[c].reference_indices[j]] += obs[c].reference_hits[j];
  }
  return static_cast<size_t>(std::count_if(points.begin(), points.end(),
                                           [&](const auto& p) { return p.second >= min_points; }));
}

// Min-points (docs/constraints.md, "Point density") on random instances with random pixel
// counts per cell, against the optimum by enumeration of every subset.
TEST(Objectives, MinPointsAgainstBruteForce) {
  for (uint64_t trial = 0; trial < 12; ++trial) {
    SCOPED_TRACE(testing::Message() << "trial " << trial);
    const size_t m = 6 + trial % 5;         // 6-10 candidates
    const size_t r = 20 + 5 * (trial % 4);  // 20-35 cells
    std::vector<Observation> obs = RandomInstance(700 + trial, m, r, 0.2 + 0.05 * (trial % 3));
    Rng rng(800 + trial, Stream::kTest, 0);
    for (Observation& o : obs) {
      for (size_t j = 0; j < o.reference_indices.size(); ++j)
        o.reference_hits.push_back(static_cast<uint16_t>(1 + rng.Below(12)));
    }
    const std::vector<std::vector<uint32_t>> subsets = AllSubsets(m);
    for (const uint32_t points : {6u, 15u}) {
      SCOPED_TRACE(testing::Message() << "min points " << points);
      std::map<int, size_t> optimum, greedy_cells;
      for (const auto& s : subsets) {
        const int n = static_cast<int>(s.size());
        if (n <= 4) optimum[n] = std::max(optimum[n], PointUnionSize(obs, s, points));
      }
      SelectOptions options;
      options.method = Method::kAll;
      options.n = 4;
      options.min_points = points;
      options.ransac_iterations = 30;
      options.seed = trial;
      ASSERT_EQ(options.objective(), Objective::kMinPoints);
      const std::vector<Selection> results = Select(obs, r, options);
      ASSERT_EQ(results.size(), 16u);  // ransac, greedy, local, exact for n = 1..4
      for (const Selection& s : results) {
        SCOPED_TRACE(testing::Message() << s.method << " n=" << s.n);
        ASSERT_EQ(static_cast<int>(s.chosen.size()), s.n);
        EXPECT_EQ(std::set<uint32_t>(s.chosen.begin(), s.chosen.end()).size(), s.chosen.size());
        const size_t cells = PointUnionSize(obs, s.chosen, points);
        EXPECT_DOUBLE_EQ(s.coverage, static_cast<double>(cells) / r);
        EXPECT_EQ(s.objective, "min-points");
        EXPECT_EQ(s.min_points, points);
        EXPECT_LE(cells, optimum[s.n]);
        if (s.method == "greedy") greedy_cells[s.n] = cells;
        if (s.method == "local") {
          EXPECT_GE(cells, greedy_cells[s.n]);
        }
        if (s.method == "exact") {
          EXPECT_EQ(cells, optimum[s.n]);
          EXPECT_TRUE(s.proven_optimal);
          ASSERT_TRUE(s.upper_bound.has_value());
          EXPECT_NEAR(*s.upper_bound, static_cast<double>(optimum[s.n]) / r, 1e-12);
        }
      }
      // The weighted MILP itself in CBC (Select enumerates instances this small), from a
      // deliberately poor start so that CBC has to find the optimum and prove its bound.
      const detail::CoverageMatrix matrix(obs, r, points);
      for (size_t n = 2; n <= 4; ++n) {
        std::vector<uint32_t> start(n);
        std::iota(start.begin(), start.end(), 0u);
        const detail::ExactResult milp =
            ExactK(matrix, n, static_cast<int>(points), start, 60, false);
        SCOPED_TRACE(testing::Message() << "MILP n=" << n << " " << milp.note);
        ASSERT_EQ(milp.chosen.size(), n);
        EXPECT_EQ(PointUnionSize(obs, milp.chosen, points), optimum[static_cast<int>(n)]);
        EXPECT_TRUE(milp.proven_optimal);
        EXPECT_EQ(milp.upper_bound, optimum[static_cast<int>(n)]);
      }
    }
  }
}

// Every pixel count 1 and min_points = k: exactly k-coverage, whose optimum the existing methods
// prove; min-points must find the same optimum.
TEST(Objectives, MinPointsWithUnitCountsIsKCoverage) {
  std::vector<Observation> obs = RandomInstance(901, 9, 30, 0.3);
  for (Observation& o : obs) o.reference_hits.assign(o.reference_indices.size(), 1);
  for (int k = 2; k <= 3; ++k) {
    SelectOptions points;
    points.method = Method::kExact;
    points.n = 4;
    points.min_points = static_cast<uint32_t>(k);
    SelectOptions kcov = points;
    kcov.min_points.reset();
    kcov.k = k;
    EXPECT_DOUBLE_EQ(Select(obs, 30, points).front().coverage,
                     Select(obs, 30, kcov).front().coverage);
  }
}

TEST(Objectives, MinPointsRefusesWhatItCannotCombineWith) {
  std::vector<Observation> obs = RandomInstance(902, 5, 20, 0.3);
  SelectOptions options;
  options.n = 2;
  options.min_points = 5;
  const auto field_of = [&](const SelectOptions& o) -> std::string {
    try {
      o.Validate(obs.size());
    } catch (const FieldError& e) {
      return e.fields().front();
    }
    return "";
  };
  SelectOptions with_k = options;
  with_k.k = 2;
  EXPECT_EQ(field_of(with_k), "min_points");
  // Kept sensors combine since issue 42 (selection_model_test); n must still hold them.
  SelectOptions kept = options;
  kept.fixed = {0};
  EXPECT_EQ(field_of(kept), "");
  kept.fixed = {0, 1, 2};
  EXPECT_EQ(field_of(kept), "n");
  SelectOptions best = options;
  best.method = Method::kBest;
  EXPECT_NE(field_of(best), "");
  // Observations without pixel counts (an old visibility file): refused, naming min_points.
  EXPECT_THROW(Select(obs, 20, options), FieldError);
}

TEST(Objectives, AgainstBruteForce) {
  for (uint64_t trial = 0; trial < 18; ++trial) {
    SCOPED_TRACE(testing::Message() << "trial " << trial);
    const size_t m = 6 + trial % 6;         // 6-11 candidates
    const size_t r = 20 + 5 * (trial % 4);  // 20-35 cells
    const double p = 0.15 + 0.05 * static_cast<double>(trial % 3);
    const std::vector<Observation> obs = RandomInstance(500 + trial, m, r, p);
    const std::vector<std::vector<uint32_t>> subsets = AllSubsets(m);

    // k-coverage, k = 2 and 3, n = k..4.
    for (int k = 2; k <= 3; ++k) {
      SelectOptions options = KOptions(Method::kAll, 4, k);
      options.ransac_iterations = 30;
      options.seed = trial;
      std::map<int, size_t> optimum, greedy_cells;
      for (const auto& s : subsets) {
        const int n = static_cast<int>(s.size());
        if (n > 4) continue;
        optimum[n] = std::max(optimum[n], KUnionSize(obs, s, k));
      }
      const std::vector<Selection> results = Select(obs, r, options);
      ASSERT_EQ(results.size(), 4u * (5 - k));
      for (const Selection& s : results) {
        SCOPED_TRACE(testing::Message() << "k=" << k << " " << s.method << " n=" << s.n);
        ASSERT_EQ(static_cast<int>(s.chosen.size()), s.n);
        EXPECT_EQ(std::set<uint32_t>(s.chosen.begin(), s.chosen.end()).size(), s.chosen.size());
        const size_t cells = KUnionSize(obs, s.chosen, k);
        EXPECT_DOUBLE_EQ(s.coverage, static_cast<double>(cells) / r);
        EXPECT_LE(cells, optimum[s.n]);
        if (s.method == "greedy") greedy_cells[s.n] = cells;
        if (s.method == "local") {
          EXPECT_GE(cells, greedy_cells[s.n]);
        }
        if (s.method == "exact") {
          EXPECT_EQ(cells, optimum[s.n]);
          EXPECT_TRUE(s.proven_optimal);
          ASSERT_TRUE(s.upper_bound.has_value());
          EXPECT_GE(*s.upper_bound, s.coverage);
          EXPECT_NEAR(*s.upper_bound, static_cast<double>(optimum[s.n]) / r, 1e-12);
        }
      }
    }

    // The k-coverage MILP itself (Select enumerates instances this small).
    {
      const detail::CoverageMatrix matrix(obs, r);
      for (int k = 2; k <= 3; ++k) {
        for (size_t n = static_cast<size_t>(k); n <= 4; ++n) {
          size_t best = 0;
          for (const auto& s : subsets) {
            if (s.size() == n) best = std::max(best, KUnionSize(obs, s, k));
          }
          const std::vector<uint32_t> start = detail::KGreedyComplete(matrix, {}, n, k);
          const detail::ExactResult milp = ExactK(matrix, n, k, start, 60, false);
          SCOPED_TRACE(testing::Message() << "MILP k=" << k << " n=" << n << " " << milp.note);
          ASSERT_EQ(milp.chosen.size(), n);
          EXPECT_EQ(KUnionSize(obs, milp.chosen, k), best);
          EXPECT_TRUE(milp.proven_optimal);
          EXPECT_EQ(milp.upper_bound, best);
        }
      }
    }

    // Budget: costs 1-5, budgets from tight to loose.
    std::vector<double> costs(m);
    Rng rng(600 + trial, Stream::kTest, 0);
    for (double& c : costs) c = 1.0 + static_cast<double>(rng.Below(5));
    for (const double budget : {5.0, 8.0, 12.5}) {
      SCOPED_TRACE(testing::Message() << "budget " << budget);
      size_t best = 0;
      for (const auto& s : subsets) {
        if (SumOfCosts(costs, s) <= budget) best = std::max(best, UnionSize(obs, s));
      }
      const std::vector<Selection> results =
          Select(obs, r, BudgetOptions(Method::kAll, budget, costs));
      ASSERT_EQ(results.size(), 3u);
      for (const Selection& s : results) {
        SCOPED_TRACE(s.method);
        ASSERT_TRUE(s.cost.has_value());
        EXPECT_LE(SumOfCosts(costs, s.chosen), budget);  // never above the budget
        EXPECT_EQ(*s.cost, SumOfCosts(costs, s.chosen));
        EXPECT_GE(s.n, 1);
        const size_t cells = UnionSize(obs, s.chosen);
        EXPECT_DOUBLE_EQ(s.coverage, static_cast<double>(cells) / r);
        EXPECT_LE(cells, best);
      }
      EXPECT_GE(results[1].coverage, results[0].coverage);  // local >= greedy
      const Selection& exact = results[2];
      EXPECT_EQ(UnionSize(obs, exact.chosen), best);
      EXPECT_TRUE(exact.proven_optimal);
      EXPECT_GE(*exact.upper_bound, exact.coverage);
    }

    // Set cover: goals as whole cells reachable by all candidates together.
    const size_t reachable = UnionSize(obs, subsets.back());
    for (const double share : {0.5, 0.8, 1.0}) {
      const double goal = std::floor(share * static_cast<double>(reachable)) / r;
      if (goal <= 0) continue;
      SCOPED_TRACE(testing::Message() << "goal " << goal);
      const size_t goal_cells = static_cast<size_t>(std::ceil(goal * r - 1e-9));
      size_t fewest = m;
      for (const auto& s : subsets) {
        if (UnionSize(obs, s) >= goal_cells) fewest = std::min(fewest, s.size());
      }
      const std::vector<Selection> results = Select(obs, r, GoalOptions(Method::kAll, goal));
      ASSERT_EQ(results.size(), 2u);
      for (const Selection& s : results) {
        EXPECT_GE(UnionSize(obs, s.chosen), goal_cells) << s.method;
        EXPECT_GE(s.coverage + 1e-12, goal) << s.method;
        EXPECT_GE(s.chosen.size(), fewest) << s.method;
      }
      EXPECT_EQ(results[1].chosen.size(), fewest);
      EXPECT_LE(results[1].n, results[0].n);
      EXPECT_TRUE(results[1].proven_optimal);
      EXPECT_EQ(results[1].n_lower_bound, static_cast<int>(fewest));
    }
  }
}

TEST(Objectives, CheapBoundsHoldOnRandomInstances) {
  for (uint64_t trial = 0; trial < 10; ++trial) {
    const size_t m = 9;
    const std::vector<Observation> obs = RandomInstance(700 + trial, m, 30, 0.2);
    const detail::CoverageMatrix matrix(obs, 30);
    const std::vector<std::vector<uint32_t>> subsets = AllSubsets(m);
    std::vector<double> costs(m);
    Rng rng(800 + trial, Stream::kTest, 0);
    for (double& c : costs) c = 0.5 + static_cast<double>(rng.Below(4));
    const double cheapest = *std::min_element(costs.begin(), costs.end());
    for (const double budget : {1.0, 4.0, 7.5}) {
      if (budget < cheapest) continue;  // Validate refuses it
      size_t best = 0;
      for (const auto& s : subsets) {
        if (SumOfCosts(costs, s) <= budget) best = std::max(best, UnionSize(obs, s));
      }
      const std::vector<uint32_t> greedy = detail::GreedyBudget(matrix, costs, budget);
      EXPECT_LE(detail::TotalCost(costs, greedy), budget);
      EXPECT_GE(detail::BudgetUpperBound(matrix, greedy, costs, budget), best);
    }
    for (int k = 2; k <= 3; ++k) {
      for (size_t n = static_cast<size_t>(k); n <= 4; ++n) {
        size_t best = 0;
        for (const auto& s : subsets) {
          if (s.size() == n) best = std::max(best, KUnionSize(obs, s, k));
        }
        const std::vector<uint32_t> start = detail::KGreedyComplete(matrix, {}, n, k);
        EXPECT_GE(detail::KUpperBound(matrix, start, n, k), best);
      }
    }
    const uint64_t seen = matrix.seen_weight();
    for (uint64_t goal = 1; goal <= seen; goal += 3) {
      size_t fewest = m;
      for (const auto& s : subsets) {
        if (UnionSize(obs, s) >= goal) fewest = std::min(fewest, s.size());
      }
      EXPECT_LE(detail::SetCoverLowerBound(matrix, goal), fewest);
    }
  }
}

TEST(Objectives, FallBackToTheStartWhenTheModelIsTooLarge) {
  // As ExactFallsBackToItsStart...: a 1 ms limit admits no MILP of this size.
  const std::vector<Observation> obs = RandomInstance(17, 60, 2000, 0.3);
  const detail::CoverageMatrix matrix(obs, 2000);
  const std::vector<uint32_t> k_start = detail::KGreedyComplete(matrix, {}, 3, 2);
  const detail::ExactResult k_result = ExactK(matrix, 3, 2, k_start, 0.001, false);
  EXPECT_EQ(k_result.chosen, k_start);
  EXPECT_FALSE(k_result.note.empty());
  EXPECT_GE(k_result.upper_bound, detail::KCoveredWeight(matrix, k_start, 2));

  const std::vector<double> costs(60, 2.0);
  const std::vector<uint32_t> b_start = detail::GreedyBudget(matrix, costs, 7);
  EXPECT_EQ(b_start.size(), 3u);
  const detail::ExactResult b_result = ExactBudget(matrix, costs, 7, b_start, 0.001);
  EXPECT_EQ(b_result.chosen, b_start);
  EXPECT_GE(b_result.upper_bound, matrix.CoveredWeight(b_start));

  const uint64_t goal = matrix.seen_weight() * 9 / 10;
  const std::vector<uint32_t> s_start = detail::GreedyToGoal(matrix, goal);
  const detail::SetCoverResult s_result = detail::SolveSetCover(matrix, goal, s_start, 0.001);
  EXPECT_EQ(s_result.chosen, s_start);
  EXPECT_LE(s_result.lower_bound, s_start.size());
  EXPECT_GE(s_result.lower_bound, 1u);
}

TEST(Objectives, DeterministicForASeed) {
  const std::vector<Observation> obs = RandomInstance(31, 14, 80, 0.2);
  std::vector<double> costs(14);
  for (size_t i = 0; i < costs.size(); ++i) costs[i] = 1.0 + static_cast<double>(i % 3);
  const std::vector<SelectOptions> all_options = {KOptions(Method::kAll, 4, 2),
                                                  GoalOptions(Method::kAll, 0.6),
                                                  BudgetOptions(Method::kAll, 6, costs)};
  for (const SelectOptions& options : all_options) {
    const std::vector<Selection> a = Select(obs, 80, options);
    const std::vector<Selection> b = Select(obs, 80, options);
    ASSERT_EQ(a.size(), b.size());
    for (size_t i = 0; i < a.size(); ++i) {
      EXPECT_EQ(a[i].chosen, b[i].chosen);
      EXPECT_EQ(a[i].upper_bound, b[i].upper_bound);
      EXPECT_EQ(a[i].n_lower_bound, b[i].n_lower_bound);
    }
  }
}

// ---------------------------------------------------------------------------------------------
// LP-strength bounds of the further objectives (issue 14), against enumeration and CLP

// The coverage LP of `obs` cell by cell for CLP (unit cell weights).
test::CoverageLpSpec LpSpec(const std::vector<Observation>& obs,
                            size_t cells,
                            int k,
                            std::vector<double> coefficients,
                            double capacity) {
  test::CoverageLpSpec spec;
  for (const Observation& o : obs) spec.rows.push_back(o.reference_indices);
  spec.weights.assign(cells, 1.0);
  spec.k = k;
  spec.coefficients = std::move(coefficients);
  spec.capacity = capacity;
  return spec;
}

TEST(ObjectiveBounds, KCoverageLpBoundHoldsAndMeetsClp) {
  int trials = 0;
  for (uint64_t trial = 0; trial < 12; ++trial) {
    const size_t m = 8 + trial % 13;          // 8..20 candidates
    const size_t r = 30 + (trial * 11) % 31;  // 30..60 cells
    const double p = 0.15 + 0.05 * static_cast<double>(trial % 4);
    const std::vector<Observation> obs = WeightedRandomInstance(1400 + trial, m, r, p);
    const detail::CoverageMatrix matrix(obs, r);
    for (int k = 2; k <= 3; ++k) {
      for (size_t n = static_cast<size_t>(k); n <= 4; ++n) {
        SCOPED_TRACE(testing::Message() << "trial " << trial << " k " << k << " n " << n);
        size_t best = 0;
        for (const auto& s : AllSubsets(std::min<size_t>(m, 12))) {
          if (s.size() == n) best = std::max(best, KUnionSize(obs, s, k));
        }
        if (m > 12) {  // the subsets of all m candidates of size n, by combination
          std::vector<bool> pick(m, false);
          std::fill(pick.begin(), pick.begin() + static_cast<std::ptrdiff_t>(n), true);
          do {
            std::vector<uint32_t> s;
            for (uint32_t i = 0; i < m; ++i) {
              if (pick[i]) s.push_back(i);
            }
            best = std::max(best, KUnionSize(obs, s, k));
          } while (std::prev_permutation(pick.begin(), pick.end()));
        }
        const detail::CoverageLpBound bound =
            detail::BoundCoverageLp(detail::CardinalityLp(matrix, n, k), 0, 3000, 1e9);
        EXPECT_GE(bound.upper_bound, best);
        const double lp =
            test::CoverageLpOptimum(LpSpec(obs, r, k, std::vector<double>(m, 1.0), n));
        // No multipliers go below the LP optimum; the steps come within 2 % of it.
        EXPECT_GE(static_cast<double>(bound.upper_bound), std::floor(lp + 1e-7));
        EXPECT_LE(static_cast<double>(bound.upper_bound), lp * 1.02 + 1);
        // exact: the optimum, and its bound no looser than the LP's when CBC does not prove it.
        const std::vector<uint32_t> start = detail::KGreedyComplete(matrix, {}, n, k);
        auto upper_bound = static_cast<double>(matrix.seen_weight());
        const uint64_t cells = KCoveredWeight(matrix, start, k);
        detail::TightenByLpBound(detail::CardinalityLp(matrix, n, k), cells,
                                 std::chrono::steady_clock::now(), 1e9, &upper_bound);
        EXPECT_GE(upper_bound, static_cast<double>(best));
        EXPECT_LE(upper_bound, static_cast<double>(std::max<uint64_t>(cells, bound.upper_bound)));
        ++trials;
      }
    }
  }
  EXPECT_EQ(trials, 12 * 5);
}

TEST(ObjectiveBounds, BudgetLpBoundHoldsAndMeetsClp) {
  for (uint64_t trial = 0; trial < 12; ++trial) {
    const size_t m = 6 + trial % 7;  // 6..12 candidates: every subset is enumerated
    const size_t r = 30 + (trial * 13) % 31;
    const std::vector<Observation> obs = WeightedRandomInstance(1500 + trial, m, r, 0.2);
    const detail::CoverageMatrix matrix(obs, r);
    std::vector<double> costs(m);
    Rng rng(1600 + trial, Stream::kTest, 0);
    for (double& c : costs) c = 0.25 * static_cast<double>(rng.Below(17));  // 0..4, some free
    const std::vector<std::vector<uint32_t>> subsets = AllSubsets(m);
    for (const double budget : {1.0, 3.5, 6.0, 9.75}) {
      SCOPED_TRACE(testing::Message() << "trial " << trial << " budget " << budget);
      size_t best = 0;
      for (const auto& s : subsets) {
        if (SumOfCosts(costs, s) <= budget) best = std::max(best, UnionSize(obs, s));
      }
      const detail::CoverageLpBound bound =
          detail::BoundCoverageLp(detail::BudgetLp(matrix, costs, budget), 0, 3000, 1e9);
      EXPECT_GE(bound.upper_bound, best);
      const double lp = test::CoverageLpOptimum(LpSpec(obs, r, 1, costs, budget));
      EXPECT_GE(static_cast<double>(bound.upper_bound), std::floor(lp + 1e-7));
      EXPECT_LE(static_cast<double>(bound.upper_bound), lp * 1.02 + 1);
      // exact finds the optimum and its bound holds.
      if (*std::min_element(costs.begin(), costs.end()) > budget) continue;
      const std::vector<uint32_t> start = detail::GreedyBudget(matrix, costs, budget);
      const detail::ExactResult exact = ExactBudget(matrix, costs, budget, start, 60);
      EXPECT_EQ(UnionSize(obs, exact.chosen), best) << exact.note;
      EXPECT_LE(detail::TotalCost(costs, exact.chosen), budget);
      EXPECT_GE(exact.upper_bound, best);
    }
  }
}

// The hand-worked K5 instance (CompleteGraphInstance) with a budget: each vertex costs 1, the
// budget 2 is its cardinality LP, 9; the same vertices at cost 2 with budget 3 allow 1.5 of them:
// uniform x_v = 3/10 covers every edge 3/5 and c fully, LP = 10 * 3/5 + 1 = 7 (concave and
// symmetric, as for N = 2).
TEST(ObjectiveBounds, BudgetBoundOfAHandWorkedInstance) {
  const std::vector<Observation> obs = CompleteGraphInstance();
  const detail::CoverageMatrix matrix(obs, 11);
  const std::vector<double> unit(5, 1.0), two(5, 2.0);
  EXPECT_EQ(detail::BoundCoverageLp(detail::BudgetLp(matrix, unit, 2), 8, 3000, 1e9).upper_bound,
            9u);
  EXPECT_EQ(detail::BoundCoverageLp(detail::BudgetLp(matrix, two, 3), 5, 3000, 1e9).upper_bound,
            7u);
}

TEST(ObjectiveBounds, SetCoverLpLowerBoundNeverExceedsTheFewest) {
  int tighter = 0;
  for (uint64_t trial = 0; trial < 10; ++trial) {
    const size_t m = 8 + trial % 5;  // 8..12
    const size_t r = 30 + (trial * 7) % 31;
    const std::vector<Observation> obs = WeightedRandomInstance(1700 + trial, m, r, 0.15);
    const detail::CoverageMatrix matrix(obs, r);
    const std::vector<std::vector<uint32_t>> subsets = AllSubsets(m);
    for (uint64_t goal = 2; goal <= matrix.seen_weight(); goal += 5) {
      SCOPED_TRACE(testing::Message() << "trial " << trial << " goal " << goal);
      size_t fewest = m;
      for (const auto& s : subsets) {
        if (UnionSize(obs, s) >= goal) fewest = std::min(fewest, s.size());
      }
      // The least t whose LP (CLP) reaches the goal: no valid bound proves it too few.
      size_t lp_least = 1;
      while (test::CoverageLpOptimum(
                 LpSpec(obs, r, 1, std::vector<double>(m, 1.0), static_cast<double>(lp_least))) <
             static_cast<double>(goal) - 1e-7) {
        ++lp_least;
      }
      const size_t lower = detail::SetCoverLpLowerBound(matrix, goal, 1, m, 1e9);
      EXPECT_LE(lower, fewest);
      EXPECT_LE(lower, lp_least);
      EXPECT_GE(lower, 1u);
      if (lower > detail::SetCoverLowerBound(matrix, goal)) ++tighter;
      // exact reaches the goal with the fewest sensors and proves it.
      const std::vector<uint32_t> start = detail::GreedyToGoal(matrix, goal);
      const detail::SetCoverResult exact = detail::SolveSetCover(matrix, goal, start, 60);
      EXPECT_EQ(exact.chosen.size(), fewest);
      EXPECT_LE(exact.lower_bound, fewest);
      EXPECT_TRUE(exact.proven_optimal);
    }
  }
  EXPECT_GT(tighter, 0);  // the LP bound improves on the largest rows somewhere
}

// ----- installation constraints (issue 20, docs/constraints.md) ------------------------------

namespace constraints_test {

// The best coverage (cells) over every subset of at most n candidates that satisfies the
// constraints, checked here independently: no conflicting pair inside, and (with a rule) the
// subset's overlap graph connected, by a union-find over pairwise intersections.
uint64_t EnumeratedOptimum(const std::vector<Observation>& obs, size_t n,
                           const InstallConstraints& constraints) {
  const size_t m = obs.size();
  uint64_t best = 0;
  for (uint32_t mask = 1; mask < (1u << m); ++mask) {
    std::vector<uint32_t> set;
    for (uint32_t i = 0; i < m; ++i)
      if (mask & (1u << i)) set.push_back(i);
    if (set.size() > n) continue;
    if (!test::SatisfiesConstraints(obs, set, constraints)) continue;
    std::set<uint32_t> cells;
    for (const uint32_t i : set)
      cells.insert(obs[i].reference_indices.begin(), obs[i].reference_indices.end());
    best = std::max<uint64_t>(best, cells.size());
  }
  return best;
}

// Random conflicting pairs among m candidates, sorted.
std::vector<Conflict> RandomConflicts(uint64_t seed, size_t m, double p) {
  Rng rng(seed, Stream::kTest, 1);
  std::vector<Conflict> conflicts;
  for (uint32_t a = 0; a < m; ++a)
    for (uint32_t b = a + 1; b < m; ++b)
      if (rng.Uniform01() < p) conflicts.push_back({a, b, ConflictKind::kSeparation, 0});
  return conflicts;
}

// Every method's answer for `options` (40 cells, kept sensors options.fixed): the kept sensors
// first, at least `fewest` and at most n sensors, feasible (checked here), covering at most the
// enumerated `optimum`; exact's covers it with a bound at or above it, proven.
void ExpectKeptAnswers(const std::vector<Observation>& obs, SelectOptions options,
                       uint64_t optimum, size_t fewest) {
  const std::vector<uint32_t>& kept = options.fixed;
  for (const Method method : {Method::kRansac, Method::kGreedy, Method::kLocal, Method::kExact}) {
    options.method = method;
    const Selection s = Select(obs, 40, options).front();
    ASSERT_GE(s.chosen.size(), fewest) << s.method;
    EXPECT_LE(s.chosen.size(), static_cast<size_t>(options.n)) << s.method;
    EXPECT_TRUE(std::equal(kept.begin(), kept.end(), s.chosen.begin())) << s.method;
    EXPECT_TRUE(test::SatisfiesConstraints(obs, s.chosen, options.constraints)) << s.method;
    EXPECT_LE(UnionSize(obs, s.chosen), optimum) << s.method;
    if (method == Method::kExact) {
      EXPECT_EQ(UnionSize(obs, s.chosen), optimum);
      ASSERT_TRUE(s.upper_bound.has_value());
      EXPECT_GE(*s.upper_bound + 1e-12, static_cast<double>(optimum) / 40.0);
      EXPECT_TRUE(s.proven_optimal);
    }
  }
}

}  // namespace constraints_test

TEST(Constraints, InterferenceConflictsUseTheShareOfTheSmallerSet) {
  // 0 and 1 share 3 of 1's 4 cells (75 %); 0 and 2 share 1 of 2's 10 (10 %): not above 0.1;
  // 3 does not project.
  std::vector<Observation> obs = {Obs({0, 1, 2, 3, 4, 5, 6, 7, 8, 9}), Obs({0, 1, 2, 20}),
                                  Obs({9, 10, 11, 12, 13, 14, 15, 16, 17, 18}), Obs({0, 1, 2})};
  const std::vector<bool> projecting = {true, true, true, false};
  const std::vector<Conflict> conflicts = InterferenceConflicts(obs, projecting, 0.1);
  ASSERT_EQ(conflicts.size(), 1u);
  EXPECT_EQ(conflicts[0].a, 0u);
  EXPECT_EQ(conflicts[0].b, 1u);
  EXPECT_DOUBLE_EQ(conflicts[0].value, 0.75);
  // Lower the threshold below 10 %: 0 ~ 2 conflicts too.
  EXPECT_EQ(InterferenceConflicts(obs, projecting, 0.09).size(), 2u);
  // Illumination ignores the quality filter: the plain cells count.
  obs[1].plain_reference_indices = {0, 1, 2, 20};
  obs[1].reference_indices = {20};
  EXPECT_EQ(InterferenceConflicts(obs, projecting, 0.1).size(), 1u);
}

TEST(Constraints, InterferenceConflictsStopPastTheirLimit) {
  // Six candidates that all see the same cells: 15 pairs conflict. With a limit of 4 the scan
  // stops at the fifth (the caller refuses that many), and a limit at or above 15 loses none.
  const std::vector<Observation> obs(6, Obs({0, 1, 2, 3}));
  const std::vector<bool> projecting(6, true);
  EXPECT_EQ(InterferenceConflicts(obs, projecting, 0.1).size(), 15u);
  EXPECT_EQ(InterferenceConflicts(obs, projecting, 0.1, 4).size(), 5u);
  EXPECT_EQ(InterferenceConflicts(obs, projecting, 0.1, 15).size(), 15u);
}

TEST(Constraints, BridgingSensorJoinsTwoDisjointViews) {
  // 0 and 1 see disjoint halves; 2 sees a little of both (the bridge). Unconstrained, n = 2
  // takes 0 and 1 (all 20 cells); connected by >= 2 common cells, the bridge must be in.
  std::vector<uint32_t> left(10), right(10);
  std::iota(left.begin(), left.end(), 0U);
  std::iota(right.begin(), right.end(), 10U);
  const std::vector<Observation> obs = {Obs(left), Obs(right), Obs({7, 8, 9, 10, 11, 12})};
  SelectOptions options;
  options.n = 2;
  options.method = Method::kExact;
  const std::vector<Selection> plain = Select(obs, 20, options);
  EXPECT_EQ(std::set<uint32_t>(plain[0].chosen.begin(), plain[0].chosen.end()),
            (std::set<uint32_t>{0, 1}));
  options.constraints.calibration = CalibrationRule{2, std::nullopt};
  for (const Method method : {Method::kGreedy, Method::kLocal, Method::kExact, Method::kRansac}) {
    options.method = method;
    const Selection s = Select(obs, 20, options).front();
    EXPECT_EQ(s.chosen.size(), 2u) << s.method;
    EXPECT_TRUE(std::count(s.chosen.begin(), s.chosen.end(), 2u)) << s.method;
    // Either half with the bridge: 10 + 3 cells.
    EXPECT_DOUBLE_EQ(s.coverage, 13.0 / 20.0) << s.method;
    EXPECT_TRUE(CheckConstraints(obs, s.chosen, options.constraints).connected()) << s.method;
  }
  const ConstraintCheck apart = CheckConstraints(obs, plain[0].chosen, options.constraints);
  EXPECT_FALSE(apart.connected());
  EXPECT_EQ(apart.components.size(), 2u);
  // A share of the smaller set: 3 of the bridge's 6 cells = 0.5.
  options.constraints.calibration = CalibrationRule{std::nullopt, 0.5};
  const std::vector<uint32_t> all = {0, 1, 2};
  const std::vector<OverlapEdge> edges = OverlapGraph(obs, all, options.constraints.calibration);
  ASSERT_EQ(edges.size(), 2u);
  EXPECT_EQ(edges[0].cells, 3u);
  options.constraints.calibration = CalibrationRule{std::nullopt, 0.51};
  EXPECT_TRUE(OverlapGraph(obs, all, options.constraints.calibration).empty());
}

TEST(Constraints, ExactMatchesEnumerationOnRandomInstances) {
  int instances = 0;
  for (uint64_t seed = 1; seed <= 8; ++seed) {
    const size_t m = 8 + seed % 5;  // 8..12 candidates
    const std::vector<Observation> obs = RandomInstance(seed, m, 40, 0.25);
    for (int variant = 0; variant < 3; ++variant) {
      SelectOptions options;
      options.n = 2 + static_cast<int>(seed % 2);
      options.seed = seed;
      options.ransac_iterations = 50;
      if (variant != 1)
        options.constraints.conflicts = constraints_test::RandomConflicts(seed, m, 0.3);
      if (variant == 1) options.constraints.calibration = CalibrationRule{3, std::nullopt};
      if (variant == 2) options.constraints.calibration = CalibrationRule{std::nullopt, 0.2};
      const uint64_t optimum = constraints_test::EnumeratedOptimum(
          obs, static_cast<size_t>(options.n), options.constraints);
      const double optimum_share = static_cast<double>(optimum) / 40.0;
      // The heuristics: feasible, never above the optimum (one CBC run per instance: exact's).
      for (const Method method : {Method::kRansac, Method::kGreedy, Method::kLocal}) {
        options.method = method;
        const Selection s = Select(obs, 40, options).front();
        const ConstraintCheck check = CheckConstraints(obs, s.chosen, options.constraints);
        EXPECT_TRUE(check.conflicts.empty()) << s.method << " seed " << seed;
        if (options.constraints.calibration) {
          EXPECT_TRUE(check.connected()) << s.method << " seed " << seed;
        }
        EXPECT_LE(s.coverage, optimum_share + 1e-12) << s.method << " seed " << seed;
      }
      options.method = Method::kExact;
      const Selection exact = Select(obs, 40, options).front();
      EXPECT_DOUBLE_EQ(exact.coverage, optimum_share) << "seed " << seed << " variant " << variant;
      const ConstraintCheck exact_check = CheckConstraints(obs, exact.chosen, options.constraints);
      EXPECT_TRUE(exact_check.conflicts.empty() &&
                  (!options.constraints.calibration || exact_check.connected()))
          << "seed " << seed;
      ASSERT_TRUE(exact.upper_bound.has_value());
      EXPECT_GE(*exact.upper_bound + 1e-12, optimum_share);
      EXPECT_TRUE(exact.proven_optimal);
      ++instances;
    }
  }
  EXPECT_EQ(instances, 24);
}

TEST(Constraints, SeparationPairsFromPositionsAndExactMatchesEnumeration) {
  for (uint64_t seed = 1; seed <= 6; ++seed) {
    const size_t m = 8 + seed % 4;  // 8..11 candidates in a 1 m cube
    Rng rng(seed, Stream::kTest, 2);
    std::vector<Candidate> candidates(m);
    for (Candidate& c : candidates)
      c.world_from_body.position = Vec3(rng.Uniform01(), rng.Uniform01(), rng.Uniform01());
    const double min_separation = 0.45;
    // Every pair compared directly.
    std::vector<std::pair<uint32_t, uint32_t>> expected;
    for (uint32_t a = 0; a < m; ++a) {
      for (uint32_t b = a + 1; b < m; ++b) {
        const Vec3 d = candidates[a].world_from_body.position - candidates[b].world_from_body.position;
        if (std::sqrt(d.x() * d.x() + d.y() * d.y() + d.z() * d.z()) < min_separation)
          expected.emplace_back(a, b);
      }
    }
    const std::vector<Conflict> pairs = detail::SeparationConflicts(candidates, min_separation);
    ASSERT_EQ(pairs.size(), expected.size()) << "seed " << seed;
    for (size_t i = 0; i < pairs.size(); ++i) {
      EXPECT_EQ(std::make_pair(pairs[i].a, pairs[i].b), expected[i]) << "seed " << seed;
      EXPECT_EQ(pairs[i].kind, ConflictKind::kSeparation);
      EXPECT_LT(pairs[i].value, min_separation);
    }
    const std::vector<Observation> obs = RandomInstance(seed + 100, m, 40, 0.25);
    SelectOptions options;
    options.n = 3;
    options.seed = seed;
    options.method = Method::kExact;
    options.constraints.conflicts = pairs;
    const uint64_t optimum = constraints_test::EnumeratedOptimum(obs, 3, options.constraints);
    const Selection exact = Select(obs, 40, options).front();
    EXPECT_DOUBLE_EQ(exact.coverage, static_cast<double>(optimum) / 40.0) << "seed " << seed;
    EXPECT_TRUE(CheckConstraints(obs, exact.chosen, options.constraints).conflicts.empty());
    ASSERT_TRUE(exact.upper_bound.has_value());
    EXPECT_GE(*exact.upper_bound + 1e-12, static_cast<double>(optimum) / 40.0);
    EXPECT_TRUE(exact.proven_optimal) << "seed " << seed;
  }
}

namespace constraints_test {

// Whether `set` satisfies `constraints` (EnumeratedOptimum's test, for one set).
bool IsFeasibleSet(const std::vector<Observation>& obs,
                   const std::vector<uint32_t>& set,
                   const InstallConstraints& constraints) {
  return test::SatisfiesConstraints(obs, set, constraints);
}

}  // namespace constraints_test

// k-coverage, min-points, a budget and set cover under conflicts and calibration rules, against
// the optimum of every feasible subset: exact finds it with a valid bound, the heuristics stay
// feasible and below it; an unreachable goal is an InputError.
TEST(Constraints, OtherObjectivesMatchEnumeration) {
  int instances = 0, binding = 0, unreachable = 0;
  for (uint64_t seed = 1; seed <= 6; ++seed) {
    const size_t m = 8 + seed % 5;  // 8..12 candidates
    std::vector<Observation> obs = RandomInstance(900 + seed, m, 40, 0.3);
    Rng rng(950 + seed, Stream::kTest, 0);
    for (Observation& o : obs) {
      for (size_t j = 0; j < o.reference_indices.size(); ++j)
        o.reference_hits.push_back(static_cast<uint16_t>(1 + rng.Below(8)));
    }
    std::vector<double> costs(m);
    for (double& c : costs) c = static_cast<double>(1 + rng.Below(3));
    const std::vector<std::vector<uint32_t>> subsets = AllSubsets(m);
    for (int variant = 0; variant < 3; ++variant) {
      InstallConstraints constraints;
      if (variant != 1) constraints.conflicts = constraints_test::RandomConflicts(seed, m, 0.3);
      if (variant == 1) constraints.calibration = CalibrationRule{4, std::nullopt};
      if (variant == 2) constraints.calibration = CalibrationRule{std::nullopt, 0.3};
      for (int objective = 0; objective < 5; ++objective) {
        const bool is_cover = objective >= 3;  // set cover, goals of 26 and 34 cells
        SCOPED_TRACE(testing::Message()
                     << "seed " << seed << " variant " << variant << " objective " << objective);
        SelectOptions options;
        options.n = 3;
        options.seed = seed;
        options.ransac_iterations = 40;
        options.constraints = constraints;
        if (objective == 0) options.k = 2;
        if (objective == 1) options.min_points = 6;
        if (objective == 2) {
          options.budget = 4;
          options.costs = costs;
        }
        const uint64_t goal_cells = objective == 4 ? 34 : 26;
        if (is_cover) options.goal = static_cast<double>(goal_cells) / 40.0;
        // The optimum by enumeration: most cells (objectives 0-2), fewest sensors (set cover).
        const auto value = [&](const std::vector<uint32_t>& set) -> uint64_t {
          if (objective == 0) return KUnionSize(obs, set, 2);
          if (objective == 1) return PointUnionSize(obs, set, 6);
          return UnionSize(obs, set);
        };
        uint64_t optimum = 0, free_optimum = 0;
        size_t fewest = m + 1, free_fewest = m + 1;
        for (const std::vector<uint32_t>& set : subsets) {
          if (objective == 2 && detail::TotalCost(costs, set) > 4) continue;
          if (objective != 2 && !is_cover && set.size() > 3) continue;
          const bool feasible = constraints_test::IsFeasibleSet(obs, set, constraints);
          const uint64_t v = value(set);
          if (is_cover) {
            if (v < goal_cells) continue;
            free_fewest = std::min(free_fewest, set.size());
            if (feasible) fewest = std::min(fewest, set.size());
            continue;
          }
          free_optimum = std::max(free_optimum, v);
          if (feasible) optimum = std::max(optimum, v);
        }
        if (is_cover && fewest > m) {
          if (free_fewest <= m) {  // reachable without the constraints only
            options.method = Method::kExact;
            EXPECT_THROW(Select(obs, 40, options), InputError);
            ++unreachable;
          }
          continue;
        }
        if (is_cover ? fewest > free_fewest : optimum < free_optimum) ++binding;
        const std::vector<Method> heuristics =
            is_cover ? std::vector<Method>{Method::kGreedy}
            : objective == 2
                ? std::vector<Method>{Method::kGreedy, Method::kLocal}
                : std::vector<Method>{Method::kRansac, Method::kGreedy, Method::kLocal};
        for (const Method method : heuristics) {
          options.method = method;
          const Selection s = Select(obs, 40, options).front();
          EXPECT_TRUE(constraints_test::IsFeasibleSet(obs, s.chosen, constraints)) << s.method;
          if (is_cover) {
            EXPECT_GE(UnionSize(obs, s.chosen), goal_cells);
            EXPECT_GE(s.chosen.size(), fewest);
          } else {
            EXPECT_LE(value(s.chosen), optimum) << s.method;
            EXPECT_DOUBLE_EQ(s.coverage, static_cast<double>(value(s.chosen)) / 40.0) << s.method;
          }
          if (objective == 2) {
            EXPECT_LE(detail::TotalCost(costs, s.chosen), 4.0);
          }
        }
        options.method = Method::kExact;
        // Under the sanitizers a proof may not finish within the limit (test::kSanitized): there
        // the limit is short, so that the suite stays within ctest's timeout, and an unproven
        // answer is checked against the optimum and its bound only.
        if (test::kSanitized) options.time_limit = 3;
        const Selection exact = Select(obs, 40, options).front();
        EXPECT_TRUE(constraints_test::IsFeasibleSet(obs, exact.chosen, constraints));
        if (!test::kSanitized) {
          EXPECT_TRUE(exact.proven_optimal);
        }
        const bool must_be_optimal = exact.proven_optimal || !test::kSanitized;
        if (is_cover) {
          if (must_be_optimal) {
            EXPECT_EQ(exact.chosen.size(), fewest);
          } else {
            EXPECT_GE(UnionSize(obs, exact.chosen), goal_cells);
            EXPECT_GE(exact.chosen.size(), fewest);
          }
          ASSERT_TRUE(exact.n_lower_bound.has_value());
          EXPECT_LE(static_cast<size_t>(*exact.n_lower_bound), fewest);
        } else {
          if (must_be_optimal) {
            EXPECT_EQ(value(exact.chosen), optimum);
          } else {
            EXPECT_LE(value(exact.chosen), optimum);
          }
          ASSERT_TRUE(exact.upper_bound.has_value());
          EXPECT_GE(*exact.upper_bound + 1e-12, static_cast<double>(optimum) / 40.0);
        }
        ++instances;
      }
    }
  }
  EXPECT_GE(instances, 60);
  EXPECT_GE(binding, 20);
  EXPECT_GE(unreachable, 1);
}

// Kept sensors under the constraints: every answer starts with them and satisfies the
// constraints, exact's is the best feasible superset (enumerated); kept sensors that conflict are
// an InputError.
TEST(Constraints, KeptSensorsMatchEnumeration) {
  int instances = 0;
  for (uint64_t seed = 1; seed <= 6; ++seed) {
    const size_t m = 8 + seed % 4;  // 8..11 candidates
    const std::vector<Observation> obs = RandomInstance(1200 + seed, m, 40, 0.3);
    const std::vector<std::vector<uint32_t>> subsets = AllSubsets(m);
    for (int variant = 0; variant < 2; ++variant) {
      InstallConstraints constraints;
      std::vector<uint32_t> kept = {static_cast<uint32_t>(seed % m)};
      if (variant == 0) {
        constraints.conflicts = constraints_test::RandomConflicts(seed, m, 0.3);
        // A second kept sensor that does not conflict with the first.
        for (uint32_t c = 0; c < m && kept.size() < 2; ++c) {
          if (c != kept[0] && constraints_test::IsFeasibleSet(obs, {kept[0], c}, constraints))
            kept.push_back(c);
        }
      } else {
        constraints.calibration = CalibrationRule{4, std::nullopt};
      }
      SCOPED_TRACE(testing::Message() << "seed " << seed << " variant " << variant);
      SelectOptions options;
      options.n = static_cast<int>(kept.size()) + 2;
      options.seed = seed;
      options.ransac_iterations = 40;
      options.constraints = constraints;
      options.fixed = kept;
      uint64_t optimum = 0;
      for (const std::vector<uint32_t>& set : subsets) {
        if (set.size() > static_cast<size_t>(options.n)) continue;
        if (!std::all_of(kept.begin(), kept.end(),
                         [&](uint32_t k) { return std::count(set.begin(), set.end(), k) > 0; }))
          continue;
        if (!constraints_test::IsFeasibleSet(obs, set, constraints)) continue;
        optimum = std::max<uint64_t>(optimum, UnionSize(obs, set));
      }
      constraints_test::ExpectKeptAnswers(obs, options, optimum, kept.size());
      options.method = Method::kAll;
      for (const Selection& s : Select(obs, 40, options)) {
        EXPECT_TRUE(std::equal(kept.begin(), kept.end(), s.chosen.begin())) << s.method;
        EXPECT_TRUE(constraints_test::IsFeasibleSet(obs, s.chosen, constraints)) << s.method;
      }
      // best: the kept sensors and the best feasible single addition.
      uint64_t best_single = 0;
      for (uint32_t c = 0; c < m; ++c) {
        if (std::count(kept.begin(), kept.end(), c)) continue;
        std::vector<uint32_t> set = kept;
        set.push_back(c);
        if (constraints_test::IsFeasibleSet(obs, set, constraints))
          best_single = std::max<uint64_t>(best_single, UnionSize(obs, set));
      }
      options.method = Method::kBest;
      options.n = static_cast<int>(kept.size()) + 1;
      const Selection best = Select(obs, 40, options).front();
      EXPECT_EQ(best.method, "best");
      EXPECT_TRUE(std::equal(kept.begin(), kept.end(), best.chosen.begin()));
      EXPECT_TRUE(constraints_test::IsFeasibleSet(obs, best.chosen, constraints));
      if (best_single > 0) {
        EXPECT_EQ(UnionSize(obs, best.chosen), best_single);
      }
      ++instances;
    }
  }
  EXPECT_EQ(instances, 12);
  // Two kept sensors in conflict.
  const std::vector<Observation> obs = RandomInstance(5, 6, 40, 0.3);
  SelectOptions options;
  options.n = 3;
  options.fixed = {1, 4};
  options.constraints.conflicts = {{1, 4, ConflictKind::kSeparation, 0.1}};
  EXPECT_THROW(Select(obs, 40, options), InputError);
}

// Kept sensors that the calibration rule leaves apart (issue 20): every answer holds them and a
// chain that joins them. Exact's answer is the best connected superset of at most n (enumerated)
// and its bound holds; best is the best single candidate that joins them, or an InputError when
// none does; when no superset of at most n is connected, every method is an InputError.
TEST(Constraints, DisconnectedKeptSensorsAreBridged) {
  int bridged = 0, one_joins = 0, refused = 0;
  for (uint64_t seed = 1; seed <= 40 && bridged < 12; ++seed) {
    const size_t m = 8 + seed % 4;  // 8..11 candidates
    const std::vector<Observation> obs = RandomInstance(2400 + seed, m, 40, 0.25);
    InstallConstraints constraints;
    constraints.calibration = CalibrationRule{3, std::nullopt};
    // The first pair of candidates that see something and are not joined.
    std::vector<uint32_t> kept;
    for (uint32_t a = 0; a < m && kept.empty(); ++a) {
      for (uint32_t b = a + 1; b < m && kept.empty(); ++b) {
        if (!obs[a].reference_indices.empty() && !obs[b].reference_indices.empty() &&
            !test::SatisfiesConstraints(obs, std::vector<uint32_t>{a, b}, constraints))
          kept = {a, b};
      }
    }
    if (kept.empty()) continue;
    SCOPED_TRACE(testing::Message() << "seed " << seed << " kept " << kept[0] << ", " << kept[1]);
    const size_t n = 4;
    // Enumerated: the fewest sensors of a connected superset, and the best one of at most n.
    size_t fewest = m + 1;
    uint64_t optimum = 0, best_single = 0;
    for (const std::vector<uint32_t>& set : AllSubsets(m)) {
      if (!std::count(set.begin(), set.end(), kept[0]) ||
          !std::count(set.begin(), set.end(), kept[1]) ||
          !test::SatisfiesConstraints(obs, set, constraints))
        continue;
      fewest = std::min(fewest, set.size());
      if (set.size() <= n) optimum = std::max<uint64_t>(optimum, UnionSize(obs, set));
      if (set.size() == 3) best_single = std::max<uint64_t>(best_single, UnionSize(obs, set));
    }
    SelectOptions options;
    options.n = static_cast<int>(n);
    options.seed = seed;
    options.ransac_iterations = 200;
    options.constraints = constraints;
    options.fixed = kept;
    if (fewest > n) {
      for (const Method method : {Method::kGreedy, Method::kExact, Method::kAll}) {
        options.method = method;
        EXPECT_THROW(Select(obs, 40, options), InputError) << MethodName(method);
      }
      ++refused;
      continue;
    }
    // Two parts without conflicts: the shortest chain is the fewest sensors that join them.
    const std::vector<uint32_t> start = ConnectKept(obs, kept, constraints);
    EXPECT_EQ(start.size(), fewest);
    EXPECT_TRUE(std::equal(kept.begin(), kept.end(), start.begin()));
    EXPECT_TRUE(test::SatisfiesConstraints(obs, start, constraints));
    constraints_test::ExpectKeptAnswers(obs, options, optimum, fewest);
    options.method = Method::kAll;
    for (const Selection& s : Select(obs, 40, options)) {
      EXPECT_GE(s.chosen.size(), fewest) << s.method;
      EXPECT_TRUE(test::SatisfiesConstraints(obs, s.chosen, constraints)) << s.method;
    }
    options.method = Method::kBest;
    options.n = 3;
    if (fewest == 3) {
      const Selection best = Select(obs, 40, options).front();
      EXPECT_EQ(UnionSize(obs, best.chosen), best_single);
      EXPECT_TRUE(test::SatisfiesConstraints(obs, best.chosen, constraints));
      ++one_joins;
    } else {
      EXPECT_THROW(Select(obs, 40, options), InputError);
    }
    ++bridged;
  }
  EXPECT_EQ(bridged, 12);
  EXPECT_GE(one_joins, 3);
  EXPECT_GE(refused, 1);
}

TEST(Constraints, ValidateNamesTheField) {
  const std::vector<Observation> obs = {Obs({0}), Obs({1}), Obs({2})};
  SelectOptions options;
  options.n = 2;
  options.constraints.conflicts = {{1, 0, ConflictKind::kInterference, 1}};
  try {
    options.Validate(obs.size());
    ADD_FAILURE() << "accepted a >= b";
  } catch (const FieldError& e) {
    EXPECT_EQ(e.fields(), std::vector<std::string>{"conflicts"});
  }
  options.constraints.conflicts = {{0, 1, ConflictKind::kInterference, 1}};
  options.k = 2;
  EXPECT_NO_THROW(options.Validate(obs.size()));  // k-coverage under constraints (issue 20)
  options.k = 1;
  options.fixed = {0};
  EXPECT_NO_THROW(options.Validate(obs.size()));  // kept sensors under constraints (issue 20)
  options.fixed.clear();
  options.constraints.calibration = CalibrationRule{0, std::nullopt};
  try {
    options.Validate(obs.size());
    ADD_FAILURE() << "accepted 0 cells";
  } catch (const FieldError& e) {
    EXPECT_EQ(e.fields(), std::vector<std::string>{"calibration_overlap"});
  }
}

}  // namespace
}  // namespace vantage
