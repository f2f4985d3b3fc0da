// The paper's Algorithm 2 (best-views-estimation.md, "Estimation of the best N sensors views").
//
// Speed (issue 47): the paper asks up to 10^6 iterations at every N. Each iteration's coverage
// comes from word-parallel bitsets (DrawCoverage: one OR per drawn row and word, then the weights
// as bit planes), about 20 times faster than summing the elements' weights bit by bit, with the
// same integers, so the same draws give the same answer.
#include <algorithm>
#include <bit>
#include <cmath>
#include <numeric>
#include <optional>
#include <type_traits>
#include <unordered_set>
#include <utility>

#include "select/constrained.hpp"
#include "select/methods.hpp"
#include "vantage/error.hpp"
#include "vantage/interrupt.hpp"
#include "vantage/rng.hpp"

namespace vantage::detail {
namespace {

// RansacDraw with the caller's scratch for the swaps (no allocation per iteration).
void DrawInto(uint64_t seed, uint64_t iteration, size_t n, std::vector<uint32_t>* order,
              std::vector<size_t>* swapped_with, std::vector<uint32_t>* drawn) {
  const size_t m = order->size();
  VANTAGE_CHECK(n >= 1 && n <= m);
  swapped_with->resize(n);
  drawn->resize(n);
  Rng rng(seed, Stream::kRansac, iteration);
  for (size_t k = 0; k < n; ++k) {
    (*swapped_with)[k] = k + static_cast<size_t>(rng.Below(m - k));
    std::swap((*order)[k], (*order)[(*swapped_with)[k]]);
    (*drawn)[k] = (*order)[k];
  }
  for (size_t k = n; k-- > 0;) std::swap((*order)[k], (*order)[(*swapped_with)[k]]);
}

}  // namespace

// Draw `iteration` of SelectSensorsRandomly: n distinct candidates of order->size(), from
// Rng(seed, Stream::kRansac, iteration). `order` must hold the identity permutation: a partial
// Fisher–Yates shuffle of it, undone after the draw so that iteration i's subset depends on its
// own stream only.
void RansacDraw(uint64_t seed,
                uint64_t iteration,
                size_t n,
                std::vector<uint32_t>* order,
                std::vector<uint32_t>* drawn) {
  std::vector<size_t> swapped_with;
  DrawInto(seed, iteration, n, order, &swapped_with, drawn);
}

int AllRansacShare::Iterations(int iterations, int n, int last_n) {
  VANTAGE_CHECK(iterations >= 1 && n >= 1 && n <= last_n);
  if (n == last_n) return iterations;
  // A draw of n costs about n rows' words, so the share is counted in drawn sensors.
  const double share = kDrawnSensors / (last_n - 1) / static_cast<double>(n);
  return static_cast<int>(std::clamp(std::floor(share), 1.0, static_cast<double>(iterations)));
}

namespace {

// Distinct subsets are tracked only up to this many: beyond it the iteration cap ends RANSAC
// long before every subset is seen (a coupon collector needs about C ln C draws).
constexpr uint64_t kMaxTrackedSubsets = 100'000;

// The bitsets of DrawCoverage are built while they take at most this much memory; beyond it
// (huge, unmergeable matrices) the scorer's own Covered serves.
constexpr size_t kMaxDrawBitsetBytes = size_t{256} << 20;

// C(m, k) when it is at most kMaxTrackedSubsets, else 0 (no overflow: each step's value is at
// most the result, times m).
uint64_t SmallBinomial(uint64_t m, uint64_t k) {
  if (k > m) return 0;
  k = std::min(k, m - k);
  uint64_t c = 1;
  for (uint64_t j = 0; j < k; ++j) {
    c = c * (m - j) / (j + 1);  // exact: C(m, j + 1)
    if (c > kMaxTrackedSubsets) return 0;
  }
  return c;
}

// The rank of a subset in the combinatorial number system: distinct subsets, distinct ranks,
// each below C(m, n). `sorted` ascending; only called when C(m, n) <= kMaxTrackedSubsets.
uint64_t SubsetRank(const std::vector<uint32_t>& sorted) {
  uint64_t rank = 0;
  for (size_t k = 0; k < sorted.size(); ++k) rank += SmallBinomial(sorted[k], k + 1);
  return rank;
}

// The cells per state of the elements that at least k of a drawn set see, from bitsets: each
// drawn row is ORed into k saturating levels (level j: the elements at least j + 1 of the rows so
// far see), then the weights of level k - 1 are read as bit planes: weight = Σ_b 2^b · [bit b],
// so a word costs one popcount per plane it has bits in. Exactly the integers of the scorers'
// Covered on matrices without point counts (those keep the scorers' path).
class DrawCoverage {
 public:
  static bool Serves(const CoverageMatrix& matrix, int k) {
    const size_t words = matrix.word_count();
    return !matrix.has_counts() && k >= 1 &&
           (matrix.candidate_count() + static_cast<size_t>(k)) * words * sizeof(uint64_t) <=
               kMaxDrawBitsetBytes;
  }

