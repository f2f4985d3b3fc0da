#pragma once
/// Exact culling for observe: only pixels whose centre ray can reach a cell of R are traced.
#include <cstdint>
#include <vector>

#include "vantage/candidates.hpp"
#include "vantage/reference.hpp"

namespace vantage::detail {

/// Bounds of blocks of 4³ reference cells. They cover every target surface point, because R
/// holds every cell the targets' surface passes through.
std::vector<Aabb> ReferenceBlocks(const Reference& reference);

/// Pixels [u0, u1] of image row v.
struct RowSpan {
  int v, u0, u1;
};

/// The pixels to trace for one camera, row by row, each pixel once: the union of the projected
/// rectangles of the blocks (padded by one pixel), or the whole image when `cull` is false.
std::vector<RowSpan> SpansToTrace(const Candidate& candidate, const std::vector<Aabb>& blocks, bool cull);

/// A 4 x 4 tile of the image, pixels 4 tu .. 4 tu + 3 of rows 4 tv .. 4 tv + 3, and which of
/// them to trace: bit 4 r + c is pixel (4 tu + c, 4 tv + r).
struct PixelTile {
  int tu, tv;
  uint16_t mask;
};

/// The pixels of `spans` (rows in ascending order, as SpansToTrace gives them) as 4 x 4 tiles, one
/// Embree packet each, in row-major order of tiles; each pixel once. Where a triangle is about a
/// pixel wide (a 200 k-triangle pile seen from 1.5 m), a square packet's rays stay within fewer
/// BVH leaves than 16 pixels of one row: 25 % less CPU per ray than 16 x 1 (issue 47).
std::vector<PixelTile> TilesOfSpans(const std::vector<RowSpan>& spans);

/// Pixel `lane_bit` (a bit of PixelTile::mask) of `tile`.
inline int TileU(const PixelTile& tile, int lane_bit) { return 4 * tile.tu + lane_bit % 4; }
inline int TileV(const PixelTile& tile, int lane_bit) { return 4 * tile.tv + lane_bit / 4; }

}  // namespace vantage::detail
