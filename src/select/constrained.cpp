// Selection under installation constraints (docs/constraints.md): feasibility of a set, and
// greedy, local search and RANSAC restricted to feasible sets, each a template over the scorer
// (scorer.hpp), so that one implementation serves plain coverage, k-coverage, point counts, a
// budget and the states of a scene; exact asks the selection model (model.hpp, exact.cpp).
#include "select/constrained.hpp"

#include <fmt/format.h>
#include <spdlog/spdlog.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <numeric>

#include "select/model.hpp"
#include "select/run_methods.hpp"
#include "vantage/error.hpp"
#include "vantage/interrupt.hpp"

namespace vantage::detail {
namespace {

using Clock = std::chrono::steady_clock;

bool SortedHas(const std::vector<uint32_t>& sorted, uint32_t value) {
  return std::binary_search(sorted.begin(), sorted.end(), value);
}

}  // namespace

Feasibility::Feasibility(std::span<const Observation> observations,
                         const InstallConstraints& constraints)
    : conflicts_(constraints.conflicts),
      conflicts_of_(observations.size()),
      neighbours_(observations.size()),
      has_calibration_(constraints.calibration.has_value()) {
  for (const Conflict& c : conflicts_) {
    conflicts_of_[c.a].push_back(c.b);
    conflicts_of_[c.b].push_back(c.a);
  }
  for (std::vector<uint32_t>& list : conflicts_of_) std::sort(list.begin(), list.end());
  if (!has_calibration_) return;
  std::vector<uint32_t> all(observations.size());
  std::iota(all.begin(), all.end(), 0U);
  for (const OverlapEdge& e : OverlapGraph(observations, all, constraints.calibration)) {
    neighbours_[e.a].push_back(e.b);
    neighbours_[e.b].push_back(e.a);
  }
  for (std::vector<uint32_t>& list : neighbours_) std::sort(list.begin(), list.end());
}

bool Feasibility::InConflict(uint32_t a, uint32_t b) const { return SortedHas(conflicts_of_[a], b); }

bool Feasibility::Joined(uint32_t a, uint32_t b) const { return SortedHas(neighbours_[a], b); }

bool Feasibility::CanAdd(std::span<const uint32_t> set, uint32_t candidate) const {
  bool is_joined = !has_calibration_ || set.empty();
  for (const uint32_t s : set) {
    if (s == candidate || InConflict(s, candidate)) return false;
    if (!is_joined && Joined(s, candidate)) is_joined = true;
  }
  return is_joined;
}

bool Feasibility::IsConnected(std::span<const uint32_t> set) const {
  if (set.size() <= 1) return true;
  std::vector<bool> reached(set.size(), false);
  std::vector<size_t> stack{0};
  reached[0] = true;
  size_t count = 1;
  while (!stack.empty()) {
    const size_t p = stack.back();
    stack.pop_back();
    for (size_t q = 0; q < set.size(); ++q) {
      if (!reached[q] && Joined(set[p], set[q])) {
        reached[q] = true;
        ++count;
        stack.push_back(q);
      }
    }
  }
  return count == set.size();
}

bool Feasibility::IsFeasible(std::span<const uint32_t> set) const {
  for (size_t p = 0; p < set.size(); ++p) {
    for (size_t q = p + 1; q < set.size(); ++q) {
      if (set[p] == set[q] || InConflict(set[p], set[q])) return false;
    }
  }
  return !has_calibration_ || IsConnected(set);
}

bool Capacity::Fits(std::span<const uint32_t> set, uint32_t candidate, size_t replaced) const {
  const bool is_add = replaced >= set.size();
  if (!has_budget()) return set.size() + (is_add ? 1 : 0) <= n;
  double total = 0;
  for (size_t s = 0; s < set.size(); ++s) total += costs[s == replaced ? candidate : set[s]];
  if (is_add) total += costs[candidate];
  return total <= budget;
}

std::vector<uint32_t> BridgeKept(const Feasibility& feasible, std::span<const uint32_t> fixed) {
  std::vector<uint32_t> set(fixed.begin(), fixed.end());
  if (!feasible.has_calibration() || set.empty()) return set;
  const size_t m = feasible.candidate_count();
  std::vector<bool> banned(m, false);  // chain members that conflicted with an earlier one
  for (;;) {
    ThrowIfInterrupted();
    // The part of set[0]: a flood over the joined members of the set.
    std::vector<int> state(m, 0);  // 0 outside the set, 1 in the set, 2 in set[0]'s part
    for (const uint32_t s : set) state[s] = 1;
    std::vector<uint32_t> part{set[0]};
    state[set[0]] = 2;
    for (size_t p = 0; p < part.size(); ++p) {
      for (const uint32_t v : feasible.Neighbours(part[p])) {
        if (state[v] == 1) {
          state[v] = 2;
          part.push_back(v);
        }
      }
    }
    if (part.size() == set.size()) return set;
    // Breadth-first from the part, through candidates that conflict with nothing in the set,
    // to the first member of another part.
    std::vector<int64_t> parent(m, -1);
    std::vector<bool> visited(m, false);
    std::sort(part.begin(), part.end());
    std::vector<uint32_t> queue(part.begin(), part.end());
    for (const uint32_t p : part) visited[p] = true;
    int64_t reached_from = -1;
    for (size_t q = 0; q < queue.size() && reached_from < 0; ++q) {
      const uint32_t u = queue[q];
      for (const uint32_t v : feasible.Neighbours(u)) {
        if (state[v] == 1) {  // another part: the chain ends at u
          reached_from = u;
          break;
        }
        if (state[v] == 2 || visited[v] || banned[v]) continue;
        visited[v] = true;
        if (std::any_of(set.begin(), set.end(),
                        [&](uint32_t s) { return feasible.InConflict(s, v); }))
          continue;
        parent[v] = u;
        queue.push_back(v);
      }
    }
    if (reached_from < 0) return {};
    std::vector<uint32_t> chain;
    for (int64_t c = reached_from; state[static_cast<size_t>(c)] == 0; c = parent[static_cast<size_t>(c)])
      chain.push_back(static_cast<uint32_t>(c));
    std::reverse(chain.begin(), chain.end());
    // Chain members may conflict with each other: the later one is banned and the search redone.
    bool clash = false;
    for (size_t a = 0; a < chain.size() && !clash; ++a) {
      for (size_t b = a + 1; b < chain.size() && !clash; ++b) {
        if (feasible.InConflict(chain[a], chain[b])) {
          banned[chain[b]] = true;
          clash = true;
        }
      }
    }
    if (!clash) set.insert(set.end(), chain.begin(), chain.end());
  }
}

namespace {

// k-coverage and point counts (k >= 2; with the matrix's counts, min-points) under the
// constraints, one state or several: PointsGreedyComplete's rule (cells completed, then the seers
// or points added where still missing, each cell's share up to k) with the scorer's aggregate —
// the score with the cells each candidate completes, ties broken by the score of the points it
// adds where they are still missing, then the lower index.
std::vector<uint32_t> StatesThresholdGreedy(const StatesScorer& scorer,
                                            const Feasibility& feasible,
                                            const Capacity& capacity,
                                            std::vector<uint32_t> chosen) {
  const CoverageMatrix& matrix = scorer.matrix();
  CappedPoints points(matrix, scorer.k());
  for (const uint32_t c : chosen) points.Add(c);
  StateTally covered = scorer.Covered(chosen);
  using Score = StatesScorer::Score;
  while (chosen.size() < capacity.n) {
    ThrowIfInterrupted();
    int64_t best = -1;
    std::pair<Score, Score> best_rank;
    StateTally best_completed;
    for (uint32_t i = 0; i < matrix.candidate_count(); ++i) {
      if (!feasible.CanAdd(chosen, i) || !capacity.Fits(chosen, i)) continue;
      StateTally completed = scorer.Zero(), added = scorer.Zero();
      points.ForEachMissing(i, [&](uint32_t element, uint32_t more, bool completes) {
        if (completes) scorer.AddElement(element, &completed);
        for (uint32_t p = 0; p < more; ++p) scorer.AddElement(element, &added);
      });
      std::pair<Score, Score> rank{scorer.ScoreOf(covered + completed), scorer.ScoreOf(added)};
      if (best < 0 || best_rank < rank) {  // strict: ties keep the lower index
        best = i;
        best_rank = rank;
        best_completed = std::move(completed);
      }
    }
    if (best < 0) break;  // nothing fits any more
    chosen.push_back(static_cast<uint32_t>(best));
    covered += best_completed;
    points.Add(static_cast<uint32_t>(best));
  }
  return chosen;
}

}  // namespace

std::vector<uint32_t> StatesCostGreedy(const StatesScorer& scorer,
                                       const Feasibility& feasible,
                                       const Capacity& capacity,
                                       std::span<const double> costs,
                                       std::optional<double> goal,
                                       std::vector<uint32_t> chosen) {
  using Score = StatesScorer::Score;
  using Real = long double;  // a rise per cost: compared, never summed
  const CoverageMatrix& matrix = scorer.matrix();
  const bool has_kept = !chosen.empty();
  CappedPoints points(matrix, scorer.k());
  for (const uint32_t c : chosen) points.Add(c);
  StateTally covered = scorer.Covered(chosen);
  const auto cost_of = [&](uint32_t c) { return costs.empty() ? 1.0 : costs[c]; };
  // A candidate's step: the rise of the score, its ratio to the cost, the points it adds.
  struct Step {
    Score rise;
    Real primary_rate = 0, secondary_rate = 0;
    bool free_rise = false;
    Score added;
    StateTally completed;
  };
  const auto before = [](const Step& a, uint32_t ia, const Step& b, uint32_t ib) {
    if (a.free_rise != b.free_rise) return a.free_rise;
    if (!a.free_rise) {
      if (a.primary_rate != b.primary_rate) return a.primary_rate > b.primary_rate;
      if (a.secondary_rate != b.secondary_rate) return a.secondary_rate > b.secondary_rate;
    }
    if (!(a.rise == b.rise)) return b.rise < a.rise;
    if (!(a.added == b.added)) return b.added < a.added;
    return ia < ib;
  };
  while (chosen.size() < capacity.n) {
    if (goal && GoalReached(scorer.Fraction(covered), *goal)) break;
    ThrowIfInterrupted();
    const Score now = scorer.ScoreOf(covered);
    int64_t best = -1;
    Step best_step;
    for (uint32_t i = 0; i < matrix.candidate_count(); ++i) {
      if (std::find(chosen.begin(), chosen.end(), i) != chosen.end()) continue;
      if (!feasible.CanAdd(chosen, i) || !capacity.Fits(chosen, i)) continue;
      Step step;
      step.completed = scorer.Zero();
      StateTally added = scorer.Zero();
      points.ForEachMissing(i, [&](uint32_t element, uint32_t more, bool completes) {
        if (completes) scorer.AddElement(element, &step.completed);
        for (uint32_t p = 0; p < more; ++p) scorer.AddElement(element, &added);
      });
      const Score after = scorer.ScoreOf(covered + step.completed);
      step.rise = {after.primary - now.primary, after.secondary - now.secondary};
      step.added = scorer.ScoreOf(added);
      const bool rises = Score{} < step.rise;
      const double cost = cost_of(i);
      step.free_rise = cost == 0 && rises;
      if (cost > 0) {
        step.primary_rate = static_cast<Real>(step.rise.primary) / static_cast<Real>(cost);
        step.secondary_rate = static_cast<Real>(step.rise.secondary) / static_cast<Real>(cost);
      }
      if (best < 0 || before(step, i, best_step, static_cast<uint32_t>(best))) {
        best = i;
        best_step = std::move(step);
      }
    }
    // Nothing fits, or nothing adds anything (not even points towards a threshold).
    if (best < 0 || (!(Score{} < best_step.rise) && !(Score{} < best_step.added))) break;
    chosen.push_back(static_cast<uint32_t>(best));
    covered += best_step.completed;
    points.Add(static_cast<uint32_t>(best));
  }
  if (capacity.has_budget() && !goal && !has_kept) {
    // The best affordable single candidate, when it beats the greedy set.
    int64_t single = -1;
    Score single_score{};
    for (uint32_t i = 0; i < matrix.candidate_count(); ++i) {
      if (capacity.costs[i] > capacity.budget) continue;
      const Score score = scorer.ScoreOf(scorer.Covered(std::vector<uint32_t>{i}));
      if (single < 0 || single_score < score) {
        single = i;
        single_score = score;
      }
    }
    if (single >= 0 && (chosen.empty() || scorer.ScoreOf(covered) < single_score))
      return {static_cast<uint32_t>(single)};
  }
  return chosen;
}

std::vector<uint32_t> StatesRansacFitted(const StatesScorer& scorer,
                                         const Feasibility& feasible,
                                         const Capacity& capacity,
                                         std::span<const double> costs,
                                         std::optional<double> goal,
                                         int iterations,
                                         double stop_coverage,
                                         uint64_t seed,
                                         const std::vector<uint32_t>& start) {
  using Score = StatesScorer::Score;
  const size_t m = scorer.matrix().candidate_count();
  std::vector<uint32_t> order(m), drawn(m), best;
  std::iota(order.begin(), order.end(), 0U);
  Score best_score{};
  double best_cost = 0;
  for (int i = 0; i < iterations; ++i) {
    if (!goal && !best.empty() &&
        scorer.Fraction(scorer.Covered(best)) >= stop_coverage)
      break;
    if (i % 64 == 0) ThrowIfInterrupted();
    RansacDraw(seed, static_cast<uint64_t>(i), m, &order, &drawn);
    std::vector<uint32_t> set = start;
    for (const uint32_t c : drawn) {
      if (goal && GoalReached(scorer.Fraction(scorer.Covered(set)), *goal)) break;
      if (std::find(set.begin(), set.end(), c) != set.end()) continue;
      if (feasible.CanAdd(set, c) && capacity.Fits(set, c)) set.push_back(c);
    }
    if (!feasible.IsFeasible(set)) continue;  // a calibration rule's order may leave parts
    const StateTally tally = scorer.Covered(set);
    if (goal && !GoalReached(scorer.Fraction(tally), *goal)) continue;
    const Score score = scorer.ScoreOf(tally);
    const double cost = costs.empty() ? static_cast<double>(set.size()) : TotalCost(costs, set);
    const bool better = best.empty() || (goal ? cost < best_cost ||
                                                    (cost == best_cost && best_score < score)
                                              : best_score < score);
    if (better) {
      best = std::move(set);
      best_score = score;
      best_cost = cost;
    }
  }
  return best;
}

template <MethodScorer Scorer>
std::vector<uint32_t> ConstrainedGreedy(const Scorer& scorer,
                                        const Feasibility& feasible,
                                        const Capacity& capacity,
                                        uint64_t goal_cells,
                                        std::vector<uint32_t> start) {
  using Tally = typename Scorer::Tally;
  using Score = typename Scorer::Score;
  const CoverageMatrix& matrix = scorer.matrix();
  if constexpr (Scorer::kCells) {
    // The threshold and the cost greedies are the model's (the states' scorer): with the matrix
    // as its one state a unit is one cell, so they rank exactly as cells do.
    if (scorer.k() > 1 || capacity.has_budget()) {
      const StatesScorer one_state(matrix, OverStates::kMean, scorer.k());
      return ConstrainedGreedy(one_state, feasible, capacity, goal_cells, std::move(start));
    }
  } else {
    if (capacity.has_budget())
      return StatesCostGreedy(scorer, feasible, capacity, capacity.costs, std::nullopt,
                              std::move(start));
    if (scorer.k() > 1) return StatesThresholdGreedy(scorer, feasible, capacity, std::move(start));
  }
  std::vector<uint32_t> chosen = std::move(start);
  Bitset covered = matrix.EmptySet();
  Tally tally = scorer.Covered(chosen);
  for (const uint32_t c : chosen) matrix.AddTo(c, &covered);
  while (chosen.size() < capacity.n) {
    if constexpr (Scorer::kCells) {
      if (goal_cells > 0 && tally >= goal_cells) break;
    }
    ThrowIfInterrupted();
    int64_t best = -1;
    Score best_rank{};
    Tally best_gain = scorer.Zero();
    for (uint32_t c = 0; c < matrix.candidate_count(); ++c) {
      if (!feasible.CanAdd(chosen, c)) continue;
      Tally gain = scorer.Gain(c, covered);
      const Score rank = scorer.Rank(tally, gain);
      if (best < 0 || best_rank < rank) {
        best = c;
        best_rank = rank;
        best_gain = std::move(gain);
      }
    }
    if (best < 0) break;  // nothing fits any more
    if constexpr (Scorer::kCells) {
      if (goal_cells > 0 && best_gain == 0) break;  // the goal is out of greedy's reach
    }
    chosen.push_back(static_cast<uint32_t>(best));
    tally += best_gain;
    matrix.AddTo(static_cast<uint32_t>(best), &covered);
  }
  return chosen;
}

template <MethodScorer Scorer>
std::vector<uint32_t> ConstrainedLocal(const Scorer& scorer,
                                       const Feasibility& feasible,
                                       std::vector<uint32_t> chosen,
                                       const Capacity& capacity,
                                       size_t frozen) {
  using Tally = typename Scorer::Tally;
  using Score = typename Scorer::Score;
  const CoverageMatrix& matrix = scorer.matrix();
  VANTAGE_CHECK(feasible.IsFeasible(chosen) &&
                (capacity.has_budget() || chosen.size() <= capacity.n));
  const bool by_gain = scorer.k() == 1;  // else each trial is scored whole (k-coverage)
  Score current = scorer.ScoreOf(scorer.Covered(chosen));
  std::vector<uint32_t> trial;
  for (;;) {
    ThrowIfInterrupted();
    // The best move of this pass: position p replaced by c (p = size: c added).
    Score best = current;
    size_t best_p = 0;
    int64_t best_c = -1;
    for (size_t p = frozen; p <= chosen.size(); ++p) {
      const bool is_add = p == chosen.size();
      if (is_add && !capacity.has_budget() && chosen.size() >= capacity.n) break;
      std::vector<uint32_t> others = chosen;
      if (!is_add) others.erase(others.begin() + static_cast<std::ptrdiff_t>(p));
      Bitset covered = matrix.EmptySet();
      Tally base = scorer.Zero();
      if (by_gain) {
        base = scorer.Covered(others);
        for (const uint32_t o : others) matrix.AddTo(o, &covered);
      }
      for (uint32_t c = 0; c < matrix.candidate_count(); ++c) {
        if (std::find(chosen.begin(), chosen.end(), c) != chosen.end()) continue;
        Score score{};
        if (by_gain) {
          score = scorer.ScoreOf(base + scorer.Gain(c, covered));
          if (!(best < score)) continue;
          trial = others;
          trial.push_back(c);
        } else {
          trial = others;
          trial.push_back(c);
          score = scorer.ScoreOf(scorer.Covered(trial));
          if (!(best < score)) continue;
        }
        if (!capacity.Fits(chosen, c, p) || !feasible.IsFeasible(trial)) continue;
        best = score;
        best_p = p;
        best_c = c;
      }
    }
    if (best_c < 0) return chosen;
    if (best_p == chosen.size()) {
      chosen.push_back(static_cast<uint32_t>(best_c));
    } else {
      chosen[best_p] = static_cast<uint32_t>(best_c);
    }
    current = best;
  }
}

template <MethodScorer Scorer>
std::vector<uint32_t> ConstrainedRansac(const Scorer& scorer,
                                        const Feasibility& feasible,
                                        size_t n,
                                        int iterations,
                                        double stop_coverage,
                                        uint64_t seed,
                                        std::span<const uint32_t> fixed) {
  using Tally = typename Scorer::Tally;
  using Score = typename Scorer::Score;
  const size_t m = scorer.matrix().candidate_count();
  // The others, drawn from (their index in `others` maps to a candidate).
  std::vector<uint32_t> others;
  for (uint32_t c = 0; c < m; ++c)
    if (std::find(fixed.begin(), fixed.end(), c) == fixed.end()) others.push_back(c);
  const std::vector<uint32_t> kept(fixed.begin(), fixed.end());
  if (n <= kept.size()) return feasible.IsFeasible(kept) ? kept : std::vector<uint32_t>{};
  const size_t free_n = n - kept.size();
  std::vector<uint32_t> order(others.size());
  std::iota(order.begin(), order.end(), 0U);
  std::vector<uint32_t> best, drawn(free_n);
  Tally best_tally = scorer.Zero();
  Score best_score{};
  for (int i = 0; i < iterations; ++i) {
    if (!best.empty() && scorer.Fraction(best_tally) >= stop_coverage) break;
    if (i % 64 == 0) ThrowIfInterrupted();
    RansacDraw(seed, static_cast<uint64_t>(i), free_n, &order, &drawn);
    if (!kept.empty()) {
      for (uint32_t& d : drawn) d = others[d];
      drawn.insert(drawn.begin(), kept.begin(), kept.end());
    }
    if (!feasible.IsFeasible(drawn)) {  // rejected draw
      drawn.resize(free_n);
      continue;
    }
    Tally tally = scorer.Covered(drawn);
    const Score score = scorer.ScoreOf(tally);
    if (best.empty() || best_score < score) {
      best = drawn;
      best_tally = std::move(tally);
      best_score = score;
    }
    drawn.resize(free_n);
  }
  return best;
}

template std::vector<uint32_t> ConstrainedGreedy(
    const CellScorer&, const Feasibility&, const Capacity&, uint64_t, std::vector<uint32_t>);
template std::vector<uint32_t> ConstrainedGreedy(
    const StatesScorer&, const Feasibility&, const Capacity&, uint64_t, std::vector<uint32_t>);
template std::vector<uint32_t> ConstrainedLocal(
    const CellScorer&, const Feasibility&, std::vector<uint32_t>, const Capacity&, size_t);
template std::vector<uint32_t> ConstrainedLocal(
    const StatesScorer&, const Feasibility&, std::vector<uint32_t>, const Capacity&, size_t);
template std::vector<uint32_t> ConstrainedRansac(const CellScorer&,
                                                 const Feasibility&,
                                                 size_t,
                                                 int,
                                                 double,
                                                 uint64_t,
                                                 std::span<const uint32_t>);
template std::vector<uint32_t> ConstrainedRansac(const StatesScorer&,
                                                 const Feasibility&,
                                                 size_t,
                                                 int,
                                                 double,
                                                 uint64_t,
                                                 std::span<const uint32_t>);

// ----- the methods for one n -------------------------------------------------------------------

namespace {

// How the model values a scorer's cells: one state's (null), or its aggregation over the states.
template <MethodScorer Scorer>
const Aggregation* AggregationOf(const Scorer& scorer) {
  if constexpr (Scorer::kCells) {
    return nullptr;
  } else {
    return &scorer.aggregation();
  }
}

}  // namespace

template <MethodScorer Scorer>
ConstrainedMethods<Scorer>::ConstrainedMethods(const Scorer& scorer,
                                               const Feasibility& feasible,
                                               const SelectOptions& options,
                                               double setup_seconds,
                                               std::vector<uint32_t> start)
    : scorer_(scorer),
      feasible_(feasible),
      model_(ModelFor(options, scorer.matrix(), AggregationOf(scorer), 0, &feasible)),
      seed_(options.seed),
      ransac_stop_coverage_(options.ransac_stop_coverage),
      setup_seconds_(setup_seconds),
      start_(start.empty() ? options.fixed : std::move(start)) {
  VANTAGE_CHECK(!model_.goal && feasible_.IsFeasible(start_));  // a goal is GoalMethods'
}

template <MethodScorer Scorer>
Capacity ConstrainedMethods<Scorer>::CapacityFor(size_t n) const {
  Capacity capacity;
  capacity.n = n;
  if (HasBudget()) {
    capacity.n = scorer_.matrix().candidate_count();
    capacity.costs = model_.costs;
    capacity.budget = model_.capacity;
  }
  return capacity;
}

template <MethodScorer Scorer>
double ConstrainedMethods<Scorer>::Share(uint64_t cells) const {
  return static_cast<double>(cells) /
         static_cast<double>(std::max<size_t>(scorer_.matrix().reference_size(), 1));
}

template <MethodScorer Scorer>
bool ConstrainedMethods<Scorer>::IsFree() const {
  if (HasRules() || !start_.empty()) return false;
  return Scorer::kCells || (!HasBudget() && scorer_.k() == 1);
}

template <MethodScorer Scorer>
ConstrainedAnswer ConstrainedMethods<Scorer>::Ransac(size_t n, int iterations) const {
  const Clock::time_point start = Clock::now();
  ConstrainedAnswer answer;
  if constexpr (Scorer::kCells) {
    if (HasBudget()) {
      // No n to draw: each draw is a random order taken until the budget stops it (under the
      // rules, from the kept sensors); where no draw adds anything, greedy's answer.
      FittedDraws fit;
      fit.threshold = scorer_.k();
      fit.costs = model_.costs;
      fit.budget = model_.capacity;
      fit.start = start_;
      if (!IsFree()) {
        fit.may_add = [&](std::span<const uint32_t> set, uint32_t c) {
          return feasible_.CanAdd(set, c);
        };
      }
      answer.chosen = RansacFitted(scorer_.matrix(), fit, iterations,
                                   ransac_stop_coverage_, seed_);
      if (answer.chosen.empty()) {
        answer.chosen = IsFree() ? GreedyBudget(scorer_.matrix(), model_.costs, model_.capacity)
                                 : ConstrainedGreedy(scorer_, feasible_, CapacityFor(n), 0, start_);
      }
      answer.seconds = setup_seconds_ + SecondsSince(start);
      return answer;
    }
  }
  if (IsFree()) {
    answer.chosen =
        RansacChoice(scorer_, n, iterations, ransac_stop_coverage_, seed_);
    answer.seconds = setup_seconds_ + SecondsSince(start);
    return answer;
  }
  if constexpr (!Scorer::kCells) {
    if (HasBudget()) {
      answer.chosen = StatesRansacFitted(scorer_, feasible_, CapacityFor(n), model_.costs,
                                         std::nullopt, iterations,
                                         ransac_stop_coverage_, seed_, start_);
      answer.seconds = setup_seconds_ + SecondsSince(start);
      return answer;
    }
  }
  answer.chosen = ConstrainedRansac(scorer_, feasible_, n, iterations,
                                    ransac_stop_coverage_, seed_, model_.fixed);
  if (answer.chosen.empty()) {
    spdlog::warn(
        "ransac, n = {}: none of its {} draws satisfies the constraints; reporting the "
        "constrained greedy answer",
        n, iterations);
    answer.chosen = ConstrainedGreedy(scorer_, feasible_, CapacityFor(n), 0, start_);
  }
  answer.seconds = setup_seconds_ + SecondsSince(start);
  return answer;
}

template <MethodScorer Scorer>
ConstrainedAnswer ConstrainedMethods<Scorer>::Greedy(size_t n) {
  const Clock::time_point start = Clock::now();
  VANTAGE_CHECK(HasBudget() || n >= start_.size());
  n_ = n;
  if (!IsFree()) {
    greedy_ = ConstrainedGreedy(scorer_, feasible_, CapacityFor(n), 0, start_);
  } else if (HasBudget()) {
    if constexpr (Scorer::kCells)
      greedy_ = GreedyBudget(scorer_.matrix(), model_.costs, model_.capacity);
  } else if (scorer_.k() > 1 || scorer_.matrix().has_counts()) {
    // The threshold greedy (k-coverage; a count matrix makes it the min-points one).
    if constexpr (Scorer::kCells) greedy_ = KGreedyComplete(scorer_.matrix(), {}, n, scorer_.k());
  } else {
    greedy_ = GreedyComplete(scorer_, {}, n);
  }
  if (!HasBudget() && greedy_.size() < n) {
    if (greedy_.size() == 1) {
      spdlog::warn("greedy, n = {}: only 1 sensor satisfies the constraints", n);
    } else {
      spdlog::warn("greedy, n = {}: only {} sensors satisfy the constraints together", n,
                     greedy_.size());
    }
  }
  greedy_seconds_ = setup_seconds_ + SecondsSince(start);
  local_ = greedy_;
  local_seconds_ = greedy_seconds_;
  return {greedy_, greedy_seconds_, std::nullopt, false, {}};
}

template <MethodScorer Scorer>
ConstrainedAnswer ConstrainedMethods<Scorer>::Local() {
  const Clock::time_point start = Clock::now();
  const CoverageMatrix& matrix = scorer_.matrix();
  free_local_.clear();
  if (IsFree()) {
    if constexpr (Scorer::kCells) {
      LocalOptions local;
      if (HasBudget()) {
        local.costs = model_.costs;
        local.budget = model_.capacity;
      }
      local_ = matrix.has_counts()
                   ? PointsLocalSearch(matrix, greedy_, scorer_.k())
                   : LocalSearch(scorer_, greedy_, local);
    } else {
      // 1-swaps only over states: LocalSearch's 2-swaps reason in cells (CellScorer).
      local_ = LocalSearch(scorer_, greedy_);
    }
    local_seconds_ = greedy_seconds_ + SecondsSince(start);
    return {local_, local_seconds_, std::nullopt, false, {}};
  }
  local_ = ConstrainedLocal(scorer_, feasible_, greedy_, CapacityFor(n_), model_.fixed.size());
  if (!model_.fixed.empty()) {
    // The unconstrained answers need not hold the kept sensors: none.
  } else if (HasBudget()) {
    if constexpr (Scorer::kCells) {  // over states the constrained search is the only one
      LocalOptions local;
      local.costs = model_.costs;
      local.budget = model_.capacity;
      free_local_ = LocalSearch(CellScorer(matrix), GreedyBudget(matrix, model_.costs, local.budget),
                                local);
    }
  } else if (n_ <= matrix.candidate_count()) {
    if constexpr (Scorer::kCells) {
      const int k = scorer_.k();
      if (k == 1) {
        free_local_ = LocalSearch(scorer_, GreedyComplete(scorer_, {}, n_));
      } else if (matrix.has_counts()) {
        free_local_ = PointsLocalSearch(matrix, KGreedyComplete(matrix, {}, n_, k), k);
      } else if (n_ >= static_cast<size_t>(k)) {
        free_local_ = LocalSearch(scorer_, KGreedyComplete(matrix, {}, n_, k));
      }
    } else if (scorer_.k() == 1) {
      free_local_ = LocalSearch(scorer_, GreedyComplete(scorer_, {}, n_));
    }
  }
  if (!free_local_.empty() && feasible_.IsFeasible(free_local_) &&
      scorer_.ScoreOf(scorer_.Covered(local_)) < scorer_.ScoreOf(scorer_.Covered(free_local_)))
    local_ = free_local_;
  local_seconds_ = greedy_seconds_ + SecondsSince(start);
  return {local_, local_seconds_, std::nullopt, false, {}};
}

template <MethodScorer Scorer>
ConstrainedAnswer ConstrainedMethods<Scorer>::Exact(double time_limit) const {
  const Clock::time_point start = Clock::now();
  const CoverageMatrix& matrix = scorer_.matrix();
  ConstrainedAnswer answer;
  std::string note;
  const auto better_or_equal = [&](const std::vector<uint32_t>& a, const std::vector<uint32_t>& b) {
    return !(scorer_.ScoreOf(scorer_.Covered(a)) < scorer_.ScoreOf(scorer_.Covered(b)));
  };
  // The unconstrained optimum first (half the time), from the unconstrained local answer: when it
  // is feasible it is the constrained one, proof included; else its bound still bounds the
  // constrained optimum.
  const bool has_free = HasBudget() ? !free_local_.empty() : free_local_.size() == n_;
  const int k = scorer_.k();
  SelectionModel model = model_;
  if (!HasBudget()) model.capacity = static_cast<double>(n_);
  SelectionModel free_model = model;  // no rule, no kept sensor
  free_model.fixed = {};
  free_model.rules = nullptr;
  if (HasBudget()) free_model.threshold = 1;  // a budget counts cells seen once
  ExactAnswer exact;
  bool solved = false;
  ExactHints hints;  // cells under rules: the cheap bound of the unconstrained problem
  if (IsFree()) {  // the model is the free one: one solve, all the time, no hint
    exact = SolveExactModel(free_model, local_, time_limit);
    solved = true;
  } else if constexpr (Scorer::kCells) {
    hints.known_bound = static_cast<double>(
        HasBudget() ? BudgetUpperBound(matrix, local_, model_.costs, model_.capacity)
        : k == 1        ? GreedyUpperBound(matrix, local_, n_)
                        : KUpperBound(matrix, local_, n_, k));
  }
  if (!solved && has_free && n_ >= 1) {
    ExactAnswer free = SolveExactModel(free_model, free_local_, 0.5 * time_limit);
    if (feasible_.IsFeasible(free.chosen) && better_or_equal(free.chosen, local_)) {
      exact = std::move(free);
      solved = true;
    } else {
      hints.known_bound = std::min(hints.known_bound.value_or(free.bound), free.bound);
    }
  }
  if (!solved)
    exact = SolveExactModel(model, local_, std::max(0.1, time_limit - SecondsSince(start)), hints);
  note = exact.note;
  answer.chosen = std::move(exact.chosen);
  if constexpr (Scorer::kCells)
    answer.upper_bound = Share(static_cast<uint64_t>(exact.bound));
  else
    answer.upper_bound = exact.bound;
  answer.proven_optimal = exact.proven_optimal;
  // A budget has no n (n_ is then the candidate count): name the budget. "constrained" only
  // where there are constraints (kept sensors and thresholds run here without any).
  const std::string which =
      fmt::format("{}{}",
                  HasBudget() ? fmt::format("budget {:g}", model_.capacity)
                                  : fmt::format("n = {}", n_),
                  HasRules() ? " (constrained)" : "");
  const char* over_states = Scorer::kCells ? "" : " over states";
  if (!note.empty()) {
    answer.log = [what = fmt::format("exact{}, {}", over_states, which), note,
                  proven = answer.proven_optimal] {
      if (!proven) {
        spdlog::warn("{}: {}; reporting the best answer found and a bound", what, note);
      } else {
        spdlog::debug("{}: {}", what, note);
      }
    };
  }
  answer.seconds = local_seconds_ + SecondsSince(start);
  return answer;
}

template class ConstrainedMethods<CellScorer>;
template class ConstrainedMethods<StatesScorer>;

// ----- Select under the constraints ------------------------------------------------------------

namespace {

class CellsRun final : public MethodSteps<Selection> {
 public:
  CellsRun(const CoverageEvaluator& evaluator,
           const CoverageMatrix& matrix,
           const Feasibility& feasible,
           const SelectOptions& options,
           double setup_seconds,
           std::vector<uint32_t> start = {})
      : evaluator_(evaluator),
        matrix_(matrix),
        feasible_(feasible),
        options_(options),
        setup_seconds_(setup_seconds),
        kept_start_(start),
        scorer_(matrix, Threshold(options)),
        methods_(scorer_, feasible, options, setup_seconds, std::move(start)) {}