  DrawCoverage(const CoverageMatrix& matrix, int k)
      : words_(matrix.word_count()),
        k_(static_cast<size_t>(k)),
        cells_(matrix.state_count(), 0),
        levels_(k_ * words_, 0) {
    const size_t candidates = matrix.candidate_count();
    rows_.assign(candidates * words_, 0);
    for (uint32_t c = 0; c < candidates; ++c) {
      uint64_t* row = rows_.data() + c * words_;
      for (const uint32_t e : matrix.Row(c)) row[e >> 6] |= uint64_t{1} << (e & 63);
    }
    // One entry per (word, state, plane) with bits: the elements of that word in that state
    // whose weight has bit `plane` set.
    for (uint32_t s = 0; s < matrix.state_count(); ++s) {
      for (uint32_t e = matrix.StateBegin(s); e < matrix.StateBegin(s + 1); ++e) {
        for (uint32_t w = matrix.Weight(e), plane = 0; w != 0; w >>= 1, ++plane) {
          if (!(w & 1)) continue;
          const uint32_t word = e >> 6;
          auto it = std::find_if(open_.begin(), open_.end(), [&](const Plane& p) {
            return p.word == word && p.state == s && p.plane == plane;
          });
          if (it == open_.end()) {
            open_.push_back({word, s, plane, 0});
            it = open_.end() - 1;
          }
          it->mask |= uint64_t{1} << (e & 63);
        }
        if ((e & 63) == 63 || e + 1 == matrix.StateBegin(s + 1)) Flush();
      }
    }
  }

  /// Cells per state (cells()[s]) of the elements at least k of `drawn` see.
  const std::vector<uint64_t>& Count(std::span<const uint32_t> drawn) {
    CountDrawn(rows_.data(), drawn, words_, k_, levels_.data(), planes_.data(), planes_.size(),
               cells_.data(), cells_.size());
    return cells_;
  }

 private:
  struct Plane {
    uint32_t word;
    uint32_t state;
    uint32_t plane;
    uint64_t mask;
  };

  // Count's loops, compiled also for SSE4.2 and AVX2 and picked by the CPU at load time: the
  // x86-64 baseline has no popcnt instruction, so std::popcount there is a libgcc call, about
  // half of RANSAC's time (issue 47's profile). Same integers on every path.
  __attribute__((target_clones("avx2", "sse4.2", "default"))) static void CountDrawn(
      const uint64_t* rows, std::span<const uint32_t> drawn, size_t words, size_t k,
      uint64_t* levels, const Plane* planes, size_t plane_count, uint64_t* cells,
      size_t state_count) {
    std::fill(levels, levels + k * words, 0);
    for (const uint32_t c : drawn) {
      const uint64_t* row = rows + c * words;
      // Top level first, so that each reads the level below as it was before this row.
      for (size_t j = k; j-- > 1;) {
        uint64_t* level = levels + j * words;
        const uint64_t* below = level - words;
        for (size_t w = 0; w < words; ++w) level[w] |= below[w] & row[w];
      }
      for (size_t w = 0; w < words; ++w) levels[w] |= row[w];
    }
    const uint64_t* top = levels + (k - 1) * words;
    std::fill(cells, cells + state_count, 0);
    for (size_t i = 0; i < plane_count; ++i) {
      const Plane& p = planes[i];
      cells[p.state] += static_cast<uint64_t>(std::popcount(top[p.word] & p.mask)) << p.plane;
    }
  }

