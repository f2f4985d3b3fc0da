#pragma once
/// A visibility matrix computed elsewhere (another simulator, a real capture, a set-cover
/// benchmark; issue 42) as the VisibilityFile that `vantage select`, the Python module's
/// Visibility and the .vis writer take like an observed one. Python's Visibility.from_matrix
/// builds it; scripts/vis_writer.py writes the same file in plain Python (docs/outputs.md,
/// "Writing one from any matrix").
#include <cstdint>
#include <span>
#include <string>
#include <vector>

#include "vantage/visibility_file.hpp"

namespace vantage {

/// Candidates × cells in compressed sparse rows (SciPy's CSR): row i sees the cells
/// indices[indptr[i] .. indptr[i + 1]).
struct ExternalMatrix {
  uint64_t cells = 0;                ///< |R|, the columns: 1 to kMaxExternalCells
  std::span<const int64_t> indptr;   ///< rows + 1 entries: 0, non-decreasing, indices.size()
  std::span<const int64_t> indices;  ///< within each row sorted, unique, in [0, cells)
  /// Per entry of indices, the pixels (points) whose hit lies in that cell, for --min-points:
  /// whole numbers >= 1, stored at most kMaxPointCount (which no --min-points exceeds, so no
  /// answer changes). Empty: 1 per cell seen.
  std::span<const double> counts;
  std::vector<std::string>
      names;                  ///< one per row: distinct, non-empty, printable; empty: c0, c1, ...
  std::vector<double> costs;  ///< one per row, finite, >= 0; empty: 1 each
};

/// The most cells: indices into R are 32-bit.
inline constexpr uint64_t kMaxExternalCells = uint64_t{1} << 32;

/// The matrix with placeholders for what only a scene gives (the same as scripts/vis_writer.py's):
/// scene "external matrix", seed 1, the default selection settings, R as 1 cm cells in a row
/// (CellOfExternalIndex), each candidate its own 64 × 48 "placeholder sensor" type t<i> (its cost
/// the row's, technology "external", so no projector interference) at (i, 0, 1) looking along +x.
/// InputError naming the argument (`csr: row 3 lists cell 5 twice — ...`, `cells: ...`,
/// `names: ...`, `costs[2]: ...`) for anything a .vis cannot hold, and for a matrix above 75 % of
/// the RAM, before anything is built.
VisibilityFile VisibilityOfMatrix(const ExternalMatrix& matrix);

/// The packed key of placeholder cell `index`: (i, j, k) with k fastest, 2^20 per axis, so that
/// the keys ascend with the index as R's must.
uint64_t CellOfExternalIndex(uint64_t index);

}  // namespace vantage
