#pragma once
/// The visibility matrix as the selection methods use it: candidates × elements, where an element
/// is a class of reference cells that exactly the same candidates see, weighted by its cell count.
/// Cells that no candidate sees are dropped. Coverage of any set of candidates is unchanged by the
/// merge (it is a sum of weights of the covered elements), so every method stays exact.
/// A scene with states stacks one such matrix per state: the elements of state 0, then those of
/// state 1, ...; an element never mixes cells of two states.
#include <cstdint>
#include <span>
#include <vector>

#include "vantage/visibility.hpp"

namespace vantage::detail {

/// A set of elements as 64-bit words (bit e of word e / 64).
using Bitset = std::vector<uint64_t>;

/// Whether `element` is in `set`.
inline bool Contains(const Bitset& set, uint32_t element) {
  return (set[element >> 6] >> (element & 63)) & 1;
}

/// One state of a stacked matrix: one observation set per candidate (indices into the state's R,
/// the candidates in the same order in every state) and |R| of the state.
struct StateBlock {
  std::span<const Observation> observations;
  size_t reference_size = 0;
};

/// Partition refinement: splits `item_count` items into classes of items that belong to exactly
/// the same `sets` (each a sorted list of unique item indices < item_count). Returns the class of
/// every item: -1 for items in no set, otherwise classes numbered 0, 1, ... in order of their first
/// (lowest) item. O(total set size + item_count), deterministic.
std::vector<int64_t> RefinePartition(size_t item_count,
                                     std::span<const std::span<const uint32_t>> sets);

class CoverageMatrix {
 public:
  /// Builds the merged matrix of one state. Throws InternalError when a reference index is >=
  /// reference_size or an observation's indices are not sorted and unique (its contract).
  CoverageMatrix(std::span<const Observation> observations, size_t reference_size);
  /// Stacks the merged matrices of several states (at least one, each with the same number of
  /// candidates); with one state it is the matrix above.
  explicit CoverageMatrix(std::span<const StateBlock> states);
  /// Point density (docs/constraints.md, "Point density"): the matrix in which a candidate's
  /// entry for a cell carries its pixels there, capped at `min_points` (Count), and a cell counts
  /// once the chosen sensors' counts add up to min_points. Elements are the cells with the same
  /// capped count from every candidate; cells that all candidates together cannot bring to
  /// min_points are dropped. Needs every observation's reference_hits (has_point_counts).
  CoverageMatrix(std::span<const Observation> observations,
                 size_t reference_size,
                 uint32_t min_points);
  /// The point-density matrices of several states (each as the one above), stacked.
  CoverageMatrix(std::span<const StateBlock> states, uint32_t min_points);

  size_t candidate_count() const { return rows_.size(); }
  size_t element_count() const { return weights_.size(); }
  /// |R| (stacked: the sum over the states).
  size_t reference_size() const { return reference_size_; }
  size_t state_count() const { return state_sizes_.size(); }
  /// |R_s| of state s.
  size_t StateReferenceSize(size_t state) const { return state_sizes_[state]; }
  /// The elements of state s are [StateBegin(s), StateBegin(s + 1)).
  uint32_t StateBegin(size_t state) const { return state_begin_[state]; }
  /// 64-bit words of a Bitset over the elements.
  size_t word_count() const { return word_count_; }
  /// Reference cells seen by at least one candidate (= sum of all element weights).
  uint64_t seen_weight() const { return seen_weight_; }
  /// Sorted element ids seen by a candidate.
  const std::vector<uint32_t>& Row(uint32_t candidate) const { return rows_[candidate]; }
  /// Whether entries carry point counts (the min-points matrix); else every Count is 1.
  bool has_counts() const { return !counts_.empty(); }
  /// What entry j of Row(candidate) adds towards the threshold: its capped pixels, or 1.
  uint32_t Count(uint32_t candidate, size_t j) const {
    return counts_.empty() ? 1 : counts_[candidate][j];
  }
  /// Count(candidate, j) for every j (empty when !has_counts()).
  std::span<const uint32_t> Counts(uint32_t candidate) const {
    return counts_.empty() ? std::span<const uint32_t>() : std::span(counts_[candidate]);
  }
  std::span<const std::vector<uint32_t>> rows() const { return rows_; }
  /// Every element's Weight.
  std::span<const uint32_t> weights() const { return weights_; }
  /// Cells in an element.
  uint32_t Weight(uint32_t element) const { return weights_[element]; }
  /// Cells seen by a candidate alone (= |O_i|).
  uint64_t RowWeight(uint32_t candidate) const { return row_weights_[candidate]; }
  /// Whether rows are also held as bitsets (false when that would take too much memory).
  bool is_dense() const { return !bits_.empty(); }

