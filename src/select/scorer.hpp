#pragma once
/// What the selection methods maximise. The methods (methods.hpp) are templates over a scorer, so
/// that one best candidate, one RANSAC, one greedy and one local search serve plain selection
/// (CellScorer: covered cells, or k-covered cells) and selection over the states of a scene
/// (StatesScorer: the mean or the worst of the states' coverages).
///
/// A scorer turns the elements that a set of candidates covers into a Tally (cells; cells per
/// state), and a Tally into a Score, which the methods compare:
///   matrix(), k()              the matrix scored; an element counts once k() chosen see it
///   Tally, Zero()              with + and -; AddElement(e, &t) adds the cells of element e
///   Gain(c, covered)           the tally of c's elements outside `covered`
///   WeightIn(c, set)           the tally of c's elements inside `set`
///   RowWeight(c)               the tally of all of c's elements
///   Covered(chosen)            the tally of the elements at least k() of `chosen` see
///   Score, ScoreOf(t)          ordered by < and ==; larger when a part of the tally grows and
///                              none shrinks (the methods' cut-offs and greedy's "nothing adds
///                              anything" rely on it)
///   Rank(covered, gain)        orders the candidates of one greedy step as the score of covered
///                              plus gain does; when lazy(), it must never grow as `covered` grows
///                              (a submodular score), so that greedy may keep stale ranks as bounds
///   Fraction(t)                the share of R, for RANSAC's stop test
///   kCells                     Score is the Tally itself (2-swaps reason in differences of cells)
#include <cstdint>
#include <span>
#include <vector>

#include "select/coverage_matrix.hpp"
#include "vantage/select_states.hpp"

namespace vantage::detail {

/// Cells of the elements that at least k of `chosen` see (a candidate listed twice counts twice).
uint64_t KCoveredWeight(const CoverageMatrix& matrix, std::span<const uint32_t> chosen, int k);

/// Plain coverage: the covered cells; with k >= 2 a cell counts once k chosen candidates see it
/// (k-coverage, for RANSAC and local search; its greedy is KGreedyComplete).
class CellScorer {
 public:
  using Tally = uint64_t;
  using Score = uint64_t;
  static constexpr bool kCells = true;

  explicit CellScorer(const CoverageMatrix& matrix, int k = 1) : matrix_(&matrix), k_(k) {}

  const CoverageMatrix& matrix() const { return *matrix_; }
  int k() const { return k_; }
  bool lazy() const { return true; }  // coverage is submodular
  Tally Zero() const { return 0; }
  void AddElement(uint32_t element, Tally* tally) const { *tally += matrix_->Weight(element); }
  Tally Gain(uint32_t candidate, const Bitset& covered) const {
    return matrix_->Gain(candidate, covered);
  }
  Tally WeightIn(uint32_t candidate, const Bitset& set) const {
    return matrix_->WeightIn(candidate, set);
  }
  Tally RowWeight(uint32_t candidate) const { return matrix_->RowWeight(candidate); }
  Tally Covered(std::span<const uint32_t> chosen) const {
    return k_ == 1 ? matrix_->CoveredWeight(chosen) : KCoveredWeight(*matrix_, chosen, k_);
  }
  Score ScoreOf(Tally cells) const { return cells; }
  Score Rank(Tally /*covered*/, Tally gain) const { return gain; }
  double Fraction(Tally cells) const {
    const size_t r = matrix_->reference_size();
    return r ? static_cast<double>(cells) / static_cast<double>(r) : 0.0;
  }

 private:
  const CoverageMatrix* matrix_;
  int k_;
};

/// Every 1-swap's tally as LocalSearch computes it (incrementally, from the cover counts of
/// `chosen`): [p * candidate_count + j] for chosen[p] out and an unused j in, p = chosen.size()
/// for j added; Zero() for a chosen j. For tests (local_search.cpp, CellScorer, StatesScorer).
template <class Scorer>
std::vector<typename Scorer::Tally> OneSwapTallies(const Scorer& scorer,
                                                   std::span<const uint32_t> chosen);

/// Covered cells per state, in state order.
class StateTally {
 public:
  explicit StateTally(size_t states = 0) : cells_(states, 0) {}
  size_t size() const { return cells_.size(); }
  uint64_t operator[](size_t state) const { return cells_[state]; }
  uint64_t& operator[](size_t state) { return cells_[state]; }
  StateTally& operator+=(const StateTally& other) {
    for (size_t s = 0; s < cells_.size(); ++s) cells_[s] += other.cells_[s];
    return *this;
  }
  StateTally& operator-=(const StateTally& other) {
    for (size_t s = 0; s < cells_.size(); ++s) cells_[s] -= other.cells_[s];
    return *this;
  }
  friend StateTally operator+(StateTally a, const StateTally& b) { return a += b; }
  friend StateTally operator-(StateTally a, const StateTally& b) { return a -= b; }

