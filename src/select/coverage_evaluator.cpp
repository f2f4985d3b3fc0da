// Coverage of a union of observation sets (SYSTEM.md, coverage metric), and k-coverage: the cells
// seen by at least k of the chosen sensors.
#include <algorithm>

#include "vantage/error.hpp"
#include "vantage/select.hpp"

namespace vantage {

CoverageEvaluator::CoverageEvaluator(std::span<const Observation> observations,
                                     size_t reference_size)
    : observations_(observations), reference_size_(reference_size) {}

size_t CoverageEvaluator::CoveredCount(std::span<const uint32_t> chosen, int k) const {
  VANTAGE_CHECK(k >= 1);
  // |(∪ O_i) ∩ R|: reference_indices are indices into R, so count how often each is seen.
  std::vector<uint32_t> seen(reference_size_, 0);
  size_t count = 0;
  for (const uint32_t c : chosen) {
    VANTAGE_CHECK(c < observations_.size());
    for (const uint32_t cell : observations_[c].reference_indices) {
      VANTAGE_CHECK(cell < reference_size_);
      if (++seen[cell] == static_cast<uint32_t>(k)) ++count;
    }
  }
  return count;
}

size_t CoverageEvaluator::PointCoveredCount(std::span<const uint32_t> chosen,
                                            uint32_t min_points) const {
  VANTAGE_CHECK(min_points >= 1);
  std::vector<uint64_t> points(reference_size_, 0);
  size_t count = 0;
  for (const uint32_t c : chosen) {
    VANTAGE_CHECK(c < observations_.size() && observations_[c].has_point_counts());
    const Observation& o = observations_[c];
    for (size_t j = 0; j < o.reference_indices.size(); ++j) {
      const uint32_t cell = o.reference_indices[j];
      VANTAGE_CHECK(cell < reference_size_);
      const uint64_t before = points[cell];
      points[cell] += o.reference_hits[j];
      if (before < min_points && points[cell] >= min_points) ++count;
    }
  }
  return count;
}

double CoverageEvaluator::PointCoverage(std::span<const uint32_t> chosen,
                                        uint32_t min_points) const {
  if (reference_size_ == 0) return 0.0;
  return static_cast<double>(PointCoveredCount(chosen, min_points)) /
         static_cast<double>(reference_size_);
}

double CoverageEvaluator::Coverage(std::span<const uint32_t> chosen, int k) const {
  if (reference_size_ == 0) return 0.0;
  return static_cast<double>(CoveredCount(chosen, k)) / static_cast<double>(reference_size_);
}

double CoverageEvaluator::PaperCoverage(std::span<const uint32_t> chosen, int k) const {
  // |∪ O_i| / |R|: the cells in R plus the distinct keys seen outside R, each counted once
  // (for k-coverage: the keys that at least k of the chosen see).
  if (reference_size_ == 0) return 0.0;
  std::vector<uint64_t> outside;
  for (const uint32_t c : chosen) {
    VANTAGE_CHECK(c < observations_.size());
    const std::vector<uint64_t>& keys = observations_[c].outside_keys;
    outside.insert(outside.end(), keys.begin(), keys.end());
  }
  std::sort(outside.begin(), outside.end());
  size_t outside_count = 0;
  for (size_t i = 0; i < outside.size();) {
    size_t j = i;
    while (j < outside.size() && outside[j] == outside[i]) ++j;
    if (j - i >= static_cast<size_t>(k)) ++outside_count;
    i = j;
  }
  return static_cast<double>(CoveredCount(chosen, k) + outside_count) /
         static_cast<double>(reference_size_);
}

}  // namespace vantage
