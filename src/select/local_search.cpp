// Swap local search after greedy (SYSTEM.md, Select: `local`), for plain coverage, k-coverage, a
// cost budget and the states of a scene (whatever the scorer scores); 2-swaps where they stay
// cheap.
#include <algorithm>
#include <bit>
#include <optional>
#include <utility>

#include "select/methods.hpp"
#include "vantage/error.hpp"
#include "vantage/interrupt.hpp"

namespace vantage::detail {
namespace {

// Work cap of the 2-swap passes of one LocalSearch call, in the bitset words that recomputing
// every a_j and every pair's value over whole rows would touch (what the search read before it
// was incremental, issue 47: about 0.1-0.3 s then, a fraction of that now): beyond it the current
// pass stops with the best swap found so far and no further pass starts. Counted, not timed, so
// the answer depends neither on the machine nor on how the values are found.
constexpr uint64_t kMaxTwoSwapWords = uint64_t{600} << 20;

// The most memory PointsLocalSearch takes for the ranks of its incremental evaluation.
constexpr size_t kMaxRankBytes = size_t{64} << 20;

void SetBit(Bitset* set, uint32_t e) { (*set)[e >> 6] |= uint64_t{1} << (e & 63); }
void ClearBit(Bitset* set, uint32_t e) { (*set)[e >> 6] &= ~(uint64_t{1} << (e & 63)); }

// A set of elements that is empty outside a few words: the bits (a full Bitset, zero outside
// `words`) and those words, increasing, so that a weight over it reads only them. Elements are
// added in increasing order (a row's order).
struct FewWords {
  Bitset bits;
  std::vector<uint32_t> words;
  explicit FewWords(size_t word_count) : bits(word_count, 0) {}
  bool empty() const { return words.empty(); }
  void Add(uint32_t e) {
    const uint32_t w = e >> 6;
    if (words.empty() || words.back() != w) words.push_back(w);
    bits[w] |= uint64_t{1} << (e & 63);
  }
  void Clear() {
    for (const uint32_t w : words) bits[w] = 0;
    words.clear();
  }
  // Word w (above every word so far) set to `word`.
  void AddWord(uint32_t w, uint64_t word) {
    if (word == 0) return;
    words.push_back(w);
    bits[w] = word;
  }
};

// The scorer's WeightIn(candidate, set.bits), reading only the set's words.
uint64_t TallyIn(const CellScorer& scorer, uint32_t candidate, const FewWords& set) {
  return scorer.matrix().WeightInWords(candidate, set.bits, set.words);
}
StateTally TallyIn(const StatesScorer& scorer, uint32_t candidate, const FewWords& set) {
  const uint64_t* row = scorer.matrix().RowBits(candidate);
  if (row == nullptr) return scorer.WeightIn(candidate, set.bits);
  StateTally tally = scorer.Zero();
  for (const uint32_t w : set.words) {
    for (uint64_t bits = row[w] & set.bits[w]; bits != 0; bits &= bits - 1) {
      scorer.AddElement(w * 64 + static_cast<uint32_t>(std::countr_zero(bits)), &tally);
    }
  }
  return tally;
}

// Whether `e` is in the row of `candidate`.
bool InRow(const CoverageMatrix& matrix, uint32_t candidate, uint32_t e) {
  const uint64_t* row = matrix.RowBits(candidate);
  if (row != nullptr) return (row[e >> 6] >> (e & 63)) & 1;
  const std::vector<uint32_t>& sorted = matrix.Row(candidate);
  return std::binary_search(sorted.begin(), sorted.end(), e);
}

// The tallies of 1-swaps, incrementally. With the cover counts of the chosen, `base` is the
// elements one more seer brings to k; removing `out` adds the elements of its row at k (lost:
// they drop to k - 1) and takes away those at k - 1 (blocked: they drop to k - 2), so an unused j
// brings WeightIn(j, base) (once per pass) + its weight in `lost` - its weight in `blocked`: the
// few words of one row per position instead of j's whole row.
template <class Scorer>
class OneSwaps {
 public:
  using Tally = typename Scorer::Tally;

  OneSwaps(const Scorer& scorer, const std::vector<uint32_t>& cover_count)
      : scorer_(scorer),
        matrix_(scorer.matrix()),
        cover_count_(cover_count),
        k_(static_cast<uint32_t>(scorer.k())),
        base_(matrix_.word_count()),
        base_weight_(matrix_.candidate_count(), scorer.Zero()),
        loss_(scorer.Zero()),
        lost_(matrix_.word_count()),
        blocked_(matrix_.word_count()) {}