 private:
  std::vector<uint64_t> cells_;
};

/// Selection over the states of a scene, on their stacked matrix: the covered cells c_s of each
/// state s, each weighing its aggregation's ω_s = p_s / q_s (select_states.hpp, kAggregations),
/// aggregated by its shape: the weighted sum Σ ω_s c_s (mean: ω_s = 1 / |R_s|; sum: 1), or the
/// least ω_s c_s with ties broken by that sum (min: the least share; then, in every method, by the
/// lower index). Scores are compared exactly: each ω_s c_s is a whole number of units 1 / L,
/// L = lcm(q_s) (fixed point 2^-62 when L is too large), so no floating-point summation order can
/// change a choice. With exact units a weighted sum is a coverage with weight L p_s / q_s per cell
/// of state s, and greedy is lazy for it as for plain coverage.
class StatesScorer {
 public:
  __extension__ typedef __int128 Int;  // exact scores: up to S · L < 2^127
  using Tally = StateTally;
  /// Lexicographic: primary (a weighted sum: Σ ω_s c_s; a minimum: the least ω_s c_s), then
  /// secondary (a minimum: Σ ω_s c_s; a weighted sum: 0), each in units.
  struct Score {
    Int primary = 0;
    Int secondary = 0;
    bool operator==(const Score& o) const {
      return primary == o.primary && secondary == o.secondary;
    }
    bool operator<(const Score& o) const {
      return primary != o.primary ? primary < o.primary : secondary < o.secondary;
    }
  };
  static constexpr bool kCells = false;

  /// A state with an empty R_s counts 0 (SelectOverStates refuses one; a plain matrix's one
  /// state may be empty). With `threshold` >= 2 (point density: a matrix with counts) an
  /// element counts in Covered once the chosen put that many points in it; Gain, WeightIn and
  /// Rank then describe plain coverage and only the constrained methods use the scorer.
  StatesScorer(const CoverageMatrix& matrix, OverStates over, int threshold = 1);

  const CoverageMatrix& matrix() const { return *matrix_; }
  OverStates over() const { return aggregation_->value; }
  const Aggregation& aggregation() const { return *aggregation_; }
  int k() const { return threshold_; }
  bool lazy() const { return aggregation_->shape == AggregateShape::kWeightedSum && exact_; }
  Tally Zero() const { return StateTally(matrix_->state_count()); }
  void AddElement(uint32_t element, Tally* tally) const {
    (*tally)[state_of_[element]] += matrix_->Weight(element);
  }
  Tally Gain(uint32_t candidate, const Bitset& covered) const;
  Tally WeightIn(uint32_t candidate, const Bitset& set) const;
  const Tally& RowWeight(uint32_t candidate) const { return row_weights_[candidate]; }
  Tally Covered(std::span<const uint32_t> chosen) const;
  Score ScoreOf(const Tally& cells) const;
  Score Rank(const Tally& covered, const Tally& gain) const {
    return lazy() ? ScoreOf(gain) : ScoreOf(covered + gain);
  }
  /// The aggregate as a fraction (for RANSAC's stop test only; choices compare Scores).
  double Fraction(const Tally& cells) const;

 private:
  /// ω_s · cells in units of 1 / L (exact), or floor(cells · p_s · 2^62 / q_s).
  Int Units(size_t state, uint64_t cells) const;
  /// The tally of the elements of `candidate` in `set` (kInSet) or outside it.
  template <bool kInSet>
  Tally RowTally(uint32_t candidate, const Bitset& set) const;

  const CoverageMatrix* matrix_;
  const Aggregation* aggregation_;
  int threshold_ = 1;
  bool exact_ = true;
  std::vector<CellWeight> weight_;  ///< per state, ω_s
  std::vector<Int> unit_;           ///< per state, L p_s / q_s (exact only)
  std::vector<uint32_t> state_of_;  ///< per element
  std::vector<Tally> row_weights_;  ///< per candidate
};

}  // namespace vantage::detail