  Selection Best() override {
    if (options_.fixed.empty()) return SelectBest(evaluator_);
    if (std::optional<Selection> best = BestAddition()) return std::move(*best);
    throw InputError(fmt::format("--method best adds one sensor to the {} kept ones, and no one "
                                 "candidate joins their parts (the chain found takes {}) — use "
                                 "another method",
                                 options_.fixed.size(),
                                 kept_start_.size() - options_.fixed.size()));
  }
  /// Plain coverage: the best single candidate, or (kept sensors) the best single addition.
  std::optional<Selection> TableHead() override {
    if (!KindFor(options_).Applies(Method::kBest)) return std::nullopt;
    if (options_.fixed.empty()) return SelectBest(evaluator_);
    return BestAddition();
  }
  /// k-coverage from n = k; below the kept sensors and their chain no answer exists.
  size_t FirstN() const override {
    const auto k = static_cast<size_t>(KindFor(options_).k);
    return std::max({k, options_.fixed.size() + 1, kept_start_.size()});
  }
  Selection Ransac(size_t n, int iterations) override {
    return Scored(Method::kRansac, methods_.Ransac(n, iterations));
  }
  Selection Greedy(size_t n) override { return Scored(Method::kGreedy, methods_.Greedy(n)); }
  Selection Local() override { return Scored(Method::kLocal, methods_.Local()); }
  std::function<ExactDone<Selection>(double)> Exact() override {
    return [this, methods = methods_](double seconds) {
      ConstrainedAnswer answer = methods.Exact(seconds);
      std::function<void()> log = std::move(answer.log);
      return ExactDone<Selection>{Scored(Method::kExact, std::move(answer)), std::move(log)};
    };
  }
  /// Without rules and kept sensors, `all`'s n's share AllExactTime's lanes.
  bool ParallelExact() const override { return methods_.IsFree(); }

