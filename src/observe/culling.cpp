#include "observe/culling.hpp"

#include <algorithm>
#include <bit>
#include <cstdint>
#include <cmath>
#include <limits>
#include <map>

namespace vantage::detail {
namespace {

/// Inclusive pixel rectangle.
struct PixelRect {
  int u0, v0, u1, v1;
  bool IsEmpty() const { return u0 > u1 || v0 > v1; }
};

PixelRect FullImage(const SensorType& s) { return {0, 0, s.width - 1, s.height - 1}; }

// A projected pixel coordinate as an int, clamped on both sides before the cast: a legal focal
// length of 1e302 px (a field of view of 1e-300 rad) projects a box beside the axis to pixel
// ±1e301, or ±inf, beyond any int. The rectangle is clipped to the image afterwards.
int PixelIndex(double x) { return static_cast<int>(std::min(1e9, std::max(-1.0, x))); }

// Pixels whose centre ray can reach a point of `bounds` within [near, far]. Exact culling: a ray
// through pixel centre c hits p only if p projects to c, and the projection of a box lying in
// front of the camera is inside the bounding rectangle of its projected corners. One pixel of
// padding absorbs the float rounding of the traced rays.
PixelRect RectOfBounds(const SensorType& s, const Pose& body_from_world, const Aabb& bounds) {
  double depth_min = std::numeric_limits<double>::infinity();
  double depth_max = -depth_min;
  double u_min = depth_min, u_max = -depth_min, v_min = depth_min, v_max = -depth_min;
  const BodyCorners body = CornersInBody(body_from_world, bounds);
  for (int corner = 0; corner < 8; ++corner) {
    const double x = body.x[corner];
    depth_min = std::min(depth_min, x);
    depth_max = std::max(depth_max, x);
    // ProjectBodyPoint's arithmetic, inline: a corner at or behind the camera plane projects
    // nowhere.
    if (x > 0) {
      const double u = s.cx + s.fx * (-body.y[corner] / x);
      const double v = s.cy + s.fy * (-body.z[corner] / x);
      u_min = std::min(u_min, u);
      u_max = std::max(u_max, u);
      v_min = std::min(v_min, v);
      v_max = std::max(v_max, v);
    }
  }
  // Depth is linear, so the box's depths lie between its corners' depths.
  const double slack = 1e-6 * (1.0 + s.far);
  if (depth_max < s.near - slack || depth_min > s.far + slack) return {0, 0, -1, -1};
  if (depth_min <= 1e-9) return FullImage(s);  // the box straddles the camera plane
  const auto lo = [](double x) { return PixelIndex(std::ceil(x - 0.5) - 1); };
  const auto hi = [](double x) { return PixelIndex(std::floor(x - 0.5) + 1); };
  PixelRect r{lo(u_min), lo(v_min), hi(u_max), hi(v_max)};
  r.u0 = std::max(r.u0, 0);
  r.v0 = std::max(r.v0, 0);
  r.u1 = std::min(r.u1, s.width - 1);
  r.v1 = std::min(r.v1, s.height - 1);
  return r;
}

// Blocks of kCullBlockCells³ reference cells: their bounds cover every target surface point,
// because R holds every cell the targets' surface passes through.
constexpr int64_t kCullBlockCells = 4;

}  // namespace

// Each operation of Pose::operator* (Eigen's quaternion product: uv = q.vec x p, uv += uv,
// p + w uv + q.vec x uv, then + position) on the same operands in the same order; a component of
// uv depends on two of the corner's coordinates, so 4 values serve the 8 corners.
BodyCorners CornersInBody(const Pose& body_from_world, const Aabb& bounds) {
  const Quat& q = body_from_world.rotation;
  const double qx = q.x(), qy = q.y(), qz = q.z(), qw = q.w();
  const Vec3& t = body_from_world.position;
  const double X[2] = {bounds.min.x(), bounds.max.x()};
  const double Y[2] = {bounds.min.y(), bounds.max.y()};
  const double Z[2] = {bounds.min.z(), bounds.max.z()};
  // uv = 2 (q.vec x p): uv0 by (y, z), uv1 by (x, z), uv2 by (x, y).
  double uv0[2][2], uv1[2][2], uv2[2][2];
  for (int i = 0; i < 2; ++i) {
    for (int j = 0; j < 2; ++j) {
      uv0[i][j] = qy * Z[j] - qz * Y[i];
      uv0[i][j] += uv0[i][j];
      uv1[i][j] = qz * X[i] - qx * Z[j];
      uv1[i][j] += uv1[i][j];
      uv2[i][j] = qx * Y[j] - qy * X[i];
      uv2[i][j] += uv2[i][j];
    }
  }
  BodyCorners out;
  for (int k = 0; k < 8; ++k) {
    const int a = k & 1, b = (k >> 1) & 1, c = (k >> 2) & 1;
    const double u0 = uv0[b][c], u1 = uv1[a][c], u2 = uv2[a][b];
    out.x[k] = X[a] + qw * u0 + (qy * u2 - qz * u1) + t.x();
    out.y[k] = Y[b] + qw * u1 + (qz * u0 - qx * u2) + t.y();
    out.z[k] = Z[c] + qw * u2 + (qx * u1 - qy * u0) + t.z();
  }
  return out;
}

std::vector<Aabb> ReferenceBlocks(const Reference& reference) {
  std::map<std::array<int64_t, 3>, Aabb> blocks;
  const double f = reference.cell_size;
  for (uint64_t key : reference.keys) {
    const VoxelIndex i = UnpackVoxel(key);
    const std::array<int64_t, 3> block{i[0] >= 0 ? i[0] / kCullBlockCells : (i[0] + 1) / kCullBlockCells - 1,
                                       i[1] >= 0 ? i[1] / kCullBlockCells : (i[1] + 1) / kCullBlockCells - 1,
                                       i[2] >= 0 ? i[2] / kCullBlockCells : (i[2] + 1) / kCullBlockCells - 1};
    Aabb& bounds = blocks[block];
    const Vec3 lo(static_cast<double>(i[0]) * f, static_cast<double>(i[1]) * f, static_cast<double>(i[2]) * f);
    bounds.Extend(lo);
    bounds.Extend(lo + Vec3::Constant(f));
  }
  std::vector<Aabb> out;
  out.reserve(blocks.size());
  for (const auto& [block, bounds] : blocks) out.push_back(bounds);
  return out;
}

// The pixels to trace for one camera, row by row, each pixel once: the union of the projected
// rectangles of the blocks (exact culling), or the whole image.
std::vector<RowSpan> SpansToTrace(const Candidate& candidate, const std::vector<Aabb>& blocks, bool cull) {
  const SensorType& s = candidate.sensor;
  std::vector<RowSpan> spans;
  if (!cull) {
    for (int v = 0; v < s.height; ++v) spans.push_back({v, 0, s.width - 1});
    return spans;
  }
  const Pose body_from_world = candidate.world_from_body.Inverse();
  // The rectangles' union as a bitmap of the rows they reach, a row of 64-pixel words per image
  // row, set word by word over the rows each rectangle covers (was: a list of intervals per row,
  // sorted and merged). The maximal runs of set bits are the merged spans: overlapping or
  // touching intervals join, as before.
  std::vector<PixelRect> rects;
  int first_row = s.height, last_row = -1;
  for (const Aabb& bounds : blocks) {
    const PixelRect r = RectOfBounds(s, body_from_world, bounds);
    if (r.IsEmpty()) continue;
    rects.push_back(r);
    first_row = std::min(first_row, r.v0);
    last_row = std::max(last_row, r.v1);
  }
  if (rects.empty()) return spans;
  const size_t words = (static_cast<size_t>(s.width) + 63) / 64;
  std::vector<uint64_t> bits(words * static_cast<size_t>(last_row - first_row + 1), 0);
  const auto row_bits = [&](int v) { return bits.data() + static_cast<size_t>(v - first_row) * words; };
  for (const PixelRect& r : rects) {
    const size_t w0 = static_cast<size_t>(r.u0) / 64, w1 = static_cast<size_t>(r.u1) / 64;
    const uint64_t head = ~uint64_t{0} << (r.u0 % 64);
    const uint64_t tail = ~uint64_t{0} >> (63 - r.u1 % 64);
    for (int v = r.v0; v <= r.v1; ++v) {
      uint64_t* row = row_bits(v);
      if (w0 == w1) {
        row[w0] |= head & tail;
        continue;
      }
      row[w0] |= head;
      for (size_t w = w0 + 1; w < w1; ++w) row[w] = ~uint64_t{0};
      row[w1] |= tail;
    }
  }
  // The first pixel at or after u whose bit is `set`, or the width.
  const auto next = [&](const uint64_t* row, int u, bool set) {
    if (u >= s.width) return s.width;
    size_t w = static_cast<size_t>(u) / 64;
    uint64_t word = (set ? row[w] : ~row[w]) & (~uint64_t{0} << (u % 64));
    while (!word) {
      if (++w >= words) return s.width;
      word = set ? row[w] : ~row[w];
    }
    return std::min(s.width, static_cast<int>(w * 64) + std::countr_zero(word));
  };
  for (int v = first_row; v <= last_row; ++v) {
    const uint64_t* row = row_bits(v);
    for (int u = next(row, 0, true); u < s.width;) {
      const int end = next(row, u, false);
      spans.push_back({v, u, end - 1});
      u = next(row, end, true);
    }
  }
  return spans;
}

}  // namespace vantage::detail
