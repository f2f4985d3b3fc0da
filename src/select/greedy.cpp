// Best single candidate, the greedy methods of every objective and their cheap bounds
// (SYSTEM.md, Select).
#include <algorithm>
#include <cmath>
#include <functional>
#include <limits>
#include <queue>

#include "select/methods.hpp"
#include "vantage/error.hpp"
#include "vantage/interrupt.hpp"

namespace vantage::detail {
namespace {

// Lazy greedy (Minoux) from `chosen`: adds the candidate that ranks highest until n sensors are
// chosen, or done(covered tally) holds, or nothing adds anything. With a lazy scorer ranks only
// shrink as the cover grows (submodularity), so a rank computed in an earlier round is an upper
// bound: an entry whose rank is fresh (computed this round) and on top of the heap is the true
// maximum, and the heap's order (rank, then lower index first) makes it the lowest-index maximum,
// as plain greedy would choose. Otherwise stale entries go first, so every rank is fresh before
// one is chosen: each round then ranks every candidate, as plain greedy does.
template <class Scorer, class Done>
std::vector<uint32_t> LazyGreedy(const Scorer& scorer,
                                 std::vector<uint32_t> chosen,
                                 size_t n,
                                 const Done& done) {
  using Score = typename Scorer::Score;
  const CoverageMatrix& matrix = scorer.matrix();
  const size_t m = matrix.candidate_count();
  std::vector<bool> is_chosen(m, false);
  Bitset covered = matrix.EmptySet();
  typename Scorer::Tally covered_tally = scorer.Zero();
  for (const uint32_t c : chosen) {
    VANTAGE_CHECK(c < m && !is_chosen[c]);
    is_chosen[c] = true;
    covered_tally += scorer.Gain(c, covered);
    matrix.AddTo(c, &covered);
  }
  struct Entry {
    Score rank;
    uint32_t candidate;
    size_t round;
  };
  const bool lazy = scorer.lazy();
  const auto lower_priority = [lazy](const Entry& a, const Entry& b) {
    if (!lazy && a.round != b.round) return a.round > b.round;
    return a.rank != b.rank ? a.rank < b.rank : a.candidate > b.candidate;
  };
  std::vector<Entry> entries;
  entries.reserve(m);
  size_t round = chosen.size();
  for (uint32_t i = 0; i < m; ++i) {
    if (is_chosen[i]) continue;
    entries.push_back(
        {scorer.Rank(covered_tally, chosen.empty() ? scorer.RowWeight(i) : scorer.Gain(i, covered)),
         i, round});
  }
  std::priority_queue<Entry, std::vector<Entry>, decltype(lower_priority)> heap(lower_priority,
                                                                                std::move(entries));
  Score nothing = scorer.Rank(covered_tally, scorer.Zero());  // the rank of adding nothing
  while (chosen.size() < n && !done(covered_tally) && !heap.empty()) {
    Entry top = heap.top();
    heap.pop();
    if (top.round == round) {
      if (top.rank == nothing) break;  // nothing adds anything any more
      chosen.push_back(top.candidate);
      is_chosen[top.candidate] = true;
      covered_tally += scorer.Gain(top.candidate, covered);
      matrix.AddTo(top.candidate, &covered);
      nothing = scorer.Rank(covered_tally, scorer.Zero());
      ++round;
    } else {
      top.rank = scorer.Rank(covered_tally, scorer.Gain(top.candidate, covered));
      top.round = round;
      heap.push(top);
    }
  }
  return chosen;
}

// Appends the lowest-index candidates not in `chosen` until it has n.
void FillByIndex(size_t candidate_count, size_t n, std::vector<uint32_t>* chosen) {
  std::vector<bool> is_chosen(candidate_count, false);
  for (const uint32_t c : *chosen) is_chosen[c] = true;
  for (uint32_t i = 0; i < candidate_count && chosen->size() < n; ++i) {
    if (!is_chosen[i]) chosen->push_back(i);
  }
}

}  // namespace

template <MethodScorer Scorer>
uint32_t BestCandidate(const Scorer& scorer) {
  const size_t m = scorer.matrix().candidate_count();
  VANTAGE_CHECK(m > 0);
  uint32_t best = 0;
  typename Scorer::Score best_score = scorer.ScoreOf(scorer.RowWeight(0));
  for (uint32_t i = 1; i < m; ++i) {
    const typename Scorer::Score score = scorer.ScoreOf(scorer.RowWeight(i));
    if (best_score < score) {  // strict: ties keep the lower
      best = i;
      best_score = score;
    }
  }
  return best;
}

double TotalCost(std::span<const double> costs, std::span<const uint32_t> chosen) {
  double total = 0;
  for (const uint32_t c : chosen) total += costs[c];
  return total;
}

uint64_t KCoveredWeight(const CoverageMatrix& matrix, std::span<const uint32_t> chosen, int k) {
  VANTAGE_CHECK(k >= 1);
  if (k == 1) return matrix.CoveredWeight(chosen);
  std::vector<uint32_t> count(matrix.element_count(), 0);
  uint64_t weight = 0;
  const auto kk = static_cast<uint32_t>(k);
  for (const uint32_t c : chosen) {
    const std::vector<uint32_t>& row = matrix.Row(c);
    for (size_t j = 0; j < row.size(); ++j) {
      const uint32_t e = row[j];
      const uint32_t before = count[e];
      count[e] += matrix.Count(c, j);  // 1, or the capped points (min-points)
      if (before < kk && count[e] >= kk) weight += matrix.Weight(e);
    }
  }
  return weight;
}

template <MethodScorer Scorer>
std::vector<uint32_t> GreedyComplete(const Scorer& scorer, std::vector<uint32_t> chosen, size_t n) {
  const size_t m = scorer.matrix().candidate_count();
  VANTAGE_CHECK(scorer.k() == 1 && n <= m && chosen.size() <= n);
  chosen = LazyGreedy(scorer, std::move(chosen), n, [](const auto&) { return false; });
  FillByIndex(m, n, &chosen);
  return chosen;
}

template uint32_t BestCandidate(const CellScorer&);
template uint32_t BestCandidate(const StatesScorer&);
template std::vector<uint32_t> GreedyComplete(const CellScorer&, std::vector<uint32_t>, size_t);
template std::vector<uint32_t> GreedyComplete(const StatesScorer&, std::vector<uint32_t>, size_t);

std::vector<uint32_t> GreedyToGoal(const CoverageMatrix& matrix, uint64_t goal_cells) {
  VANTAGE_CHECK(goal_cells >= 1 && goal_cells <= matrix.seen_weight());
  std::vector<uint32_t> chosen = LazyGreedy(CellScorer(matrix), {}, matrix.candidate_count(),
                                            [&](uint64_t cells) { return cells >= goal_cells; });
  VANTAGE_CHECK(matrix.CoveredWeight(chosen) >= goal_cells);
  return chosen;
}

std::vector<uint32_t> GreedyToGoal(const CoverageMatrix& matrix, uint64_t goal_cells, int k,
                                   std::span<const double> costs) {
  const size_t m = matrix.candidate_count();
  VANTAGE_CHECK(k >= 1 && goal_cells >= 1 && (costs.empty() || costs.size() == m));
  if (k == 1 && costs.empty() && !matrix.has_counts()) return GreedyToGoal(matrix, goal_cells);
  CappedPoints points(matrix, k);
  std::vector<bool> is_chosen(m, false);
  std::vector<uint32_t> chosen;
  uint64_t reached = 0;
  const auto cost = [&](uint32_t i) { return costs.empty() ? 1.0 : costs[i]; };
  // Each step: the most cells completed per cost, ties by the most points added where missing
  // per cost, then the lower index (zero cost: before any priced candidate that adds as much).
  const auto better = [&](std::pair<uint64_t, uint64_t> a, double cost_a,
                          std::pair<uint64_t, uint64_t> b, double cost_b) {
    const auto ratio = [](uint64_t gain, double c) {
      return c > 0 ? static_cast<double>(gain) / c
                   : (gain > 0 ? std::numeric_limits<double>::infinity() : 0.0);
    };
    if (ratio(a.first, cost_a) != ratio(b.first, cost_b))
      return ratio(a.first, cost_a) > ratio(b.first, cost_b);
    return ratio(a.second, cost_a) > ratio(b.second, cost_b);
  };
  while (reached < goal_cells) {
    ThrowIfInterrupted();
    int64_t best = -1;
    std::pair<uint64_t, uint64_t> best_gain{0, 0};
    for (uint32_t i = 0; i < m; ++i) {
      if (is_chosen[i]) continue;
      const std::pair<uint64_t, uint64_t> gain = points.Gain(i);
      if (gain.second == 0) continue;
      if (best < 0 || better(gain, cost(i), best_gain, cost(static_cast<uint32_t>(best)))) {
        best = i;
        best_gain = gain;
      }
    }
    VANTAGE_CHECK(best >= 0);  // the caller checked that all candidates reach the goal
    is_chosen[best] = true;
    chosen.push_back(static_cast<uint32_t>(best));
    points.Add(static_cast<uint32_t>(best));
    reached += best_gain.first;
  }
  // Drop what the goal no longer needs, the dearest (then the latest) first.
  std::vector<uint32_t> order = chosen;
  std::stable_sort(order.begin(), order.end(),
                   [&](uint32_t a, uint32_t b) { return cost(a) > cost(b); });
  for (const uint32_t drop : order) {
    std::vector<uint32_t> without;
    for (const uint32_t c : chosen)
      if (c != drop) without.push_back(c);
    if (!without.empty() && KCoveredWeight(matrix, without, k) >= goal_cells)
      chosen = std::move(without);
  }
  VANTAGE_CHECK(KCoveredWeight(matrix, chosen, k) >= goal_cells);
  return chosen;
}

std::vector<uint32_t> PointsGreedyComplete(const CoverageMatrix& matrix,
                                           std::vector<uint32_t> chosen, size_t n, int k) {
  const size_t m = matrix.candidate_count();
  VANTAGE_CHECK(k >= 1 && n <= m && chosen.size() <= n);
  CappedPoints points(matrix, k);
  std::vector<bool> is_chosen(m, false);
  const auto add = [&](uint32_t candidate) {
    VANTAGE_CHECK(candidate < m && !is_chosen[candidate]);
    is_chosen[candidate] = true;
    points.Add(candidate);
  };
  for (const uint32_t c : chosen) add(c);
  while (chosen.size() < n) {
    ThrowIfInterrupted();
    int64_t best = -1;
    std::pair<uint64_t, uint64_t> best_gain{0, 0};  // (cells completed, points added)
    for (uint32_t i = 0; i < m; ++i) {
      if (is_chosen[i]) continue;
      const std::pair<uint64_t, uint64_t> gain = points.Gain(i);
      if (best < 0 || best_gain < gain) {  // strict: ties keep the lower index
        best = i;
        best_gain = gain;
      }
    }
    if (best < 0 || best_gain.second == 0) break;  // nothing adds anything: fill by index
    chosen.push_back(static_cast<uint32_t>(best));
    add(static_cast<uint32_t>(best));
  }
  FillByIndex(m, n, &chosen);
  return chosen;
}

std::vector<uint32_t> KGreedyComplete(const CoverageMatrix& matrix,
                                      std::vector<uint32_t> chosen,
                                      size_t n,
                                      int k) {
  if (matrix.has_counts()) return PointsGreedyComplete(matrix, std::move(chosen), n, k);
  const size_t m = matrix.candidate_count();
  VANTAGE_CHECK(k >= 1 && n <= m && chosen.size() <= n);
  const auto levels = static_cast<size_t>(k);
  // level[c]: the elements that exactly c chosen sensors see, for c < k.
  std::vector<uint32_t> count(matrix.element_count(), 0);
  std::vector<Bitset> level(levels, matrix.EmptySet());
  for (uint32_t e = 0; e < matrix.element_count(); ++e) level[0][e >> 6] |= uint64_t{1} << (e & 63);
  std::vector<bool> is_chosen(m, false);
  const auto add = [&](uint32_t candidate) {
    VANTAGE_CHECK(candidate < m && !is_chosen[candidate]);
    is_chosen[candidate] = true;
    for (const uint32_t e : matrix.Row(candidate)) {
      const uint32_t c = count[e]++;
      if (c >= levels) continue;
      level[c][e >> 6] &= ~(uint64_t{1} << (e & 63));
      if (c + 1 < levels) level[c + 1][e >> 6] |= uint64_t{1} << (e & 63);
    }
  };
  for (const uint32_t c : chosen) add(c);
  std::vector<uint64_t> gains(levels), best_gains(levels);
  while (chosen.size() < n) {
    ThrowIfInterrupted();
    int64_t best = -1;
    for (uint32_t i = 0; i < m; ++i) {
      if (is_chosen[i]) continue;
      // Gains from the top level down; stop as soon as this candidate is already behind.
      bool is_better = best < 0;
      bool is_decided = best < 0;
      for (size_t l = levels; l-- > 0;) {
        gains[l] = matrix.WeightIn(i, level[l]);
        if (!is_decided && gains[l] != best_gains[l]) {
          is_better = gains[l] > best_gains[l];
          is_decided = true;
          if (!is_better) break;
        }
      }
      if (is_better) {
        best = i;
        best_gains = gains;
      }
    }
    if (best < 0 ||
        std::all_of(best_gains.begin(), best_gains.end(), [](uint64_t g) { return g == 0; })) {
      break;  // nothing adds anything at any level: fill by index
    }
    chosen.push_back(static_cast<uint32_t>(best));
    add(static_cast<uint32_t>(best));
  }
  FillByIndex(m, n, &chosen);
  return chosen;
}

std::vector<uint32_t> GreedyBudget(const CoverageMatrix& matrix,
                                   std::span<const double> costs,
                                   double budget) {
  const size_t m = matrix.candidate_count();
  VANTAGE_CHECK(costs.size() == m);
  // Single best affordable candidate (ties: lower index).
  int64_t single = -1;
  for (uint32_t i = 0; i < m; ++i) {
    if (costs[i] <= budget && (single < 0 || matrix.RowWeight(i) > matrix.RowWeight(single)))
      single = i;
  }
  VANTAGE_CHECK(single >= 0);

  // Lazy greedy on gain / cost: gains only shrink, and the remaining budget only shrinks, so a
  // stale ratio is an upper bound and a candidate that no longer fits never fits again.
  struct Entry {
    uint64_t gain;
    uint32_t candidate;
    size_t round;
  };
  // a before b: higher gain/cost (cross-multiplied; cost 0 is an infinite ratio), then higher
  // gain, then lower index.
  const auto lower_priority = [&](const Entry& a, const Entry& b) {
    const double ca = costs[a.candidate], cb = costs[b.candidate];
    const double ra = static_cast<double>(a.gain) * cb, rb = static_cast<double>(b.gain) * ca;
    const bool a_free = ca == 0 && a.gain > 0, b_free = cb == 0 && b.gain > 0;
    if (a_free != b_free) return b_free;
    if (!a_free && ra != rb) return ra < rb;
    if (a.gain != b.gain) return a.gain < b.gain;
    return a.candidate > b.candidate;
  };
  std::vector<Entry> entries;
  for (uint32_t i = 0; i < m; ++i) {
    if (costs[i] <= budget) entries.push_back({matrix.RowWeight(i), i, 0});
  }
  std::priority_queue<Entry, std::vector<Entry>, decltype(lower_priority)> heap(lower_priority,
                                                                                std::move(entries));
  std::vector<uint32_t> chosen;
  Bitset covered = matrix.EmptySet();
  double spent = 0;
  size_t round = 0;
  while (!heap.empty()) {
    Entry top = heap.top();
    heap.pop();
    if (spent + costs[top.candidate] > budget) continue;  // does not fit now, nor later
    if (top.round == round) {
      if (top.gain == 0) break;  // the best ratio adds nothing: nothing does
      chosen.push_back(top.candidate);
      spent += costs[top.candidate];
      matrix.AddTo(top.candidate, &covered);
      ++round;
    } else {
      top.gain = matrix.Gain(top.candidate, covered);
      top.round = round;
      heap.push(top);
    }
  }
  if (chosen.empty() || matrix.RowWeight(static_cast<uint32_t>(single)) > matrix.SetWeight(covered))
    return {static_cast<uint32_t>(single)};
  return chosen;
}

uint64_t SimpleUpperBound(const CoverageMatrix& matrix,
                          std::span<const uint32_t> chosen,
                          size_t n) {
  // f(OPT) <= f(S) + sum over OPT \ S of gain(j | S) <= f(S) + the n largest gains (submodular).
  Bitset covered = matrix.EmptySet();
  for (const uint32_t c : chosen) matrix.AddTo(c, &covered);
  const uint64_t base = matrix.SetWeight(covered);
  std::vector<uint64_t> gains(matrix.candidate_count());
  for (uint32_t i = 0; i < matrix.candidate_count(); ++i) gains[i] = matrix.Gain(i, covered);
  const size_t k = std::min(n, gains.size());
  std::partial_sort(gains.begin(), gains.begin() + static_cast<std::ptrdiff_t>(k), gains.end(),
                    std::greater<>());
  uint64_t bound = base;
  for (size_t i = 0; i < k; ++i) bound += gains[i];
  return std::min(bound, matrix.seen_weight());
}

uint64_t GreedyUpperBound(const CoverageMatrix& matrix,
                          std::span<const uint32_t> chosen,
                          size_t n) {
  // SimpleUpperBound holds over any set S; the best S is often a short greedy prefix (for S = {}
  // it is the sum of the n largest rows), rarely the final answer (Leskovec et al. 2007).
  uint64_t bound = SimpleUpperBound(matrix, chosen, n);
  const std::vector<uint32_t> greedy = GreedyComplete(CellScorer(matrix), {}, n);
  for (size_t j = 0; j <= greedy.size(); ++j) {
    bound = std::min(bound, SimpleUpperBound(matrix, std::span(greedy).first(j), n));
  }
  return bound;
}

namespace {

uint64_t KnapsackBound(const CoverageMatrix& matrix,
                       std::span<const uint32_t> chosen,
                       std::span<const double> costs,
                       double budget) {
  // f(OPT) <= f(S) + sum over OPT \ S of gain(j | S), and OPT's costs add up to at most the
  // budget: so at most f(S) + the fractional knapsack of the gains (an LP bound, rounded down
  // because cells are whole).
  const size_t m = matrix.candidate_count();
  VANTAGE_CHECK(costs.size() == m);
  Bitset covered = matrix.EmptySet();
  for (const uint32_t c : chosen) matrix.AddTo(c, &covered);
  const uint64_t base = matrix.SetWeight(covered);
  Bitset affordable = matrix.EmptySet();
  std::vector<uint32_t> order;
  std::vector<uint64_t> gains(m, 0);
  double free_gain = 0;
  for (uint32_t i = 0; i < m; ++i) {
    if (costs[i] > budget) continue;
    matrix.AddTo(i, &affordable);
    gains[i] = matrix.Gain(i, covered);
    if (gains[i] == 0) continue;
    if (costs[i] == 0) {
      free_gain += static_cast<double>(gains[i]);
    } else {
      order.push_back(i);
    }
  }
  std::sort(order.begin(), order.end(), [&](uint32_t a, uint32_t b) {
    const double ra = static_cast<double>(gains[a]) * costs[b];
    const double rb = static_cast<double>(gains[b]) * costs[a];
    return ra != rb ? ra > rb : a < b;
  });
  double bound = static_cast<double>(base) + free_gain;
  double left = budget;
  for (const uint32_t i : order) {
    if (left <= 0) break;
    const double share = std::min(1.0, left / costs[i]);
    bound += share * static_cast<double>(gains[i]);
    left -= costs[i];
  }
  // Candidates that cannot be afforded alone are in no feasible answer.
  const uint64_t reachable = matrix.SetWeight(affordable);
  const double rounded = std::floor(bound + 1e-6);
  return rounded >= static_cast<double>(reachable) ? reachable : static_cast<uint64_t>(rounded);
}

}  // namespace

uint64_t BudgetUpperBound(const CoverageMatrix& matrix,
                          std::span<const uint32_t> chosen,
                          std::span<const double> costs,
                          double budget) {
  // Over `chosen` and over the empty set (the fractional knapsack of the rows themselves).
  return std::min(KnapsackBound(matrix, chosen, costs, budget),
                  KnapsackBound(matrix, {}, costs, budget));
}

uint64_t KUpperBound(const CoverageMatrix& matrix,
                     std::span<const uint32_t> chosen,
                     size_t n,
                     int k) {
  // A cell seen by k of the chosen is seen by one of them: the 1-coverage bound holds.
  std::vector<uint32_t> seers(matrix.element_count(), 0);
  for (uint32_t i = 0; i < matrix.candidate_count(); ++i) {
    const std::vector<uint32_t>& row = matrix.Row(i);
    for (size_t j = 0; j < row.size(); ++j) seers[row[j]] += matrix.Count(i, j);
  }
  uint64_t seen_by_k = 0;
  for (uint32_t e = 0; e < matrix.element_count(); ++e) {
    if (seers[e] >= static_cast<uint32_t>(k)) seen_by_k += matrix.Weight(e);
  }
  return std::min(seen_by_k, GreedyUpperBound(matrix, chosen, n));
}

size_t SetCoverLowerBound(const CoverageMatrix& matrix, uint64_t goal_cells) {
  // t sensors cover at most the sum of their row sizes, so at most the t largest rows' sum.
  std::vector<uint64_t> sizes(matrix.candidate_count());
  for (uint32_t i = 0; i < matrix.candidate_count(); ++i) sizes[i] = matrix.RowWeight(i);
  std::sort(sizes.begin(), sizes.end(), std::greater<>());
  uint64_t sum = 0;
  for (size_t t = 0; t < sizes.size(); ++t) {
    sum += sizes[t];
    if (sum >= goal_cells) return t + 1;
  }
  return sizes.size();
}

size_t ThresholdGoalLowerBound(const CoverageMatrix& matrix, uint64_t goal_cells, int k) {
  // Each cell the goal counts needs k points, and a sensor adds at most min(count, k) to each.
  std::vector<uint64_t> points(matrix.candidate_count(), 0);
  for (uint32_t i = 0; i < matrix.candidate_count(); ++i) {
    const std::vector<uint32_t>& row = matrix.Row(i);
    for (size_t j = 0; j < row.size(); ++j)
      points[i] += uint64_t{matrix.Weight(row[j])} *
                   std::min<uint64_t>(matrix.Count(i, j), static_cast<uint64_t>(k));
  }
  std::sort(points.begin(), points.end(), std::greater<>());
  const uint64_t needed = goal_cells * static_cast<uint64_t>(k);
  uint64_t sum = 0;
  for (size_t t = 0; t < points.size(); ++t) {
    sum += points[t];
    if (sum >= needed) return t + 1;
  }
  return points.size();
}

}  // namespace vantage::detail