  // Moves the planes of the word just finished into planes_ (in word order: reads stay local).
  void Flush() {
    std::sort(open_.begin(), open_.end(),
              [](const Plane& a, const Plane& b) { return a.plane < b.plane; });
    planes_.insert(planes_.end(), open_.begin(), open_.end());
    open_.clear();
  }

  size_t words_;
  size_t k_;
  std::vector<uint64_t> cells_;
  std::vector<uint64_t> rows_;    ///< candidate × words_
  std::vector<uint64_t> levels_;  ///< k_ × words_
  std::vector<Plane> planes_;
  std::vector<Plane> open_;  ///< the word being built
};

}  // namespace

template <MethodScorer Scorer>
std::vector<uint32_t> RansacChoice(
    const Scorer& scorer, size_t n, int iterations, double stop_coverage, uint64_t seed) {
  const CoverageMatrix& matrix = scorer.matrix();
  const size_t m = matrix.candidate_count();
  VANTAGE_CHECK(n >= 1 && n <= m);
  std::vector<uint32_t> order(m);
  std::iota(order.begin(), order.end(), 0U);
  std::vector<uint32_t> best;  // s
  typename Scorer::Tally best_tally = scorer.Zero();
  typename Scorer::Score best_score{};  // c
  bool stop = false;                    // the best reached stop_coverage
  std::vector<uint32_t> drawn(n);
  std::vector<size_t> swapped_with(n);
  // Issue 15: 2^31 - 1 iterations over 120 possible subsets ran for hours. Once every subset has
  // been drawn no later draw can be strictly better, so stopping then returns the same subset.
  const uint64_t subsets = SmallBinomial(m, n);
  std::unordered_set<uint64_t> seen;
  std::vector<uint32_t> sorted;
  std::optional<DrawCoverage> fast;
  if (DrawCoverage::Serves(matrix, scorer.k())) fast.emplace(matrix, scorer.k());
  // Merge, filter, coverage (k-coverage: the cells at least k of the draw see).
  const auto covered = [&]() -> typename Scorer::Tally {
    if (!fast) return scorer.Covered(drawn);
    const std::vector<uint64_t>& cells = fast->Count(drawn);
    if constexpr (std::is_same_v<Scorer, CellScorer>) {
      return std::accumulate(cells.begin(), cells.end(), uint64_t{0});
    } else {
      typename Scorer::Tally tally = scorer.Zero();
      for (size_t s = 0; s < cells.size(); ++s) tally[s] = cells[s];
      return tally;
    }
  };
  // `best.empty()`: Algorithm 2 would return nothing when no draw covers anything (or C = 0);
  // keeping the first draw instead changes no other outcome.
  for (int i = 0; i < iterations && !stop;) {
    if (i % 64 == 0) ThrowIfInterrupted();
    DrawInto(seed, static_cast<uint64_t>(i), n, &order, &swapped_with, &drawn);
    if (subsets > 0) {
      sorted = drawn;
      std::sort(sorted.begin(), sorted.end());
      seen.insert(SubsetRank(sorted));
    }
    typename Scorer::Tally tally = covered();
    const typename Scorer::Score score = scorer.ScoreOf(tally);
    ++i;
    if (best.empty() || best_score < score) {
      best = drawn;
      best_tally = std::move(tally);
      best_score = score;
      stop = scorer.Fraction(best_tally) >= stop_coverage;
    }
    if (subsets > 0 && seen.size() == subsets) break;
  }
  return best;
}

template std::vector<uint32_t> RansacChoice(const CellScorer&, size_t, int, double, uint64_t);
template std::vector<uint32_t> RansacChoice(const StatesScorer&, size_t, int, double, uint64_t);

}  // namespace vantage::detail

