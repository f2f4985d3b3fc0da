#pragma once
/// Exact culling for observe: only pixels whose centre ray can reach a cell of R are traced.
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

/// The eight corners of a box in the body frame (x, y, z by corner; corner k takes the box's max
/// on axis a where bit a of k is set), equal bit for bit to `body_from_world * corner`
/// (Pose::operator*) with the products that corners share computed once.
struct BodyCorners {
  double x[8], y[8], z[8];
};
BodyCorners CornersInBody(const Pose& body_from_world, const Aabb& bounds);

/// The pixels to trace for one camera, row by row, each pixel once: the union of the projected
/// rectangles of the blocks (padded by one pixel), or the whole image when `cull` is false.
std::vector<RowSpan> SpansToTrace(const Candidate& candidate, const std::vector<Aabb>& blocks, bool cull);

}  // namespace vantage::detail
