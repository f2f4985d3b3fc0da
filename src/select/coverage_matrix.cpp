#include "select/coverage_matrix.hpp"

#include <algorithm>
#include <array>
#include <bit>
#include <map>

#include "vantage/error.hpp"

namespace vantage::detail {
namespace {

// Rows are also kept as bitsets (one bit per element, popcount gains) while that costs at most
// this much memory; above it (huge, unmergeable instances) the sparse rows alone are used.
constexpr size_t kMaxDenseBytes = size_t{512} << 20;

// The hot kernels of the dense weights (greedy's gains, local search's swaps): built for AVX2,
// SSE4.2 (both with the popcnt instruction) and the baseline, the loader picking the best the
// machine has. Integer sums, so every version returns the same number.
#define VANTAGE_KERNEL __attribute__((target_clones("avx2", "sse4.2", "default")))

// popcount(row & (set ^ flip)) over `words` words.
VANTAGE_KERNEL uint64_t PopcountAnd(const uint64_t* row,
                                    const uint64_t* set,
                                    uint64_t flip,
                                    size_t words) {
  uint64_t count = 0;
  for (size_t w = 0; w < words; ++w) count += std::popcount(row[w] & (set[w] ^ flip));
  return count;
}

// popcount(row & set) over the listed words.
VANTAGE_KERNEL uint64_t PopcountAndWords(const uint64_t* row,
                                         const uint64_t* set,
                                         const uint32_t* words,
                                         size_t word_count) {
  uint64_t count = 0;
  for (size_t i = 0; i < word_count; ++i) count += std::popcount(row[words[i]] & set[words[i]]);
  return count;
}

// sum_b 2^b popcount(bits & plane b) over `plane_count` planes.
VANTAGE_KERNEL uint64_t PlanesWeight(uint64_t bits, const uint64_t* planes, uint32_t plane_count) {
  uint64_t weight = 0;
  for (uint32_t b = 0; b < plane_count; ++b) {
    weight += static_cast<uint64_t>(std::popcount(bits & planes[b])) << b;
  }
  return weight;
}

}  // namespace

std::vector<int64_t> RefinePartition(size_t item_count,
                                     std::span<const std::span<const uint32_t>> sets) {
  // Class 0 holds the items of no set so far and is never reused. Each set splits every class it
  // touches into the part inside the set (moved to a fresh class) and the part outside; classes
  // emptied by a split are recycled, so at most item_count + 1 class ids are ever live.
  std::vector<uint32_t> class_of(item_count, 0);
  std::vector<size_t> class_size{item_count};
  std::vector<uint32_t> split_into{0};
  std::vector<uint64_t> split_round{0};
  std::vector<uint32_t> free_classes;
  std::vector<uint32_t> touched;
  for (size_t s = 0; s < sets.size(); ++s) {
    const uint64_t round = s + 1;
    touched.clear();
    for (const uint32_t item : sets[s]) {
      VANTAGE_CHECK(item < item_count);
      const uint32_t k = class_of[item];
      if (split_round[k] != round) {
        split_round[k] = round;
        uint32_t fresh = 0;
        if (!free_classes.empty()) {
          fresh = free_classes.back();
          free_classes.pop_back();
        } else {
          fresh = static_cast<uint32_t>(class_size.size());
          class_size.push_back(0);
          split_into.push_back(0);
          split_round.push_back(0);
        }
        split_into[k] = fresh;
        touched.push_back(k);
      }
      class_of[item] = split_into[k];
      --class_size[k];
      ++class_size[split_into[k]];
    }
    for (const uint32_t k : touched) {
      if (k != 0 && class_size[k] == 0) free_classes.push_back(k);
    }
  }
  // Number the classes by their first item so the result does not depend on recycling order.
  std::vector<int64_t> number(class_size.size(), -1);
  std::vector<int64_t> result(item_count, -1);
  int64_t next = 0;
  for (size_t item = 0; item < item_count; ++item) {
    const uint32_t k = class_of[item];
    if (k == 0) continue;
    if (number[k] < 0) number[k] = next++;
    result[item] = number[k];
  }
  return result;
}

CoverageMatrix::CoverageMatrix(std::span<const Observation> observations, size_t reference_size)
    : CoverageMatrix(std::array{StateBlock{observations, reference_size}}) {}

CoverageMatrix::CoverageMatrix(std::span<const StateBlock> states) {
  VANTAGE_CHECK(!states.empty());
  const size_t candidates = states.front().observations.size();
  rows_.resize(candidates);
  row_weights_.assign(candidates, 0);
  std::vector<std::span<const uint32_t>> sets;
  std::vector<uint32_t> last_candidate;
  for (const StateBlock& state : states) {
    VANTAGE_CHECK(state.observations.size() == candidates);
    sets.clear();
    for (const Observation& o : state.observations) {
      // Observation's contract: sorted, unique, indices into R (checked: merging relies on it).
      for (size_t k = 0; k < o.reference_indices.size(); ++k) {
        VANTAGE_CHECK(o.reference_indices[k] < state.reference_size);
        VANTAGE_CHECK(k == 0 || o.reference_indices[k - 1] < o.reference_indices[k]);
      }
      sets.emplace_back(o.reference_indices);
    }
    // The state's elements follow those of the states before it.
    std::vector<int64_t> element_of = RefinePartition(state.reference_size, sets);
    const auto first = static_cast<int64_t>(weights_.size());
    for (int64_t& e : element_of) {
      if (e < 0) continue;
      e += first;
      if (static_cast<size_t>(e) >= weights_.size()) weights_.resize(e + 1, 0);
      ++weights_[e];
      ++seen_weight_;
    }
    last_candidate.assign(weights_.size(), UINT32_MAX);
    for (size_t i = 0; i < candidates; ++i) {
      std::vector<uint32_t>& row = rows_[i];
      const size_t row_begin = row.size();
      for (const uint32_t cell : state.observations[i].reference_indices) {
        const auto e = static_cast<uint32_t>(element_of[cell]);
        if (last_candidate[e] == i) continue;
        last_candidate[e] = static_cast<uint32_t>(i);
        row.push_back(e);
      }
      if (!std::is_sorted(row.begin() + row_begin, row.end()))
        std::sort(row.begin() + row_begin, row.end());
      row_weights_[i] += state.observations[i].reference_indices.size();
    }
    reference_size_ += state.reference_size;
    state_sizes_.push_back(state.reference_size);
    state_begin_.push_back(static_cast<uint32_t>(weights_.size()));
  }
  Finish();
}

CoverageMatrix::CoverageMatrix(std::span<const Observation> observations,
                               size_t reference_size,
                               uint32_t min_points) {
  VANTAGE_CHECK(min_points >= 1);
  const size_t candidates = observations.size();
  const auto capped = [&](const Observation& o, size_t j) {
    return std::min<uint32_t>(o.reference_hits[j], min_points);
  };
  // The points all candidates together bring to each cell: below min_points it never counts.
  std::vector<uint64_t> total(reference_size, 0);
  for (const Observation& o : observations) {
    VANTAGE_CHECK(o.has_point_counts());
    for (size_t j = 0; j < o.reference_indices.size(); ++j) {
      VANTAGE_CHECK(o.reference_indices[j] < reference_size);
      VANTAGE_CHECK(j == 0 || o.reference_indices[j - 1] < o.reference_indices[j]);
      total[o.reference_indices[j]] += capped(o, j);
    }
  }
  // One set per (candidate, capped count): cells in the same sets get the same count from every
  // candidate, so they merge into one element.
  std::vector<std::vector<uint32_t>> level_sets;
  for (const Observation& o : observations) {
    std::map<uint32_t, std::vector<uint32_t>> by_count;
    for (size_t j = 0; j < o.reference_indices.size(); ++j) {
      const uint32_t cell = o.reference_indices[j];
      if (total[cell] >= min_points) by_count[capped(o, j)].push_back(cell);
    }
    for (auto& [count, cells] : by_count) level_sets.push_back(std::move(cells));
  }
  const std::vector<std::span<const uint32_t>> sets(level_sets.begin(), level_sets.end());
  const std::vector<int64_t> element_of = RefinePartition(reference_size, sets);
  for (const int64_t e : element_of) {
    if (e < 0) continue;
    if (static_cast<size_t>(e) >= weights_.size()) weights_.resize(e + 1, 0);
    ++weights_[e];
    ++seen_weight_;
  }
  rows_.resize(candidates);
  counts_.resize(candidates);
  row_weights_.assign(candidates, 0);
  std::vector<uint32_t> last_candidate(weights_.size(), UINT32_MAX);
  std::vector<std::pair<uint32_t, uint32_t>> entries;
  for (size_t i = 0; i < candidates; ++i) {
    const Observation& o = observations[i];
    entries.clear();
    for (size_t j = 0; j < o.reference_indices.size(); ++j) {
      const int64_t e = element_of[o.reference_indices[j]];
      if (e < 0) continue;
      ++row_weights_[i];
      if (last_candidate[e] == i) continue;
      last_candidate[e] = static_cast<uint32_t>(i);
      entries.emplace_back(static_cast<uint32_t>(e), capped(o, j));
    }
    std::sort(entries.begin(), entries.end());
    for (const auto& [e, count] : entries) {
      rows_[i].push_back(e);
      counts_[i].push_back(count);
    }
  }
  reference_size_ = reference_size;
  state_sizes_.push_back(reference_size);
  state_begin_.push_back(static_cast<uint32_t>(weights_.size()));
  Finish();
}

CoverageMatrix::CoverageMatrix(std::span<const StateBlock> states, uint32_t min_points) {
  VANTAGE_CHECK(!states.empty());
  const size_t candidates = states.front().observations.size();
  rows_.resize(candidates);
  counts_.resize(candidates);
  row_weights_.assign(candidates, 0);
  for (const StateBlock& state : states) {
    VANTAGE_CHECK(state.observations.size() == candidates);
    const CoverageMatrix one(state.observations, state.reference_size, min_points);
    const auto offset = static_cast<uint32_t>(weights_.size());
    weights_.insert(weights_.end(), one.weights_.begin(), one.weights_.end());
    seen_weight_ += one.seen_weight_;
    for (size_t i = 0; i < candidates; ++i) {
      for (const uint32_t e : one.rows_[i]) rows_[i].push_back(offset + e);
      counts_[i].insert(counts_[i].end(), one.counts_[i].begin(), one.counts_[i].end());
      row_weights_[i] += one.row_weights_[i];
    }
    reference_size_ += state.reference_size;
    state_sizes_.push_back(state.reference_size);
    state_begin_.push_back(static_cast<uint32_t>(weights_.size()));
  }
  Finish();
}

void CoverageMatrix::Finish() {
  unit_weights_ = std::all_of(weights_.begin(), weights_.end(), [](uint32_t w) { return w == 1; });
  word_count_ = (weights_.size() + 63) / 64;
  const size_t candidates = rows_.size();
  if (candidates * word_count_ * sizeof(uint64_t) <= kMaxDenseBytes) {
    bits_.assign(candidates * word_count_, 0);
    for (size_t i = 0; i < rows_.size(); ++i) {
      uint64_t* words = bits_.data() + i * word_count_;
      for (const uint32_t e : rows_[i]) words[e >> 6] |= uint64_t{1} << (e & 63);
    }
  }
  // Every element weighs at least one cell: a weight is the popcount plus, in the words that
  // hold a heavier element, the bit planes of weight - 1.
  const uint32_t max_weight =
      weights_.empty() ? 1 : *std::max_element(weights_.begin(), weights_.end());
  extra_plane_count_ = static_cast<uint32_t>(std::bit_width(max_weight - 1));
  extra_slot_.assign(word_count_, kNoSlot);
  extra_words_.clear();
  extra_planes_.clear();
  for (size_t e = 0; e < weights_.size(); ++e) {
    VANTAGE_CHECK(weights_[e] >= 1);
    if (weights_[e] == 1) continue;
    const auto w = static_cast<uint32_t>(e >> 6);
    if (extra_slot_[w] == kNoSlot) {
      extra_slot_[w] = static_cast<uint32_t>(extra_words_.size());
      extra_words_.push_back(w);
      extra_planes_.resize(extra_planes_.size() + extra_plane_count_, 0);
    }
    uint64_t* planes = extra_planes_.data() + size_t{extra_slot_[w]} * extra_plane_count_;
    for (uint32_t b = 0; b < extra_plane_count_; ++b) {
      if (((weights_[e] - 1) >> b) & 1) planes[b] |= uint64_t{1} << (e & 63);
    }
  }
}

uint64_t CoverageMatrix::DenseWeight(const uint64_t* row,
                                     const uint64_t* set,
                                     uint64_t flip) const {
  uint64_t weight = PopcountAnd(row, set, flip, word_count_);
  for (size_t i = 0; i < extra_words_.size(); ++i) {
    const uint32_t w = extra_words_[i];
    const uint64_t bits = row[w] & (set[w] ^ flip);
    if (bits != 0)
      weight +=
          PlanesWeight(bits, extra_planes_.data() + i * extra_plane_count_, extra_plane_count_);
  }
  return weight;
}

uint64_t CoverageMatrix::WordWeight(size_t w, uint64_t bits) const {
  if (unit_weights_) return static_cast<uint64_t>(std::popcount(bits));
  uint64_t weight = 0;
  while (bits) {
    weight += weights_[w * 64 + std::countr_zero(bits)];
    bits &= bits - 1;
  }
  return weight;
}

template <bool kInSet>
uint64_t CoverageMatrix::RowWeightWhere(uint32_t candidate, const Bitset& set) const {
  uint64_t weight = 0;
  if (!is_dense()) {
    for (const uint32_t e : rows_[candidate]) {
      if (Contains(set, e) == kInSet) weight += weights_[e];
    }
    return weight;
  }
  return DenseWeight(Bits(candidate), set.data(), kInSet ? 0 : ~uint64_t{0});
}

uint64_t CoverageMatrix::Gain(uint32_t candidate, const Bitset& covered) const {
  return RowWeightWhere<false>(candidate, covered);
}

uint64_t CoverageMatrix::WeightIn(uint32_t candidate, const Bitset& set) const {
  return RowWeightWhere<true>(candidate, set);
}

uint64_t CoverageMatrix::WeightInWords(uint32_t candidate,
                                       const Bitset& set,
                                       std::span<const uint32_t> words) const {
  if (!is_dense()) return WeightIn(candidate, set);
  const uint64_t* row = Bits(candidate);
  uint64_t weight = PopcountAndWords(row, set.data(), words.data(), words.size());
  // The heavier elements: over the fewer of the listed words and the words holding one (`set`
  // is empty outside the listed words).
  const auto add_extra = [&](uint32_t w, uint32_t slot) {
    const uint64_t bits = row[w] & set[w];
    if (bits != 0)
      weight += PlanesWeight(bits, extra_planes_.data() + size_t{slot} * extra_plane_count_,
                             extra_plane_count_);
  };
  if (extra_words_.size() <= words.size()) {
    for (size_t i = 0; i < extra_words_.size(); ++i)
      add_extra(extra_words_[i], static_cast<uint32_t>(i));
  } else {
    for (const uint32_t w : words) {
      if (extra_slot_[w] != kNoSlot) add_extra(w, extra_slot_[w]);
    }
  }
  return weight;
}

void CoverageMatrix::AddTo(uint32_t candidate, Bitset* covered) const {
  if (!is_dense()) {
    for (const uint32_t e : rows_[candidate]) (*covered)[e >> 6] |= uint64_t{1} << (e & 63);
    return;
  }
  const uint64_t* row = Bits(candidate);
  for (size_t w = 0; w < word_count_; ++w) (*covered)[w] |= row[w];
}

uint64_t CoverageMatrix::SetWeight(const Bitset& set) const {
  uint64_t weight = 0;
  for (size_t w = 0; w < word_count_; ++w) weight += WordWeight(w, set[w]);
  return weight;
}

uint64_t CoverageMatrix::CoveredWeight(std::span<const uint32_t> chosen) const {
  Bitset covered = EmptySet();
  uint64_t weight = 0;
  for (const uint32_t c : chosen) {
    weight += Gain(c, covered);
    AddTo(c, &covered);
  }
  return weight;
}

bool CoverageMatrix::IsSubset(uint32_t a, uint32_t b) const {
  if (rows_[a].size() > rows_[b].size()) return false;
  if (!is_dense())
    return std::includes(rows_[b].begin(), rows_[b].end(), rows_[a].begin(), rows_[a].end());
  const uint64_t* row_b = Bits(b);
  for (const uint32_t e : rows_[a]) {
    if (!((row_b[e >> 6] >> (e & 63)) & 1)) return false;
  }
  return true;
}

}  // namespace vantage::detail