  // A pass over the current counts: `base` and each unused candidate's weight in it.
  void StartPass(const std::vector<uint32_t>& chosen, const std::vector<bool>& is_chosen) {
    // Elements one more seer would bring to k (bits past the last element never meet a row).
    std::fill(base_.begin(), base_.end(), k_ == 1 ? ~uint64_t{0} : 0);
    if (k_ > 1) {
      for (uint32_t e = 0; e < matrix_.element_count(); ++e) {
        if (cover_count_[e] == k_ - 1) SetBit(&base_, e);
      }
    } else {
      for (const uint32_t c : chosen) {
        for (const uint32_t e : matrix_.Row(c)) ClearBit(&base_, e);
      }
    }
    for (uint32_t j = 0; j < matrix_.candidate_count(); ++j) {
      if (!is_chosen[j]) base_weight_[j] = scorer_.WeightIn(j, base_);
    }
  }

  // The chosen `out` leaves (nobody when `out` is empty: an addition); returns the tally lost.
  const Tally& Remove(std::optional<uint32_t> out) {
    lost_.Clear();
    blocked_.Clear();
    loss_ = scorer_.Zero();
    if (out) {
      for (const uint32_t e : matrix_.Row(*out)) {
        if (cover_count_[e] == k_) {
          lost_.Add(e);
          scorer_.AddElement(e, &loss_);
        } else if (cover_count_[e] == k_ - 1) {
          blocked_.Add(e);
        }
      }
    }
    if (!matrix_.is_dense()) {  // rows as lists: the target set itself
      target_ = base_;
      for (const uint32_t w : lost_.words) target_[w] |= lost_.bits[w];
      for (const uint32_t w : blocked_.words) target_[w] &= ~blocked_.bits[w];
    }
    return loss_;
  }

  // What unused j brings at most after Remove: its weight in `base` plus the tally lost.
  const Tally& BaseWeight(uint32_t j) const { return base_weight_[j]; }

  // `kept` (the tally without the removed) plus what unused j brings.
  Tally After(const Tally& kept, uint32_t j) const {
    if (!matrix_.is_dense()) return kept + scorer_.WeightIn(j, target_);
    Tally after = kept + base_weight_[j];
    if (!lost_.empty()) after += TallyIn(scorer_, j, lost_);
    if (!blocked_.empty()) after -= TallyIn(scorer_, j, blocked_);
    return after;
  }

