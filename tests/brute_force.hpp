#pragma once
/// Brute-force checks the tests compare vantage's answers with, written independently of
/// src/select (no Feasibility, no OverlapGraph): plain loops and std::set_intersection.
#include <algorithm>
#include <cstdint>
#include <iterator>
#include <map>
#include <numeric>
#include <span>
#include <string>
#include <vector>

#include "vantage/constraints.hpp"
#include "vantage/rng.hpp"
#include "vantage/select_states.hpp"
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

/// `candidates` random visibility sets over `cells` cells, each cell seen with probability `p`
/// (with `with_hits`, 1 to 3 points there); deterministic in `seed`.
inline std::vector<Observation> RandomInstance(uint64_t seed, size_t candidates, size_t cells,
                                               double p, bool with_hits) {
  Rng rng(seed, Stream::kTest, 0);
  std::vector<Observation> obs(candidates);
  for (Observation& o : obs) {
    for (uint32_t c = 0; c < cells; ++c) {
      if (rng.Uniform01() >= p) continue;
      o.reference_indices.push_back(c);
      if (with_hits) o.reference_hits.push_back(static_cast<uint16_t>(1 + rng.Below(3)));
    }
  }
  return obs;
}

/// Random scene states; `states` views `observed` (moving the struct keeps the buffers).
struct RandomStates {
  std::vector<std::vector<Observation>> observed;
  std::vector<size_t> sizes;
  std::vector<StateObservations> states;
};

/// State s has sizes[s] cells, its candidates drawn by RandomInstance(seed + s, ...).
inline RandomStates MakeStates(uint64_t seed, std::vector<size_t> sizes, size_t candidates,
                               double p, bool with_hits) {
  RandomStates random;
  random.sizes = std::move(sizes);
  for (size_t s = 0; s < random.sizes.size(); ++s)
    random.observed.push_back(RandomInstance(seed + s, candidates, random.sizes[s], p, with_hits));
  for (size_t s = 0; s < random.sizes.size(); ++s)
    random.states.push_back({"s" + std::to_string(s), random.sizes[s], random.observed[s]});
  return random;
}

/// Cells of R that `mask` brings to `threshold` (seers, or with `points` the summed hits).
inline size_t Counted(const std::vector<Observation>& obs, uint32_t mask, uint32_t threshold,
                      bool points) {
  std::map<uint32_t, uint32_t> sum;
  for (uint32_t i = 0; i < obs.size(); ++i) {
    if (!(mask >> i & 1)) continue;
    for (size_t j = 0; j < obs[i].reference_indices.size(); ++j)
      sum[obs[i].reference_indices[j]] += points ? obs[i].reference_hits[j] : 1;
  }
  return static_cast<size_t>(std::count_if(sum.begin(), sum.end(),
                                            [&](const auto& e) { return e.second >= threshold; }));
}

/// The set of candidates as a bit mask, and back.
inline uint32_t MaskOf(const std::vector<uint32_t>& chosen) {
  uint32_t mask = 0;
  for (const uint32_t i : chosen) mask |= 1u << i;
  return mask;
}
inline std::vector<uint32_t> Members(uint32_t mask, size_t m) {
  std::vector<uint32_t> set;
  for (uint32_t i = 0; i < m; ++i)
    if (mask >> i & 1) set.push_back(i);
  return set;
}
inline int Size(uint32_t mask) { return __builtin_popcount(mask); }

/// The summed `costs` of the candidates in `mask`.
inline double CostOf(const std::vector<double>& costs, uint32_t mask) {
  double total = 0;
  for (uint32_t i = 0; i < costs.size(); ++i)
    if (mask >> i & 1) total += costs[i];
  return total;
}

}  // namespace vantage::test
