#pragma once
/// The one check of a cell size F, wherever it is given (scene file, --cell-size, the reference).
#include <string>

namespace vantage::detail {

/// "" when `cell_size` is a length the voxel grid can use: finite, positive and at most
/// kMaxWorldCoordinate (issue 15: 1e308 put ±inf cell centres into reference.ply); otherwise
/// "cell_size = X must be ..." with the fix.
std::string CellSizeProblem(double cell_size);

}  // namespace vantage::detail
