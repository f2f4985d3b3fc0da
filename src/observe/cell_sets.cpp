#include "observe/cell_sets.hpp"

#include <algorithm>
#include <bit>

#include "vantage/error.hpp"

namespace vantage::detail {

namespace {

// Sizes in the memory estimate are capped here (2^40 cells: far beyond any machine), so that the
// products below cannot wrap; the estimate is refused long before.
constexpr uint64_t kEstimateCap = uint64_t{1} << 40;

}  // namespace

// At most two thirds full.
size_t CellIndex::Capacity(size_t size) {
  return std::bit_ceil(std::max<size_t>(size + size / 2, 16));
}

uint64_t CellIndex::Bytes(size_t reference_size) {
  return Capacity(std::min<uint64_t>(reference_size, kEstimateCap)) *
         (sizeof(uint64_t) + sizeof(uint32_t));
}

CellIndex::CellIndex(const std::vector<uint64_t>& keys) : size_(keys.size()) {
  VANTAGE_CHECK(keys.size() <= UINT32_MAX);
  const size_t capacity = Capacity(keys.size());
  keys_.assign(capacity, kEmpty);
  indices_.assign(capacity, 0);
  mask_ = capacity - 1;
  shift_ = 64 - std::countr_zero(capacity);
  for (size_t i = 0; i < keys.size(); ++i) {
    VANTAGE_CHECK(keys[i] != kEmpty);
    size_t slot = Slot(keys[i]);
    while (keys_[slot] != kEmpty && keys_[slot] != keys[i]) slot = (slot + 1) & mask_;
    // R's keys are unique; were one repeated, the first index stands, as a merge would find it.
    if (keys_[slot] == keys[i]) continue;
    keys_[slot] = keys[i];
    indices_[slot] = static_cast<uint32_t>(i);
  }
}

void CellSet::Reset(const CellIndex& index, bool count) {
  index_ = &index;
  count_ = count;
  last_key_ = ~uint64_t{0};
  last_index_ = -1;
  // A candidate that threw before its Take left marks: the touched list finds them all.
  for (const uint32_t i : touched_) {
    marks_[i >> 6] = 0;
    if (i < counts_.size()) counts_[i] = 0;
  }
  const size_t words = (index.size() + 63) / 64;
  // Take leaves the marks and counts zero; only a larger R needs more.
  if (marks_.size() < words) marks_.resize(words, 0);
  if (count && counts_.size() < index.size()) counts_.resize(index.size(), 0);
  touched_.clear();
  outside_.clear();
}

void CellSet::Take(std::vector<uint32_t>* indices,
                   std::vector<uint16_t>* hits,
                   std::vector<uint64_t>* outside) {
  const bool with_hits = count_ && hits != nullptr;
  const size_t n = touched_.size();
  const size_t words = (index_->size() + 63) / 64;
  indices->reserve(indices->size() + n);
  if (with_hits) hits->reserve(hits->size() + n);
  // Ascending indices: read off the marks where they are few words per touched cell, else sort
  // the touched list (n log n against |R| / 64).
  const auto emit = [&](uint32_t i) {
    indices->push_back(i);
    if (with_hits) hits->push_back(counts_[i]);
    if (count_) counts_[i] = 0;
  };
  if (words <= 8 * n) {
    for (size_t w = 0; w < words; ++w) {
      uint64_t word = marks_[w];
      if (!word) continue;
      marks_[w] = 0;
      do {
        emit(static_cast<uint32_t>(w * 64 + static_cast<size_t>(std::countr_zero(word))));
        word &= word - 1;
      } while (word);
    }
  } else {
    std::sort(touched_.begin(), touched_.end());
    for (const uint32_t i : touched_) {
      marks_[i >> 6] = 0;
      emit(i);
    }
  }
  touched_.clear();
  if (outside) {
    std::sort(outside_.begin(), outside_.end());
    outside_.erase(std::unique(outside_.begin(), outside_.end()), outside_.end());
    outside->insert(outside->end(), outside_.begin(), outside_.end());
  }
  outside_.clear();
  last_key_ = ~uint64_t{0};
  last_index_ = -1;
}

uint64_t CellSet::Bytes(size_t reference_size_in, uint64_t pixels, bool count) {
  const uint64_t reference_size = std::min<uint64_t>(reference_size_in, kEstimateCap);
  pixels = std::min(pixels, kEstimateCap);
  const uint64_t cells = std::min<uint64_t>(reference_size, pixels);
  return (reference_size + 63) / 64 * 8 + (count ? reference_size * sizeof(uint16_t) : 0) +
         cells * sizeof(uint32_t) + pixels * sizeof(uint64_t);
}

CellSetsPool::Lease::Lease(CellSetsPool* pool) : pool_(pool) {
  {
    const std::lock_guard<std::mutex> lock(pool->mutex_);
    if (!pool->free_.empty()) {
      sets_ = std::move(pool->free_.back());
      pool->free_.pop_back();
    }
  }
  if (!sets_) sets_ = std::make_unique<CellSets>();
}

CellSetsPool::Lease::~Lease() {
  const std::lock_guard<std::mutex> lock(pool_->mutex_);
  pool_->free_.push_back(std::move(sets_));
}

}  // namespace vantage::detail