namespace vantage::detail {

std::vector<uint32_t> RansacFitted(const CoverageMatrix& matrix, const FittedDraws& fit,
                                   int iterations, double stop_coverage, uint64_t seed) {
  const size_t m = matrix.candidate_count();
  VANTAGE_CHECK(fit.threshold >= 1 && (fit.costs.empty() || fit.costs.size() == m));
  VANTAGE_CHECK(fit.budget.has_value() != (fit.goal_cells > 0));
  const auto cost = [&](uint32_t c) { return fit.costs.empty() ? 1.0 : fit.costs[c]; };
  std::vector<bool> is_start(m, false);
  for (const uint32_t c : fit.start) is_start[c] = true;
  std::vector<uint32_t> order(m), shuffled(m);
  std::iota(order.begin(), order.end(), 0U);
  std::vector<size_t> swapped_with;
  std::vector<uint32_t> best, set;
  uint64_t best_cells = 0;
  double best_price = 0;
  for (int i = 0; i < iterations; ++i) {
    if (i % 64 == 0) ThrowIfInterrupted();
    // Draw i: a random order of every candidate (RansacDraw's shuffle, run to the end).
    DrawInto(seed, static_cast<uint64_t>(i), m, &order, &swapped_with, &shuffled);
    CappedPoints points(matrix, fit.threshold);
    set.assign(fit.start.begin(), fit.start.end());
    uint64_t cells = 0;
    double spent = 0;
    for (const uint32_t c : set) {
      cells += points.Gain(c).first;
      points.Add(c);
      spent += cost(c);
    }
    // Passes over the order until nothing more is taken (a candidate the rule refused may join
    // once another is in).
    for (bool took = true; took && !(fit.goal_cells > 0 && cells >= fit.goal_cells);) {
      took = false;
      for (const uint32_t c : shuffled) {
        if (is_start[c] || std::find(set.begin(), set.end(), c) != set.end()) continue;
        if (fit.goal_cells > 0 && cells >= fit.goal_cells) break;
        if (fit.budget && spent + cost(c) > *fit.budget) continue;
        const std::pair<uint64_t, uint64_t> gain = points.Gain(c);
        if (gain.second == 0) continue;  // adds nothing the objective counts
        if (fit.may_add && !fit.may_add(set, c)) continue;
        set.push_back(c);
        points.Add(c);
        cells += gain.first;
        spent += cost(c);
        took = true;
      }
    }
    double price = 0;
    if (fit.goal_cells > 0) {
      if (cells < fit.goal_cells) continue;  // this order under the rules never reached it
      // Latest first, drop what the goal no longer needs (and the rules allow to drop).
      for (size_t p = set.size(); p-- > fit.start.size();) {
        std::vector<uint32_t> without = set;
        without.erase(without.begin() + static_cast<std::ptrdiff_t>(p));
        if (KCoveredWeight(matrix, without, fit.threshold) < fit.goal_cells) continue;
        if (fit.is_feasible && !fit.is_feasible(without)) continue;
        set = std::move(without);
      }
      for (const uint32_t c : set) price += cost(c);
      if (best.empty() || price < best_price) {
        best = set;
        best_price = price;
      }
      continue;
    }
    if (best.empty() || cells > best_cells) {
      best = set;
      best_cells = cells;
    }
    const size_t r = matrix.reference_size();
    if (r > 0 && static_cast<double>(best_cells) / static_cast<double>(r) >= stop_coverage) break;
  }
  return best;
}

}  // namespace vantage::detail
