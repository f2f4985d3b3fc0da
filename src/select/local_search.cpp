// Swap local search after greedy (SYSTEM.md, Select: `local`), for plain coverage, k-coverage, a
// cost budget and the states of a scene (whatever the scorer scores); 2-swaps where they stay
// cheap.
#include <algorithm>
#include <utility>

#include "select/methods.hpp"
#include "vantage/error.hpp"
#include "vantage/interrupt.hpp"

namespace vantage::detail {
namespace {

// Work cap of the 2-swap passes of one LocalSearch call, in bitset words touched (about 0.1-0.3 s
// at a few words per ns): beyond it the current pass stops with the best swap found so far and no
// further pass starts. Counted, not timed, so the answer does not depend on the machine.
constexpr uint64_t kMaxTwoSwapWords = uint64_t{600} << 20;

void SetBit(Bitset* set, uint32_t e) { (*set)[e >> 6] |= uint64_t{1} << (e & 63); }
void ClearBit(Bitset* set, uint32_t e) { (*set)[e >> 6] &= ~(uint64_t{1} << (e & 63)); }

struct TwoSwap {
  int64_t delta = 0;
  size_t p = 0, q = 0;    // positions out
  uint32_t x = 0, y = 0;  // candidates in (x to p, y to q)
};

// The best 2-swap for plain coverage (k = 1): two chosen out, two unused in. For each pair out,
// the freed cells F are those nobody else chosen sees; a newcomer j brings a_j = |row j ∩ F| and a
// pair brings a_x + |row y ∩ F \ row x| <= a_x + a_y, so pairs are tried in decreasing a and cut
// off once a_x + a_y cannot beat the best. Ties: earlier positions, then larger a, lower index.
TwoSwap BestTwoSwap(const CoverageMatrix& matrix,
                    const std::vector<uint32_t>& chosen,
                    const std::vector<bool>& is_chosen,
                    const std::vector<uint32_t>& cover_count,
                    uint64_t* words_left) {
  TwoSwap best;
  const size_t m = matrix.candidate_count();
  const size_t n = chosen.size();
  const uint64_t words = std::max<size_t>(matrix.word_count(), 1);
  Bitset uncovered(matrix.word_count(), ~uint64_t{0});
  for (const uint32_t c : chosen) {
    for (const uint32_t e : matrix.Row(c)) ClearBit(&uncovered, e);
  }
  Bitset freed, rest;
  std::vector<uint32_t> removed(matrix.element_count(), 0);
  std::vector<uint64_t> bring(m, 0);
  std::vector<uint32_t> order;
  for (size_t p = 0; p < n; ++p) {
    for (size_t q = p + 1; q < n; ++q) {
      if (*words_left < words * (m + 2)) return best;
      *words_left -= words * (m + 2);
      const uint32_t a = chosen[p], b = chosen[q];
      freed = uncovered;
      int64_t loss = 0;
      // Cells whose every chosen seer is a or b become uncovered.
      for (const uint32_t c : {a, b}) {
        for (const uint32_t e : matrix.Row(c)) ++removed[e];
      }
      for (const uint32_t c : {a, b}) {
        for (const uint32_t e : matrix.Row(c)) {
          if (removed[e] == 0) continue;  // done at its first occurrence
          if (cover_count[e] == removed[e]) {
            SetBit(&freed, e);
            loss += matrix.Weight(e);
          }
          removed[e] = 0;
        }
      }
      order.clear();
      for (uint32_t j = 0; j < m; ++j) {
        if (is_chosen[j]) continue;
        bring[j] = matrix.WeightIn(j, freed);
        if (bring[j] > 0) order.push_back(j);
      }
      std::sort(order.begin(), order.end(), [&](uint32_t u, uint32_t v) {
        return bring[u] != bring[v] ? bring[u] > bring[v] : u < v;
      });
      for (size_t s = 0; s + 1 < order.size(); ++s) {
        const uint32_t x = order[s];
        const auto need = loss + best.delta;  // a pair must bring more than this
        if (static_cast<int64_t>(bring[x] + bring[order[s + 1]]) <= need) break;
        rest = freed;
        for (const uint32_t e : matrix.Row(x)) ClearBit(&rest, e);
        for (size_t t = s + 1; t < order.size(); ++t) {
          const uint32_t y = order[t];
          if (static_cast<int64_t>(bring[x] + bring[y]) <= loss + best.delta) break;
          if (*words_left < words) return best;
          *words_left -= words;
          const int64_t delta = static_cast<int64_t>(bring[x] + matrix.WeightIn(y, rest)) - loss;
          if (delta > best.delta) best = {delta, p, q, x, y};
        }
      }
    }
  }
  return best;
}

}  // namespace

template <MethodScorer Scorer>
std::vector<uint32_t> LocalSearch(const Scorer& scorer,
                                  std::vector<uint32_t> chosen,
                                  const LocalOptions& options) {
  using Tally = typename Scorer::Tally;
  using Score = typename Scorer::Score;
  const CoverageMatrix& matrix = scorer.matrix();
  const size_t m = matrix.candidate_count();
  const size_t n = chosen.size();
  const bool has_budget = !options.costs.empty();
  VANTAGE_CHECK(scorer.k() >= 1 && (!has_budget || options.costs.size() == m));
  if (n == 0 || n >= m) return chosen;
  const auto k = static_cast<uint32_t>(scorer.k());
  std::vector<bool> is_chosen(m, false);
  // How many chosen candidates see each element: removing one lowers the counts of its row.
  std::vector<uint32_t> cover_count(matrix.element_count(), 0);
  for (const uint32_t c : chosen) {
    VANTAGE_CHECK(c < m && !is_chosen[c]);
    is_chosen[c] = true;
    for (const uint32_t e : matrix.Row(c)) ++cover_count[e];
  }
  // The tally of the elements that at least k chosen see.
  const auto tally_of_chosen = [&] {
    Tally tally = scorer.Zero();
    for (uint32_t e = 0; e < matrix.element_count(); ++e) {
      if (cover_count[e] >= k) scorer.AddElement(e, &tally);
    }
    return tally;
  };
  // Whether `chosen` with position p replaced by j (p == n: j appended) stays within the budget,
  // summed in the order TotalCost sums the answer.
  const auto fits = [&](size_t p, uint32_t j) {
    if (!has_budget) return true;
    double total = 0;
    for (size_t s = 0; s < chosen.size(); ++s) total += options.costs[s == p ? j : chosen[s]];
    if (p == chosen.size()) total += options.costs[j];
    return total <= options.budget;
  };
  const bool try_two_swap =
      Scorer::kCells && options.two_swap && k == 1 && !has_budget && n >= 2 && m - n >= 2;
  uint64_t two_swap_words = kMaxTwoSwapWords;
  Tally current = tally_of_chosen();
  Bitset base(matrix.word_count());
  Bitset target;
  while (true) {
    ThrowIfInterrupted();
    // Elements one more seer would bring to k (bits past the last element never meet a row).
    std::fill(base.begin(), base.end(), k == 1 ? ~uint64_t{0} : 0);
    if (k > 1) {
      for (uint32_t e = 0; e < matrix.element_count(); ++e) {
        if (cover_count[e] == k - 1) SetBit(&base, e);
      }
    } else {
      for (const uint32_t c : chosen) {
        for (const uint32_t e : matrix.Row(c)) ClearBit(&base, e);
      }
    }
    Score best = scorer.ScoreOf(current);
    bool improves = false;
    Tally best_tally = current;
    size_t best_position = 0;
    uint32_t best_in = 0;
    // With a budget, adding a sensor that fits is a move too (position n).
    const size_t positions = has_budget ? n + 1 : n;
    for (size_t p = 0; p < positions; ++p) {
      const bool is_add = p == chosen.size();
      target = base;
      Tally loss = scorer.Zero();
      if (!is_add) {
        // Removing chosen[p]: its cells at k drop to k - 1 (lost, and one seer brings them
        // back); those at k - 1 drop to k - 2 (one newcomer no longer completes them).
        for (const uint32_t e : matrix.Row(chosen[p])) {
          if (cover_count[e] == k) {
            SetBit(&target, e);
            scorer.AddElement(e, &loss);
          } else if (cover_count[e] == k - 1) {
            ClearBit(&target, e);
          }
        }
      }
      const Tally kept = current - loss;
      for (uint32_t j = 0; j < m; ++j) {
        if (is_chosen[j]) continue;
        // A candidate cannot add more than it sees: skip those that cannot beat the best move.
        if (!(best < scorer.ScoreOf(kept + scorer.RowWeight(j)))) continue;
        Tally after = kept + scorer.WeightIn(j, target);
        const Score score = scorer.ScoreOf(after);
        if (best < score && fits(p, j)) {
          best = score;
          improves = true;
          best_tally = std::move(after);
          best_position = p;
          best_in = j;
        }
      }
    }
    if (improves) {
      if (best_position == chosen.size()) {
        chosen.push_back(best_in);
      } else {
        const uint32_t out = chosen[best_position];
        for (const uint32_t e : matrix.Row(out)) --cover_count[e];
        is_chosen[out] = false;
        chosen[best_position] = best_in;
      }
      for (const uint32_t e : matrix.Row(best_in)) ++cover_count[e];
      is_chosen[best_in] = true;
      current = std::move(best_tally);
      continue;
    }
    if (!try_two_swap || two_swap_words == 0) break;
    const TwoSwap swap = BestTwoSwap(matrix, chosen, is_chosen, cover_count, &two_swap_words);
    if (swap.delta <= 0) break;
    for (const auto& [position, in] : {std::pair{swap.p, swap.x}, std::pair{swap.q, swap.y}}) {
      const uint32_t out = chosen[position];
      for (const uint32_t e : matrix.Row(out)) --cover_count[e];
      for (const uint32_t e : matrix.Row(in)) ++cover_count[e];
      is_chosen[out] = false;
      is_chosen[in] = true;
      chosen[position] = in;
    }
    current = tally_of_chosen();
  }
  return chosen;
}

std::vector<uint32_t> PointsLocalSearch(const CoverageMatrix& matrix, std::vector<uint32_t> chosen,
                                        int k) {
  const size_t m = matrix.candidate_count();
  const size_t n = chosen.size();
  VANTAGE_CHECK(k >= 1);
  if (n == 0 || n >= m) return chosen;
  const auto kk = static_cast<uint32_t>(k);
  std::vector<bool> is_chosen(m, false);
  std::vector<uint32_t> points(matrix.element_count(), 0);  // of the chosen, uncapped
  const auto change = [&](uint32_t candidate, bool add) {
    const std::vector<uint32_t>& row = matrix.Row(candidate);
    for (size_t j = 0; j < row.size(); ++j) {
      if (add) {
        points[row[j]] += matrix.Count(candidate, j);
      } else {
        points[row[j]] -= matrix.Count(candidate, j);
      }
    }
  };
  for (const uint32_t c : chosen) {
    VANTAGE_CHECK(c < m && !is_chosen[c]);
    is_chosen[c] = true;
    change(c, true);
  }
  while (true) {
    ThrowIfInterrupted();
    int64_t best_delta = 0;
    size_t best_position = 0;
    uint32_t best_in = 0;
    for (size_t p = 0; p < n; ++p) {
      const uint32_t out = chosen[p];
      // Cells that lose their k points with `out` gone, then what each unused one completes.
      int64_t loss = 0;
      const std::vector<uint32_t>& out_row = matrix.Row(out);
      for (size_t j = 0; j < out_row.size(); ++j) {
        const uint32_t have = points[out_row[j]];
        if (have >= kk && have - matrix.Count(out, j) < kk) loss += matrix.Weight(out_row[j]);
      }
      change(out, false);
      for (uint32_t in = 0; in < m; ++in) {
        if (is_chosen[in]) continue;
        // A candidate cannot complete more than it sees: skip those that cannot beat the best.
        if (static_cast<int64_t>(matrix.RowWeight(in)) - loss <= best_delta) continue;
        int64_t gain = 0;
        const std::vector<uint32_t>& row = matrix.Row(in);
        for (size_t j = 0; j < row.size(); ++j) {
          const uint32_t have = points[row[j]];
          if (have < kk && have + matrix.Count(in, j) >= kk) gain += matrix.Weight(row[j]);
        }
        if (gain - loss > best_delta) {
          best_delta = gain - loss;
          best_position = p;
          best_in = in;
        }
      }
      change(out, true);
    }
    if (best_delta <= 0) break;
    const uint32_t out = chosen[best_position];
    change(out, false);
    is_chosen[out] = false;
    change(best_in, true);
    is_chosen[best_in] = true;
    chosen[best_position] = best_in;
  }
  return chosen;
}

template std::vector<uint32_t> LocalSearch(const CellScorer&,
                                           std::vector<uint32_t>,
                                           const LocalOptions&);
template std::vector<uint32_t> LocalSearch(const StatesScorer&,
                                           std::vector<uint32_t>,
                                           const LocalOptions&);

}  // namespace vantage::detail
