#pragma once
/// Symmetries of a set system (set_cover_search.cpp's orbital branching): the permutations of the
/// columns (candidates) and rows (elements) that map every column's row set onto another's, with
/// nauty (Debian libnauty2-dev) on the bipartite incidence graph. Only the select stage links
/// nauty; nothing else sees it.
#include <cstdint>
#include <span>
#include <vector>

namespace vantage::detail {

/// The column orbits of the automorphism group of a set system.
struct ColumnOrbits {
  /// Per column, the smallest column of its orbit (columns i and j are in one orbit iff some
  /// automorphism maps i to j, i.e. orbit[i] == orbit[j]).
  std::vector<uint32_t> orbit;
  /// How many columns share an orbit with another (0: no column moves, the group acts
  /// trivially on the columns).
  size_t moved_columns = 0;
  /// log10 of the group's order, as nauty reports it (rows included).
  double log10_group_size = 0;
};

/// The orbits of `columns` (each a sorted list of unique row indices < row_count) under the
/// permutations of columns and rows that preserve incidence and map each column to one of its
/// own colour (`colours`: one per column, or empty for all one colour). Deterministic; thread
/// safe (nauty's calls are serialised).
ColumnOrbits FindColumnOrbits(std::span<const std::vector<uint32_t>> columns, size_t row_count,
                              std::span<const uint32_t> colours = {});

}  // namespace vantage::detail