  Selection Scored(Method method, ConstrainedAnswer answer) const {
    VANTAGE_CHECK(feasible_.IsFeasible(answer.chosen));
    Selection s =
        ScoreSelection(evaluator_, std::move(answer.chosen), MethodName(method), options_);
    s.seconds = answer.seconds;
    if (answer.upper_bound) s.upper_bound = std::max(*answer.upper_bound, s.coverage);
    s.proven_optimal = answer.proven_optimal;
    if (s.budget) VANTAGE_CHECK(*s.cost <= *s.budget);
    return s;
  }

 private:
  // The best single addition to the kept sensors (optimal for that n): greedy's first step, or
  // with parts to join, the best of the candidates that join them all.
  std::optional<Selection> BestAddition() {
    const std::vector<uint32_t>& fixed = options_.fixed;
    Selection best;
    if (kept_start_.size() == fixed.size()) {
      best = Greedy(fixed.size() + 1);
    } else {
      std::vector<uint32_t> trial(fixed.begin(), fixed.end());
      trial.push_back(0);
      int64_t best_c = -1;
      uint64_t best_weight = 0;
      for (uint32_t c = 0; c < matrix_.candidate_count(); ++c) {
        trial.back() = c;
        if (!feasible_.IsFeasible(trial)) continue;
        const uint64_t weight = matrix_.CoveredWeight(trial);
        if (best_c < 0 || weight > best_weight) {
          best_c = c;
          best_weight = weight;
        }
      }
      if (best_c < 0) return std::nullopt;
      trial.back() = static_cast<uint32_t>(best_c);
      best = Scored(Method::kBest, {trial, setup_seconds_, std::nullopt, false, {}});
    }
    best.method = MethodName(Method::kBest);
    best.upper_bound = best.coverage;
    best.proven_optimal = true;
    return best;
  }

