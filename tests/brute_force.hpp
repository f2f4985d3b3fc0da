#pragma once
/// Brute-force checks the tests compare vantage's answers with, written independently of
/// src/select (no Feasibility, no OverlapGraph): plain loops and std::set_intersection.
#include <algorithm>
#include <cstdint>
#include <iterator>
#include <numeric>
#include <span>
#include <vector>

#include "vantage/constraints.hpp"
#include "vantage/visibility.hpp"

namespace vantage::test {

/// Whether `set` satisfies `constraints`: no conflicting pair inside, and with a calibration rule
/// its overlap graph (an edge where two members see enough common cells of
/// `obs[i].reference_indices`) connected, by a union-find over pairwise intersections.
inline bool SatisfiesConstraints(std::span<const Observation> obs, std::span<const uint32_t> set,
                                 const InstallConstraints& constraints) {
  const auto in_set = [&](uint32_t i) { return std::count(set.begin(), set.end(), i) > 0; };
  for (const Conflict& c : constraints.conflicts) {
    if (in_set(c.a) && in_set(c.b)) return false;
  }
  if (!constraints.calibration || set.size() <= 1) return true;
  std::vector<size_t> group(set.size());
  std::iota(group.begin(), group.end(), size_t{0});
  for (size_t p = 0; p < set.size(); ++p) {
    for (size_t q = p + 1; q < set.size(); ++q) {
      const std::vector<uint32_t>& a = obs[set[p]].reference_indices;
      const std::vector<uint32_t>& b = obs[set[q]].reference_indices;
      std::vector<uint32_t> common;
      std::set_intersection(a.begin(), a.end(), b.begin(), b.end(), std::back_inserter(common));
      const double smaller = static_cast<double>(std::min(a.size(), b.size()));
      const bool joined =
          !common.empty() &&
          (constraints.calibration->min_cells
               ? common.size() >= *constraints.calibration->min_cells
               : common.size() >= *constraints.calibration->min_fraction * smaller - 1e-9);
      if (!joined) continue;
      const size_t from = group[q], to = group[p];
      for (size_t& g : group)
        if (g == from) g = to;
    }
  }
  return std::all_of(group.begin(), group.end(), [&](size_t g) { return g == group[0]; });
}

}  // namespace vantage::test