 private:
  const Scorer& scorer_;
  const CoverageMatrix& matrix_;
  const std::vector<uint32_t>& cover_count_;
  uint32_t k_;
  Bitset base_;
  std::vector<Tally> base_weight_;
  Tally loss_;
  FewWords lost_, blocked_;
  Bitset target_;
};

// What an unused candidate completes on the `open` cells with points (those of the chosen
// without `out`) minus what it completes there with `out_points` added: for each cell of its
// row (`row` bits) in `open`, its count found by the cell's rank in the row (`before`: the row's
// popcount before each word; counts null: every count 1). Built for AVX2, SSE4.2 and the
// baseline (the popcount of the rank), the loader picking the best the machine has.
__attribute__((target_clones("avx2", "sse4.2", "default"))) int64_t OpenGain(
    const uint64_t* row,
    const uint32_t* before,
    const uint32_t* counts,
    const FewWords& open,
    const uint32_t* points,
    const uint32_t* out_points,
    const uint32_t* weights,
    uint32_t k) {
  int64_t gain = 0;
  for (const uint32_t w : open.words) {
    for (uint64_t bits = row[w] & open.bits[w]; bits != 0; bits &= bits - 1) {
      const auto bit = static_cast<uint32_t>(std::countr_zero(bits));
      const uint32_t e = w * 64 + bit;
      const uint32_t count =
          counts == nullptr
              ? 1
              : counts[before[w] +
                       static_cast<uint32_t>(std::popcount(row[w] & ((uint64_t{1} << bit) - 1)))];
      const uint32_t have = points[e];
      const bool now = have < k && have + count >= k;
      const bool with_out = have + out_points[e] < k && have + out_points[e] + count >= k;
      gain += (static_cast<int64_t>(now) - static_cast<int64_t>(with_out)) * weights[e];
    }
  }
  return gain;
}

struct TwoSwap {
  int64_t delta = 0;
  size_t p = 0, q = 0;    // positions out
  uint32_t x = 0, y = 0;  // candidates in (x to p, y to q)
};

// The best 2-swap for plain coverage (k = 1): two chosen out, two unused in. For each pair out,
// the freed cells F are those nobody else chosen sees; a newcomer j brings a_j = |row j ∩ F| and a
// pair brings a_x + |row y ∩ F \ row x| <= a_x + a_y, so pairs are tried in decreasing a and cut
// off once a_x + a_y cannot beat the best. Ties: earlier positions, then larger a, lower index.
// F is the uncovered cells, those only p sees, those only q sees and those only both see, so
// a_j is summed from the pass's BaseWeight (row j ∩ uncovered) and the few words of the other
// three. The work cap counts what a recomputation of every a_j would read, so that where it stops
// (and the answer) does not depend on how a_j is found.
TwoSwap BestTwoSwap(const CoverageMatrix& matrix,
                    const std::vector<uint32_t>& chosen,
                    const std::vector<bool>& is_chosen,
                    const std::vector<uint32_t>& cover_count,
                    const OneSwaps<CellScorer>& swaps,
                    uint64_t* words_left) {
  TwoSwap best;
  const size_t m = matrix.candidate_count();
  const size_t n = chosen.size();
  const uint64_t words = std::max<size_t>(matrix.word_count(), 1);
  if (*words_left < words * (m + 2)) return best;  // as the first pair would
  Bitset uncovered(matrix.word_count(), ~uint64_t{0});
  for (const uint32_t c : chosen) {
    for (const uint32_t e : matrix.Row(c)) ClearBit(&uncovered, e);
  }
  // Per position: the cells only it sees, their weight, and what each unused candidate sees of
  // them (sees_alone[p * m + j]).
  std::vector<FewWords> alone(n, FewWords(matrix.word_count()));
  std::vector<uint64_t> alone_weight(n, 0);
  std::vector<uint64_t> sees_alone(n * m, 0);
  for (size_t p = 0; p < n; ++p) {
    for (const uint32_t e : matrix.Row(chosen[p])) {
      if (cover_count[e] != 1) continue;
      alone[p].Add(e);
      alone_weight[p] += matrix.Weight(e);
    }
    if (alone[p].empty()) continue;
    for (uint32_t j = 0; j < m; ++j) {
      if (!is_chosen[j]) sees_alone[p * m + j] = TallyIn(CellScorer(matrix), j, alone[p]);
    }
  }
  FewWords both(matrix.word_count()), with_x(matrix.word_count());
  Bitset freed;
  std::vector<uint64_t> bring(m, 0);
  std::vector<uint32_t> order;
  for (size_t p = 0; p < n; ++p) {
    for (size_t q = p + 1; q < n; ++q) {
      if (*words_left < words * (m + 2)) return best;
      *words_left -= words * (m + 2);
      const uint32_t a = chosen[p], b = chosen[q];
      // Cells whose every chosen seer is a or b become uncovered.
      both.Clear();
      uint64_t freed_weight = alone_weight[p] + alone_weight[q];
      for (const uint32_t e : matrix.Row(a)) {
        if (cover_count[e] == 2 && InRow(matrix, b, e)) {
          both.Add(e);
          freed_weight += matrix.Weight(e);
        }
      }
      const auto loss = static_cast<int64_t>(freed_weight);
      order.clear();
      uint64_t most = 0;
      for (uint32_t j = 0; j < m; ++j) {
        if (is_chosen[j]) continue;
        bring[j] = swaps.BaseWeight(j) + sees_alone[p * m + j] + sees_alone[q * m + j];
        if (!both.empty()) bring[j] += TallyIn(CellScorer(matrix), j, both);
        if (bring[j] > 0) {
          order.push_back(j);
          most = std::max(most, bring[j]);
        }
      }
      // Only a prefix of the decreasing order can be reached: a newcomer with a_j <= loss +
      // best.delta - max a ends both loops below wherever it comes (best.delta only grows), so
      // it need not be sorted.
      const int64_t cut = loss + best.delta - static_cast<int64_t>(most);
      const auto reached = std::partition(order.begin(), order.end(), [&](uint32_t j) {
        return static_cast<int64_t>(bring[j]) > cut;
      });
      order.erase(reached, order.end());
      std::sort(order.begin(), order.end(), [&](uint32_t u, uint32_t v) {
        return bring[u] != bring[v] ? bring[u] > bring[v] : u < v;
      });
      bool freed_made = false;
      for (size_t s = 0; s + 1 < order.size(); ++s) {
        const uint32_t x = order[s];
        const auto need = loss + best.delta;  // a pair must bring more than this
        if (static_cast<int64_t>(bring[x] + bring[order[s + 1]]) <= need) break;
        if (!freed_made) {
          freed = uncovered;
          for (const FewWords* set : {&alone[p], &alone[q], &both}) {
            for (const uint32_t w : set->words) freed[w] |= set->bits[w];
          }
          freed_made = true;
        }
        // A pair's a_x + |row y ∩ F \ row x| = a_x + a_y - |row y ∩ (row x ∩ F)|.
        with_x.Clear();
        if (const uint64_t* row = matrix.RowBits(x)) {
          for (uint32_t w = 0; w < matrix.word_count(); ++w) with_x.AddWord(w, row[w] & freed[w]);
        } else {
          for (const uint32_t e : matrix.Row(x)) {
            if (Contains(freed, e)) with_x.Add(e);
          }
        }
        for (size_t t = s + 1; t < order.size(); ++t) {
          const uint32_t y = order[t];
          if (static_cast<int64_t>(bring[x] + bring[y]) <= loss + best.delta) break;
          if (*words_left < words) return best;
          *words_left -= words;
          const uint64_t shared = with_x.empty() ? 0 : TallyIn(CellScorer(matrix), y, with_x);
          const int64_t delta = static_cast<int64_t>(bring[x] + bring[y] - shared) - loss;
          if (delta > best.delta) best = {delta, p, q, x, y};
        }
      }
    }
  }
  return best;
}

// Marks the chosen candidates (each once) and counts, per element, the chosen that see it.
std::vector<uint32_t> CoverCounts(const CoverageMatrix& matrix, std::span<const uint32_t> chosen,
                                  std::vector<bool>* is_chosen) {
  is_chosen->assign(matrix.candidate_count(), false);
  std::vector<uint32_t> cover_count(matrix.element_count(), 0);
  for (const uint32_t c : chosen) {
    VANTAGE_CHECK(c < matrix.candidate_count() && !(*is_chosen)[c]);
    (*is_chosen)[c] = true;
    for (const uint32_t e : matrix.Row(c)) ++cover_count[e];
  }
  return cover_count;
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
  std::vector<bool> is_chosen;
  // How many chosen candidates see each element: removing one lowers the counts of its row.
  std::vector<uint32_t> cover_count = CoverCounts(matrix, chosen, &is_chosen);
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
  OneSwaps<Scorer> swaps(scorer, cover_count);
  while (true) {
    ThrowIfInterrupted();
    swaps.StartPass(chosen, is_chosen);
    Score best = scorer.ScoreOf(current);
    bool improves = false;
    Tally best_tally = current;
    size_t best_position = 0;
    uint32_t best_in = 0;
    // With a budget, adding a sensor that fits is a move too (position n).
    const size_t positions = has_budget ? n + 1 : n;
    for (size_t p = 0; p < positions; ++p) {
      const bool is_add = p == chosen.size();
      const Tally kept =
          current - swaps.Remove(is_add ? std::nullopt : std::optional<uint32_t>(chosen[p]));
      for (uint32_t j = 0; j < m; ++j) {
        if (is_chosen[j]) continue;
        // j brings at most its weight in `base` plus the loss (current + that in all): skip
        // those that cannot beat the best move.
        if (!(best < scorer.ScoreOf(current + swaps.BaseWeight(j)))) continue;
        Tally after = swaps.After(kept, j);
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
    TwoSwap swap;
    if constexpr (Scorer::kCells) {
      swap = BestTwoSwap(matrix, chosen, is_chosen, cover_count, swaps, &two_swap_words);
    }
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

std::vector<uint32_t> PointsLocalSearch(const CoverageMatrix& matrix,
                                        std::vector<uint32_t> chosen,
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
  // Incrementally (dense rows): with points' the counts without `out`, an unused candidate
  // completes sum over its row of w(e) [points' < k <= points' + its count], which differs
  // from `complete` (the same with every chosen, once per pass) only on the cells of out's row
  // that points' leaves below k (`open`); there its count is found by its rank in the row (the
  // row's popcounts before each word, `before`: half the dense rows' memory, so only up to
  // kMaxRankBytes; beyond it each row is read whole, as before).
  const size_t words = matrix.word_count();
  const bool dense = matrix.is_dense() && m * words * sizeof(uint32_t) <= kMaxRankBytes;
  std::vector<uint32_t> before;
  std::vector<int64_t> complete;
  std::vector<uint32_t> out_points(dense ? matrix.element_count() : 0, 0);
  FewWords open(dense ? words : 0);
  if (dense) {
    before.resize(m * words);
    complete.resize(m);
    for (uint32_t c = 0; c < m; ++c) {
      const uint64_t* row = matrix.RowBits(c);
      uint32_t count = 0;
      for (size_t w = 0; w < words; ++w) {
        before[c * words + w] = count;
        count += static_cast<uint32_t>(std::popcount(row[w]));
      }
    }
  }
  const auto completes = [&](uint32_t have, uint32_t count) {
    return have < kk && have + count >= kk;
  };
  while (true) {
    ThrowIfInterrupted();
    int64_t best_delta = 0;
    size_t best_position = 0;
    uint32_t best_in = 0;
    if (dense) {
      for (uint32_t in = 0; in < m; ++in) {
        if (is_chosen[in]) continue;
        int64_t gain = 0;
        const std::vector<uint32_t>& row = matrix.Row(in);
        for (size_t j = 0; j < row.size(); ++j) {
          if (completes(points[row[j]], matrix.Count(in, j))) gain += matrix.Weight(row[j]);
        }
        complete[in] = gain;
      }
    }
    for (size_t p = 0; p < n; ++p) {
      const uint32_t out = chosen[p];
      // Cells that lose their k points with `out` gone, then what each unused one completes.
      int64_t loss = 0;
      int64_t open_weight = 0;
      const std::vector<uint32_t>& out_row = matrix.Row(out);
      open.Clear();
      for (size_t j = 0; j < out_row.size(); ++j) {
        const uint32_t have = points[out_row[j]];
        if (have >= kk && have - matrix.Count(out, j) < kk) loss += matrix.Weight(out_row[j]);
        if (dense && have - matrix.Count(out, j) < kk) {
          open.Add(out_row[j]);
          open_weight += matrix.Weight(out_row[j]);
          out_points[out_row[j]] = matrix.Count(out, j);
        }
      }
      change(out, false);
      for (uint32_t in = 0; in < m; ++in) {
        if (is_chosen[in]) continue;
        // A candidate cannot complete more than it sees, nor more than `complete` and the open
        // cells: skip those that cannot beat the best.
        if (static_cast<int64_t>(matrix.RowWeight(in)) - loss <= best_delta) continue;
        int64_t gain = 0;
        if (dense) {
          if (complete[in] + open_weight - loss <= best_delta) continue;
          gain = complete[in] + OpenGain(matrix.RowBits(in), before.data() + in * words,
                                         matrix.Counts(in).data(), open, points.data(),
                                         out_points.data(), matrix.weights().data(), kk);
        } else {
          const std::vector<uint32_t>& row = matrix.Row(in);
          for (size_t j = 0; j < row.size(); ++j) {
            if (completes(points[row[j]], matrix.Count(in, j))) gain += matrix.Weight(row[j]);
          }
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

template <class Scorer>
std::vector<typename Scorer::Tally> OneSwapTallies(const Scorer& scorer,
                                                   std::span<const uint32_t> chosen) {
  const CoverageMatrix& matrix = scorer.matrix();
  const size_t m = matrix.candidate_count();
  const auto k = static_cast<uint32_t>(scorer.k());
  std::vector<bool> is_chosen;
  const std::vector<uint32_t> cover_count = CoverCounts(matrix, chosen, &is_chosen);
  typename Scorer::Tally current = scorer.Zero();
  for (uint32_t e = 0; e < matrix.element_count(); ++e) {
    if (cover_count[e] >= k) scorer.AddElement(e, &current);
  }
  const std::vector<uint32_t> list(chosen.begin(), chosen.end());
  OneSwaps<Scorer> swaps(scorer, cover_count);
  swaps.StartPass(list, is_chosen);
  std::vector<typename Scorer::Tally> tallies((chosen.size() + 1) * m, scorer.Zero());
  for (size_t p = 0; p <= chosen.size(); ++p) {
    const auto out = p < chosen.size() ? std::optional<uint32_t>(chosen[p]) : std::nullopt;
    const typename Scorer::Tally kept = current - swaps.Remove(out);
    for (uint32_t j = 0; j < m; ++j) {
      if (!is_chosen[j]) tallies[p * m + j] = swaps.After(kept, j);
    }
  }
  return tallies;
}

template std::vector<uint64_t> OneSwapTallies(const CellScorer&, std::span<const uint32_t>);
template std::vector<StateTally> OneSwapTallies(const StatesScorer&, std::span<const uint32_t>);

template std::vector<uint32_t> LocalSearch(const CellScorer&,
                                           std::vector<uint32_t>,
                                           const LocalOptions&);
template std::vector<uint32_t> LocalSearch(const StatesScorer&,
                                           std::vector<uint32_t>,
                                           const LocalOptions&);

}  // namespace vantage::detail
