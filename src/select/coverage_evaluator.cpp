// Coverage of a union of observation sets (SYSTEM.md, coverage metric).
#include <algorithm>

#include "vantage/error.hpp"
#include "vantage/select.hpp"

namespace vantage {

CoverageEvaluator::CoverageEvaluator(std::span<const Observation> observations,
                                     size_t reference_size)
    : observations_(observations), reference_size_(reference_size) {}

size_t CoverageEvaluator::CoveredCount(std::span<const uint32_t> chosen) const {
  // |(∪ O_i) ∩ R|: reference_indices are indices into R, so mark them.
  std::vector<bool> seen(reference_size_, false);
  size_t count = 0;
  for (const uint32_t c : chosen) {
    VANTAGE_CHECK(c < observations_.size());
    for (const uint32_t cell : observations_[c].reference_indices) {
      VANTAGE_CHECK(cell < reference_size_);
      if (!seen[cell]) {
        seen[cell] = true;
        ++count;
      }
    }
  }
  return count;
}

double CoverageEvaluator::Coverage(std::span<const uint32_t> chosen) const {
  if (reference_size_ == 0) return 0.0;
  return static_cast<double>(CoveredCount(chosen)) / static_cast<double>(reference_size_);
}

double CoverageEvaluator::PaperCoverage(std::span<const uint32_t> chosen) const {
  // |∪ O_i| / |R|: the cells in R plus the distinct keys seen outside R, each counted once.
  if (reference_size_ == 0) return 0.0;
  std::vector<uint64_t> outside;
  for (const uint32_t c : chosen) {
    VANTAGE_CHECK(c < observations_.size());
    const std::vector<uint64_t>& keys = observations_[c].outside_keys;
    outside.insert(outside.end(), keys.begin(), keys.end());
  }
  std::sort(outside.begin(), outside.end());
  const size_t distinct_outside =
      static_cast<size_t>(std::unique(outside.begin(), outside.end()) - outside.begin());
  return static_cast<double>(CoveredCount(chosen) + distinct_outside) /
         static_cast<double>(reference_size_);
}

}  // namespace vantage
