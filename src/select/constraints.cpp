// Installation constraints (issue 20, docs/constraints.md): overlaps of observation sets, the
// interference pairs, the overlap graph and what a constellation breaks.
#include "vantage/constraints.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <numeric>
#include <tuple>

#include "vantage/error.hpp"

namespace vantage {
namespace {

// For every a in `among` (positions p), the cells it shares with each later b (positions q > p):
// visit(p, q, common) for every pair with common >= 1, until it returns false. Through an index of
// seers per cell, so the cost is the sum over cells of their seers squared, never |among|² set
// intersections.
template <typename Visit>
void ForEachOverlap(std::span<const Observation> observations, std::span<const uint32_t> among,
                    bool illuminated, const Visit& visit) {
  const auto cells_of = [&](uint32_t i) -> std::span<const uint32_t> {
    return illuminated ? IlluminatedCells(observations[i])
                       : std::span<const uint32_t>(observations[i].reference_indices);
  };
  uint32_t cell_count = 0;
  for (const uint32_t i : among) {
    const std::span<const uint32_t> cells = cells_of(i);
    if (!cells.empty()) cell_count = std::max(cell_count, cells.back() + 1);
  }
  std::vector<std::vector<uint32_t>> seers(cell_count);  // positions in `among`, ascending
  for (uint32_t p = 0; p < among.size(); ++p) {
    for (const uint32_t cell : cells_of(among[p])) seers[cell].push_back(p);
  }
  std::vector<uint64_t> common(among.size(), 0);
  std::vector<uint32_t> touched;
  for (uint32_t p = 0; p < among.size(); ++p) {
    for (const uint32_t cell : cells_of(among[p])) {
      const std::vector<uint32_t>& s = seers[cell];
      for (auto it = std::upper_bound(s.begin(), s.end(), p); it != s.end(); ++it) {
        if (common[*it]++ == 0) touched.push_back(*it);
      }
    }
    std::sort(touched.begin(), touched.end());
    bool go_on = true;
    for (const uint32_t q : touched) {
      go_on = go_on && visit(p, q, common[q]);
      common[q] = 0;
    }
    if (!go_on) return;
    touched.clear();
  }
}

bool PairLess(const Conflict& x, const Conflict& y) {
  return std::tie(x.a, x.b) < std::tie(y.a, y.b);
}

}  // namespace

std::string ConflictKindName(ConflictKind kind) {
  return kind == ConflictKind::kInterference ? "interference" : "separation";
}

bool CalibrationRule::Joins(uint64_t common, uint64_t size_a, uint64_t size_b) const {
  if (common == 0) return false;
  if (min_cells) return common >= *min_cells;
  if (min_fraction) {
    return static_cast<double>(common) >=
           *min_fraction * static_cast<double>(std::min(size_a, size_b)) - 1e-9;
  }
  return true;
}

void CalibrationRule::Validate() const {
  if (min_cells.has_value() == min_fraction.has_value()) {
    throw FieldError({"calibration_overlap", "calibration_overlap_frac"},
                     "give one of calibration_overlap (cells) and calibration_overlap_frac");
  }
  if (min_cells && *min_cells < 1) {
    throw FieldError({"calibration_overlap"},
                     "calibration_overlap must be at least 1 common cell");
  }
  if (min_fraction && !(*min_fraction > 0.0 && *min_fraction <= 1.0)) {
    throw FieldError({"calibration_overlap_frac"},
                     fmt::format("calibration_overlap_frac = {} must be a fraction in (0, 1]",
                                 *min_fraction));
  }
}

void InstallConstraints::Validate(size_t candidate_count) const {
  for (size_t i = 0; i < conflicts.size(); ++i) {
    const Conflict& c = conflicts[i];
    if (c.a >= c.b || c.b >= candidate_count || (i > 0 && !PairLess(conflicts[i - 1], c))) {
      throw FieldError({"conflicts"},
                       fmt::format("conflicts: pair {} ({}, {}) must be two candidate indices "
                                   "a < b < {}, sorted and unique",
                                   i, c.a, c.b, candidate_count));
    }
  }
  if (calibration) calibration->Validate();
}

std::span<const uint32_t> IlluminatedCells(const Observation& observation) {
  return observation.plain_reference_indices.empty() ? observation.reference_indices
                                                     : observation.plain_reference_indices;
}

std::vector<Conflict> InterferenceConflicts(std::span<const Observation> observations,
                                            const std::vector<bool>& projecting, double max_overlap,
                                            size_t max_pairs) {
  VANTAGE_CHECK(projecting.size() == observations.size());
  std::vector<uint32_t> among;
  for (uint32_t i = 0; i < projecting.size(); ++i)
    if (projecting[i]) among.push_back(i);
  std::vector<Conflict> conflicts;
  ForEachOverlap(observations, among, true, [&](uint32_t p, uint32_t q, uint64_t common) {
    const uint32_t a = among[p], b = among[q];
    const double smaller = static_cast<double>(
        std::min(IlluminatedCells(observations[a]).size(), IlluminatedCells(observations[b]).size()));
    const double share = static_cast<double>(common) / smaller;
    if (share > max_overlap) conflicts.push_back({a, b, ConflictKind::kInterference, share});
    return conflicts.size() <= max_pairs;
  });
  std::sort(conflicts.begin(), conflicts.end(), PairLess);
  return conflicts;
}

void MergeConflicts(std::vector<Conflict> extra, std::vector<Conflict>* conflicts) {
  std::vector<Conflict> merged = std::move(*conflicts);
  merged.insert(merged.end(), extra.begin(), extra.end());
  std::stable_sort(merged.begin(), merged.end(), PairLess);
  merged.erase(std::unique(merged.begin(), merged.end(),
                           [](const Conflict& x, const Conflict& y) {
                             return x.a == y.a && x.b == y.b;
                           }),
               merged.end());
  *conflicts = std::move(merged);
}

std::vector<OverlapEdge> OverlapGraph(std::span<const Observation> observations,
                                      std::span<const uint32_t> among,
                                      const std::optional<CalibrationRule>& rule) {
  std::vector<OverlapEdge> edges;
  const CalibrationRule any;
  const CalibrationRule& joins = rule ? *rule : any;
  ForEachOverlap(observations, among, false, [&](uint32_t p, uint32_t q, uint64_t common) {
    const uint32_t a = among[p], b = among[q];
    if (joins.Joins(common, observations[a].reference_indices.size(),
                    observations[b].reference_indices.size()))
      edges.push_back({std::min(a, b), std::max(a, b), common});
    return true;
  });
  std::sort(edges.begin(), edges.end(), [](const OverlapEdge& x, const OverlapEdge& y) {
    return std::tie(x.a, x.b) < std::tie(y.a, y.b);
  });
  return edges;
}

ConstraintCheck CheckConstraints(std::span<const Observation> observations,
                                 std::span<const uint32_t> chosen,
                                 const InstallConstraints& constraints) {
  ConstraintCheck check;
  std::vector<uint32_t> sorted(chosen.begin(), chosen.end());
  std::sort(sorted.begin(), sorted.end());
  for (const Conflict& c : constraints.conflicts) {
    if (std::binary_search(sorted.begin(), sorted.end(), c.a) &&
        std::binary_search(sorted.begin(), sorted.end(), c.b))
      check.conflicts.push_back(c);
  }
  check.edges = OverlapGraph(observations, sorted, constraints.calibration);
  // Components by union-find over positions in `sorted`.
  std::vector<uint32_t> parent(sorted.size());
  std::iota(parent.begin(), parent.end(), 0U);
  const auto find = [&](uint32_t x) {
    while (parent[x] != x) x = parent[x] = parent[parent[x]];
    return x;
  };
  const auto position = [&](uint32_t i) {
    return static_cast<uint32_t>(std::lower_bound(sorted.begin(), sorted.end(), i) -
                                 sorted.begin());
  };
  for (const OverlapEdge& e : check.edges) {
    const uint32_t x = find(position(e.a)), y = find(position(e.b));
    if (x != y) parent[std::max(x, y)] = std::min(x, y);
  }
  std::vector<int> component_of(sorted.size(), -1);
  for (uint32_t p = 0; p < sorted.size(); ++p) {
    const uint32_t root = find(p);
    if (component_of[root] < 0) {
      component_of[root] = static_cast<int>(check.components.size());
      check.components.emplace_back();
    }
    check.components[static_cast<size_t>(component_of[root])].push_back(sorted[p]);
  }
  return check;
}

std::vector<Conflict> ConflictsAvoided(std::span<const uint32_t> chosen,
                                       const InstallConstraints& constraints) {
  std::vector<uint32_t> sorted(chosen.begin(), chosen.end());
  std::sort(sorted.begin(), sorted.end());
  std::vector<Conflict> avoided;
  for (const Conflict& c : constraints.conflicts) {
    const bool has_a = std::binary_search(sorted.begin(), sorted.end(), c.a);
    const bool has_b = std::binary_search(sorted.begin(), sorted.end(), c.b);
    if (has_a != has_b) avoided.push_back(c);
  }
  return avoided;
}

}  // namespace vantage
