#include "util/cell_size.hpp"

#include <fmt/format.h>

#include <cmath>

#include "vantage/types.hpp"

namespace vantage::detail {

std::string CellSizeProblem(double cell_size) {
  if (!std::isfinite(cell_size) || cell_size <= 0)
    return fmt::format("cell_size = {} must be a positive length in metres (e.g. 0.005)", cell_size);
  if (cell_size < kMinCellSize)
    return fmt::format("cell_size = {:g} m is finer than the {:g} m (1 µm) vantage can resolve — "
                       "give the voxel size in metres, e.g. 0.005",
                       cell_size, kMinCellSize);
  if (cell_size > kMaxWorldCoordinate)
    return fmt::format("cell_size = {:g} m is larger than the world vantage ray casts (at most "
                       "{:g} m) — give the voxel size in metres, e.g. 0.005",
                       cell_size, kMaxWorldCoordinate);
  return {};
}

}  // namespace vantage::detail