  const CoverageEvaluator& evaluator_;
  const CoverageMatrix& matrix_;
  const Feasibility& feasible_;
  const SelectOptions& options_;
  double setup_seconds_;
  std::vector<uint32_t> kept_start_;
  CellScorer scorer_;
  ConstrainedMethods<CellScorer> methods_;
};

}  // namespace

std::vector<uint32_t> KeptStart(const Feasibility& feasible, const SelectOptions& options) {
  const std::vector<uint32_t>& fixed = options.fixed;
  // Kept sensors: conflict-free and (with a calibration rule) connected among themselves, so
  // that every method only has to keep the others joined (docs/constraints.md).
  for (size_t p = 0; p < fixed.size(); ++p) {
    for (size_t q = p + 1; q < fixed.size(); ++q) {
      if (feasible.InConflict(fixed[p], fixed[q]))
        throw InputError(fmt::format("kept sensors {} and {} conflict — drop one of them from "
                                     "the scene, or the constraint",
                                     fixed[p], fixed[q]));
    }
  }
  std::vector<uint32_t> start = BridgeKept(feasible, fixed);
  if (!fixed.empty() && start.empty())
    throw InputError("the kept sensors are not connected by the calibration rule, and no chain "
                     "of candidates joins them");
  if (!fixed.empty() && options.budget && TotalCost(options.costs, start) > *options.budget)
    throw InputError(fmt::format("joining the kept sensors takes {} more sensors, over the "
                                 "budget {:g}",
                                 start.size() - fixed.size(), *options.budget));
  return start;
}

std::vector<Selection> SelectConstrained(std::span<const Observation> observations,
                                         size_t reference_size,
                                         const SelectOptions& options) {
  VANTAGE_CHECK(!options.goal);  // a goal under rules or with kept sensors: the one model's
  const CoverageEvaluator evaluator(observations, reference_size);
  const std::vector<uint32_t>& fixed = options.fixed;
  // One sensor alone breaks no constraint: best is the plain best single candidate.
  if (options.method == Method::kBest && fixed.empty()) return {SelectBest(evaluator)};
  const Clock::time_point start = Clock::now();
  const CoverageMatrix matrix = MatrixFor(observations, reference_size, options);
  const Feasibility feasible(observations, options.constraints);
  const double setup_seconds = SecondsSince(start);
  // Kept sensors that the calibration rule leaves in parts grow from the chain that joins them.
  const std::vector<uint32_t> kept_start = KeptStart(feasible, options);
  const bool is_bridged = kept_start.size() > fixed.size();
  if (!fixed.empty()) {
    // No room: n is the kept sensors, or no other candidate fits what the budget leaves.
    bool no_room = static_cast<size_t>(options.n) <= fixed.size();
    if (options.budget) {
      const double left = *options.budget - TotalCost(options.costs, fixed);
      no_room = true;
      for (uint32_t c = 0; c < observations.size() && no_room; ++c)
        no_room = std::find(fixed.begin(), fixed.end(), c) != fixed.end() || options.costs[c] > left;
    }
    if (!is_bridged && no_room) return {ScoreSelection(evaluator, fixed, "kept", options)};
    if (!options.budget && static_cast<size_t>(options.n) < kept_start.size() &&
        options.method != Method::kBest)
      throw InputError(fmt::format("n = {}: joining the {} kept sensors takes {} more sensors",
                                   options.n, fixed.size(), kept_start.size() - fixed.size()));
  }
  CellsRun run(evaluator, matrix, feasible, options, setup_seconds, kept_start);
  return RunMethods<Selection>(run, options, observations.size(), start);
}

std::vector<Selection> ConstrainedCurve(std::span<const Observation> observations,
                                        size_t reference_size,
                                        const SelectOptions& options,
                                        const std::vector<Selection>& results,
                                        int first_n,
                                        int last_n) {
  const int k = KindFor(options).k;
  const auto has = [&](const std::string& method, int n) {
    return std::any_of(results.begin(), results.end(), [&](const Selection& s) {
      return s.method == method && s.n == n && s.k == k;
    });
  };
  const CoverageEvaluator evaluator(observations, reference_size);
  const CoverageMatrix matrix = MatrixFor(observations, reference_size, options);
  const Feasibility feasible(observations, options.constraints);
  const std::vector<uint32_t> start = BridgeKept(feasible, options.fixed);
  if (start.empty() && !options.fixed.empty()) return {};  // Select refused these kept sensors
  CellsRun run(evaluator, matrix, feasible, options, 0, start);
  const std::string greedy = MethodName(Method::kGreedy), local = MethodName(Method::kLocal);
  std::vector<Selection> curve;
  // With kept sensors every point of the curve holds them, and the chain that joins them.
  first_n = std::max({first_n, static_cast<int>(options.fixed.size()) + 1,
                      static_cast<int>(start.size())});
  for (int n = first_n; n <= last_n; ++n) {
    const bool want_greedy = !has(greedy, n), want_local = !has(local, n);
    if (!want_greedy && !want_local) continue;
    Selection g = run.Greedy(static_cast<size_t>(n));
    if (want_greedy) curve.push_back(std::move(g));
    if (want_local) curve.push_back(run.Local());
  }
  return curve;
}

}  // namespace vantage::detail

namespace vantage {

std::vector<uint32_t> ConnectKept(std::span<const Observation> observations,
                                  std::span<const uint32_t> kept,
                                  const InstallConstraints& constraints) {
  return detail::BridgeKept(detail::Feasibility(observations, constraints), kept);
}

}  // namespace vantage