  Bitset EmptySet() const { return Bitset(word_count_, 0); }
  /// Weight of the elements of `candidate` not in `covered`.
  uint64_t Gain(uint32_t candidate, const Bitset& covered) const;
  /// Weight of the elements of `candidate` that are in `set`.
  uint64_t WeightIn(uint32_t candidate, const Bitset& set) const;
  /// WeightIn for a `set` that is empty outside the listed words (sorted, unique): only those
  /// words are read, so a small set costs its words, not the row's.
  uint64_t WeightInWords(uint32_t candidate,
                         const Bitset& set,
                         std::span<const uint32_t> words) const;
  /// The row of `candidate` as word_count() words (dense matrices only, else nullptr).
  const uint64_t* RowBits(uint32_t candidate) const {
    return is_dense() ? Bits(candidate) : nullptr;
  }
  /// covered |= row(candidate).
  void AddTo(uint32_t candidate, Bitset* covered) const;
  /// Total weight of the elements in `set`.
  uint64_t SetWeight(const Bitset& set) const;
  /// Cells covered by the union of `chosen` (duplicates allowed).
  uint64_t CoveredWeight(std::span<const uint32_t> chosen) const;
  /// Whether row(a) ⊆ row(b).
  bool IsSubset(uint32_t a, uint32_t b) const;

 private:
  const uint64_t* Bits(uint32_t candidate) const { return bits_.data() + candidate * word_count_; }
  /// Weight of the elements of `candidate` that are in `set` (kInSet) or not in it.
  template <bool kInSet>
  uint64_t RowWeightWhere(uint32_t candidate, const Bitset& set) const;
  /// Weight of the elements of word w set in `bits`.
  uint64_t WordWeight(size_t w, uint64_t bits) const;
  /// Weight of the elements of `row` & (`set` ^ flip) over all words (flip 0: in `set`; ~0: not
  /// in it): popcounts, and those of the weights' bit planes where an element weighs more.
  uint64_t DenseWeight(const uint64_t* row, const uint64_t* set, uint64_t flip) const;
  /// Word count, unit weights and the dense bitsets, once rows_ and weights_ are set.
  void Finish();

  size_t reference_size_ = 0;
  std::vector<size_t> state_sizes_;
  std::vector<uint32_t> state_begin_{0};  ///< state_count() + 1 entries
  size_t word_count_ = 0;
  uint64_t seen_weight_ = 0;
  bool unit_weights_ = true;
  std::vector<uint32_t> weights_;
  std::vector<std::vector<uint32_t>> rows_;
  std::vector<std::vector<uint32_t>> counts_;  ///< parallel to rows_ (min-points), or empty
  std::vector<uint64_t> row_weights_;
  std::vector<uint64_t> bits_;  ///< candidate_count × word_count, or empty (sparse mode)
  /// The weights above one cell by bit planes, so that a weighted sum over a word is
  /// popcount(bits) + sum_b 2^b popcount(bits & plane b): the words holding an element heavier
  /// than one (extra_words_, increasing), word w's slot among them (extra_slot_, kNoSlot for
  /// none) and each slot's planes of weight - 1 (extra_planes_[slot * extra_plane_count_ + b]).
  static constexpr uint32_t kNoSlot = UINT32_MAX;
  uint32_t extra_plane_count_ = 0;
  std::vector<uint32_t> extra_words_;
  std::vector<uint32_t> extra_slot_;
  std::vector<uint64_t> extra_planes_;
};

}  // namespace vantage::detail
