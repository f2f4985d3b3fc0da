#include "vantage/reference.hpp"

#include <fmt/format.h>
#include <tbb/blocked_range.h>
#include <tbb/enumerable_thread_specific.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>

#include "util/cell_size.hpp"
#include "vantage/error.hpp"

namespace vantage {
namespace {

// Everything below works in cell units (q = p / F), the same division VoxelKeyOf makes, so that
// cell k is exactly [k, k+1) per axis and boundary comparisons are exact.
using Cell = std::array<int64_t, 3>;

// Separating-axis test of a triangle against the closed box [lo, hi] (Akenine-Möller). Used only
// to prune blocks of cells, so closed (conservative) is right here.
bool TriangleOverlapsClosedBox(const Vec3 (&tri)[3], const Vec3& lo, const Vec3& hi) {
  const Vec3 center = 0.5 * (lo + hi);
  const Vec3 half = 0.5 * (hi - lo);
  const Vec3 v[3] = {tri[0] - center, tri[1] - center, tri[2] - center};
  for (int axis = 0; axis < 3; ++axis) {
    const double mn = std::min({v[0][axis], v[1][axis], v[2][axis]});
    const double mx = std::max({v[0][axis], v[1][axis], v[2][axis]});
    if (mn > half[axis] || mx < -half[axis]) return false;
  }
  const Vec3 e[3] = {v[1] - v[0], v[2] - v[1], v[0] - v[2]};
  const Vec3 normal = e[0].cross(e[1]);
  const double plane_d = normal.dot(v[0]);
  const double plane_r = half.dot(normal.cwiseAbs());
  if (std::abs(plane_d) > plane_r) return false;
  for (const Vec3& edge : e) {
    for (int axis = 0; axis < 3; ++axis) {
      const Vec3 a = Vec3::Unit(axis).cross(edge);
      const double p0 = a.dot(v[0]), p1 = a.dot(v[1]), p2 = a.dot(v[2]);
      const double r = half.dot(a.cwiseAbs());
      const double mn = std::min({p0, p1, p2}), mx = std::max({p0, p1, p2});
      if (mn > r || mx < -r) return false;
    }
  }
  return true;
}

// Sutherland–Hodgman clip of a convex polygon to one side of an axis plane. Points created on
// the plane get exactly the plane's coordinate, so "on the upper face" is decided exactly.
void ClipAxis(std::vector<Vec3>* poly, int axis, double bound, bool keep_below) {
  std::vector<Vec3> out;
  out.reserve(poly->size() + 2);
  const auto inside = [&](const Vec3& p) { return keep_below ? p[axis] <= bound : p[axis] >= bound; };
  for (size_t i = 0; i < poly->size(); ++i) {
    const Vec3& a = (*poly)[i];
    const Vec3& b = (*poly)[(i + 1) % poly->size()];
    const bool a_in = inside(a), b_in = inside(b);
    if (a_in) out.push_back(a);
    if (a_in != b_in) {
      const double t = (bound - a[axis]) / (b[axis] - a[axis]);
      Vec3 p = a + t * (b - a);
      p[axis] = bound;
      out.push_back(p);
    }
  }
  poly->swap(out);
}

// Exact test against the half-open cell [k, k+1)³: clip the triangle to the closed cell; the
// closed triangle meets the half-open cell unless the clipped convex polygon is empty or lies
// entirely in one upper face (then its relative interior avoids every upper face otherwise).
bool TriangleTouchesHalfOpenCell(const Vec3 (&tri)[3], const Cell& k, std::vector<Vec3>* poly) {
  poly->assign(std::begin(tri), std::end(tri));
  for (int axis = 0; axis < 3 && !poly->empty(); ++axis) {
    ClipAxis(poly, axis, static_cast<double>(k[axis]), false);
    if (!poly->empty()) ClipAxis(poly, axis, static_cast<double>(k[axis] + 1), true);
  }
  if (poly->empty()) return false;
  for (int axis = 0; axis < 3; ++axis) {
    const double upper = static_cast<double>(k[axis] + 1);
    if (std::all_of(poly->begin(), poly->end(), [&](const Vec3& p) { return p[axis] == upper; }))
      return false;
  }
  return true;
}

void VisitBlock(const Vec3 (&tri)[3], const Cell& lo, const Cell& hi, std::vector<Vec3>* poly,
                std::vector<uint64_t>* keys) {
  const int64_t count = (hi[0] - lo[0] + 1) * (hi[1] - lo[1] + 1) * (hi[2] - lo[2] + 1);
  if (count <= 8) {
    for (int64_t x = lo[0]; x <= hi[0]; ++x)
      for (int64_t y = lo[1]; y <= hi[1]; ++y)
        for (int64_t z = lo[2]; z <= hi[2]; ++z) {
          const Cell c{x, y, z};
          if (TriangleTouchesHalfOpenCell(tri, c, poly)) keys->push_back(PackVoxel(c));
        }
    return;
  }
  const Vec3 box_lo(lo[0], lo[1], lo[2]);
  const Vec3 box_hi(hi[0] + 1, hi[1] + 1, hi[2] + 1);
  if (!TriangleOverlapsClosedBox(tri, box_lo, box_hi)) return;
  int axis = 0;
  for (int a = 1; a < 3; ++a)
    if (hi[a] - lo[a] > hi[axis] - lo[axis]) axis = a;
  const int64_t mid = lo[axis] + (hi[axis] - lo[axis]) / 2;
  Cell first_hi = hi, second_lo = lo;
  first_hi[axis] = mid;
  second_lo[axis] = mid + 1;
  VisitBlock(tri, lo, first_hi, poly, keys);
  VisitBlock(tri, second_lo, hi, poly, keys);
}

}  // namespace

void ReferenceOptions::Validate() const {
  if (const std::string problem = detail::CellSizeProblem(cell_size); !problem.empty())
    throw InputError(problem);
}

int64_t Reference::IndexOf(uint64_t key) const {
  const auto it = std::lower_bound(keys.begin(), keys.end(), key);
  if (it == keys.end() || *it != key) return -1;
  return it - keys.begin();
}

void AppendTriangleCells(const Vec3& a, const Vec3& b, const Vec3& c, double cell_size,
                         std::vector<uint64_t>* keys) {
  const Vec3 tri[3] = {a / cell_size, b / cell_size, c / cell_size};
  Cell lo, hi;
  for (int axis = 0; axis < 3; ++axis) {
    lo[axis] = static_cast<int64_t>(std::floor(std::min({tri[0][axis], tri[1][axis], tri[2][axis]})));
    hi[axis] = static_cast<int64_t>(std::floor(std::max({tri[0][axis], tri[1][axis], tri[2][axis]})));
  }
  VANTAGE_CHECK(VoxelIndexFits(lo) && VoxelIndexFits(hi));
  std::vector<Vec3> poly;
  VisitBlock(tri, lo, hi, &poly, keys);
}

void CheckTargetsFitGrid(const Scene& scene, double cell_size) {
  Aabb bounds;
  bool any = false;
  for (const SceneObject& object : scene.objects) {
    if (!object.is_target() || object.mesh.triangles.empty()) continue;
    bounds.Extend(object.mesh.Bounds());
    any = true;
  }
  if (!any) return;
  for (const Vec3& corner : {bounds.min, bounds.max}) {
    if (!corner.allFinite() || !VoxelIndexFits(VoxelKeyOf(corner, cell_size)))
      throw InputError(fmt::format(
          "targets reach ({:.3f}, {:.3f}, {:.3f}) m, beyond the ±{:.0f} cells that a cell size of "
          "{} m can index — move the targets near the origin or use a larger cell size",
          corner.x(), corner.y(), corner.z(), static_cast<double>(kVoxelAxisOffset), cell_size));
  }
}

double EstimateReferenceCells(const Scene& scene, double cell_size) {
  if (!std::isfinite(cell_size) || cell_size <= 0) return 0.0;
  double area_cells = 0, edge_cells = 0, triangles = 0;
  for (const SceneObject& object : scene.objects) {
    if (!object.is_target()) continue;
    const TriangleMesh& mesh = object.mesh;
    for (const auto& t : mesh.triangles) {
      const Vec3& a = mesh.vertices[t[0]];
      const Vec3& b = mesh.vertices[t[1]];
      const Vec3& c = mesh.vertices[t[2]];
      // |cross| = 2 · area; its 1-norm is 2 · area · (|nx| + |ny| + |nz|).
      area_cells += 0.5 * (b - a).cross(c - a).lpNorm<1>();
      edge_cells += (b - a).norm() + (c - b).norm() + (a - c).norm();
      triangles += 1;
    }
  }
  return area_cells / (cell_size * cell_size) + std::sqrt(3.0) * edge_cells / cell_size + triangles;
}

Reference BuildReference(const Scene& scene, const ReferenceOptions& options) {
  options.Validate();
  struct Tri {
    const TriangleMesh* mesh;
    size_t index;
  };
  std::vector<Tri> triangles;
  for (const SceneObject& object : scene.objects) {
    if (!object.is_target()) continue;
    for (size_t i = 0; i < object.mesh.triangles.size(); ++i) triangles.push_back({&object.mesh, i});
  }
  if (triangles.empty())
    throw InputError("the scene has no target surface — mark at least one object as a target");
  CheckTargetsFitGrid(scene, options.cell_size);

  tbb::enumerable_thread_specific<std::vector<uint64_t>> per_thread;
  tbb::parallel_for(tbb::blocked_range<size_t>(0, triangles.size(), 1024),
                    [&](const tbb::blocked_range<size_t>& range) {
                      std::vector<uint64_t>& keys = per_thread.local();
                      for (size_t i = range.begin(); i != range.end(); ++i) {
                        const TriangleMesh& mesh = *triangles[i].mesh;
                        const auto& t = mesh.triangles[triangles[i].index];
                        AppendTriangleCells(mesh.vertices[t[0]], mesh.vertices[t[1]],
                                            mesh.vertices[t[2]], options.cell_size, &keys);
                      }
                    });
  Reference reference;
  reference.cell_size = options.cell_size;
  for (const auto& keys : per_thread) reference.keys.insert(reference.keys.end(), keys.begin(), keys.end());
  // Sorting makes the result independent of how the work was split between threads.
  std::sort(reference.keys.begin(), reference.keys.end());
  reference.keys.erase(std::unique(reference.keys.begin(), reference.keys.end()), reference.keys.end());
  return reference;
}

}  // namespace vantage
