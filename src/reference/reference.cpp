#include "vantage/reference.hpp"

#include <fmt/format.h>
#include <tbb/blocked_range.h>
#include <tbb/enumerable_thread_specific.h>
#include <tbb/parallel_for.h>
#include <tbb/parallel_sort.h>
#include <tbb/task_group.h>

#include <algorithm>
#include <array>
#include <atomic>
#include <bit>
#include <limits>
#include <optional>
#include <span>
#include <tuple>
#include <cmath>

#include "util/cell_size.hpp"
#include "vantage/error.hpp"
#include "vantage/mesh_weld.hpp"

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

// A triangle clipped to a cell: at most 3 * 2^6 corners, as each of the six clips at most
// doubles them (it keeps a corner and adds a crossing per edge), held without allocating.
struct Polygon {
  static constexpr size_t kMax = 3 << 6;
  std::array<Vec3, kMax> v;
  size_t n = 0;
  void Assign(const Vec3 (&tri)[3]) {
    v[0] = tri[0];
    v[1] = tri[1];
    v[2] = tri[2];
    n = 3;
  }
  std::span<const Vec3> Corners() const { return {v.data(), n}; }
};

// Sutherland–Hodgman clip of a convex polygon to one side of an axis plane, `in` into `out`.
// Points created on the plane get exactly the plane's coordinate, so "on the upper face" is
// decided exactly.
void ClipAxis(const Polygon& in, Polygon* out, int axis, double bound, bool keep_below) {
  out->n = 0;
  const auto inside = [&](const Vec3& p) { return keep_below ? p[axis] <= bound : p[axis] >= bound; };
  for (size_t i = 0; i < in.n; ++i) {
    const Vec3& a = in.v[i];
    const Vec3& b = in.v[i + 1 == in.n ? 0 : i + 1];
    const bool a_in = inside(a), b_in = inside(b);
    if (a_in) out->v[out->n++] = a;
    if (a_in != b_in) {
      const double t = (bound - a[axis]) / (b[axis] - a[axis]);
      Vec3 p = a + t * (b - a);
      p[axis] = bound;
      out->v[out->n++] = p;
    }
  }
}

// Exact test against the half-open cell [k, k+1)³: clip the triangle to the closed cell; the
// closed triangle meets the half-open cell unless the clipped convex polygon is empty or lies
// entirely in one upper face (then its relative interior avoids every upper face otherwise).
// `poly` gets the clipped polygon.
bool TriangleTouchesHalfOpenCell(const Vec3 (&tri)[3], const Cell& k, Polygon* poly) {
  Polygon scratch;
  poly->Assign(tri);
  for (int axis = 0; axis < 3 && poly->n != 0; ++axis) {
    ClipAxis(*poly, &scratch, axis, static_cast<double>(k[axis]), false);
    if (scratch.n != 0) {
      ClipAxis(scratch, poly, axis, static_cast<double>(k[axis] + 1), true);
    } else {
      poly->n = 0;
    }
  }
  if (poly->n == 0) return false;
  const std::span<const Vec3> corners = poly->Corners();
  for (int axis = 0; axis < 3; ++axis) {
    const double upper = static_cast<double>(k[axis] + 1);
    if (std::all_of(corners.begin(), corners.end(), [&](const Vec3& p) { return p[axis] == upper; }))
      return false;
  }
  return true;
}

// Whether every vertex lies in [k, k + 1) on every axis (false for a NaN).
bool InsideCell(const Vec3 (&tri)[3], const Cell& k) {
  for (const Vec3& v : tri) {
    for (int axis = 0; axis < 3; ++axis) {
      const auto low = static_cast<double>(k[axis]);
      if (!(v[axis] >= low && v[axis] < low + 1.0)) return false;
    }
  }
  return true;
}

// Whether a corner of the triangle lies in the half-open cell: then the triangle touches it,
// with no clip needed to tell.
bool CornerInCell(const Vec3 (&tri)[3], const Cell& k) {
  for (const Vec3& v : tri) {
    bool in = true;
    for (int axis = 0; axis < 3 && in; ++axis) {
      const auto low = static_cast<double>(k[axis]);
      in = v[axis] >= low && v[axis] < low + 1.0;
    }
    if (in) return true;
  }
  return false;
}

// Calls sink(cell) for each cell of [lo, hi] that the triangle touches (half-open cells), in
// x, y, z order within each block; only a cell holding none of the corners is clipped to tell.
template <typename Sink>
void VisitBlock(const Vec3 (&tri)[3], const Cell& lo, const Cell& hi, Polygon* poly,
                const Sink& sink) {
  const int64_t count = (hi[0] - lo[0] + 1) * (hi[1] - lo[1] + 1) * (hi[2] - lo[2] + 1);
  if (count <= 8) {
    // Most triangles of a fine mesh lie in one cell or straddle two: each of their cells holds
    // a corner (a third of the reference stage's samples were clips that could only say yes).
    for (int64_t x = lo[0]; x <= hi[0]; ++x)
      for (int64_t y = lo[1]; y <= hi[1]; ++y)
        for (int64_t z = lo[2]; z <= hi[2]; ++z) {
          const Cell c{x, y, z};
          if (CornerInCell(tri, c) || TriangleTouchesHalfOpenCell(tri, c, poly)) sink(c);
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
  VisitBlock(tri, lo, first_hi, poly, sink);
  VisitBlock(tri, second_lo, hi, poly, sink);
}

// Packed cell keys to their index among R's sorted keys, by open addressing (in place of a sort
// of every listed key and a binary search of R per listed key, twice). Keys are < 2^63, so all
// ones marks a free slot.
class KeyIndex {
 public:
  static constexpr uint64_t kFreeSlot = ~uint64_t{0};
  explicit KeyIndex(size_t expected) {
    size_t capacity = 16;
    while (capacity < 2 * expected) capacity *= 2;
    slots_.assign(capacity, {kFreeSlot, 0});
  }
  // Inserts `key` with `value` unless present. Grows past half full.
  void Insert(uint64_t key, int32_t value) {
    if (2 * (size_ + 1) > slots_.size()) Grow();
    Slot& slot = slots_[SlotOf(key)];
    if (slot.key == key) return;
    slot = {key, value};
    ++size_;
  }
  // The value inserted with `key`, or -1.
  int32_t At(uint64_t key) const {
    const Slot& slot = slots_[SlotOf(key)];
    return slot.key == key ? slot.value : -1;
  }
  template <typename Visit>
  void ForEachKey(const Visit& visit) const {
    for (const Slot& slot : slots_)
      if (slot.key != kFreeSlot) visit(slot.key);
  }

 private:
  struct Slot {
    uint64_t key;
    int32_t value;
  };
  // The slot holding `key`, or the free one where it would go.
  size_t SlotOf(uint64_t key) const {
    const size_t mask = slots_.size() - 1;
    // Fibonacci hashing spreads the packed x, y, z bits over the table.
    size_t i = static_cast<size_t>((key * 0x9E3779B97F4A7C15ull) >> 20) & mask;
    while (slots_[i].key != kFreeSlot && slots_[i].key != key) i = (i + 1) & mask;
    return i;
  }
  void Grow() {
    std::vector<Slot> old(2 * slots_.size(), {kFreeSlot, 0});
    old.swap(slots_);
    for (const Slot& slot : old)
      if (slot.key != kFreeSlot) slots_[SlotOf(slot.key)] = slot;
  }
  std::vector<Slot> slots_;
  size_t size_ = 0;
};

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
  Polygon poly;
  VisitBlock(tri, lo, hi, &poly, [keys](const Cell& c) { keys->push_back(PackVoxel(c)); });
}

namespace {

// Each target triangle's cells (AppendTriangleCells' keys, in its order), the targets' triangles
// in scene order (object by object, every triangle): BuildReference clips them once, and the
// exposure grid's walls and samples read the cells instead of clipping the triangles again.
struct TargetCells {
  std::vector<size_t> first;     // per object: the index of its first triangle among the targets'
  std::vector<size_t> start;     // per target triangle: its first key (and one past the last)
  std::vector<uint64_t> keys;
  std::vector<int32_t> index;    // per key: its index among R's keys (IndexAmong), -1 if not in R
  std::span<const uint64_t> Of(uint32_t object, size_t triangle) const {
    const size_t j = first[object] + triangle;
    return {keys.data() + start[j], keys.data() + start[j + 1]};
  }
  std::span<const int32_t> IndexOf(uint32_t object, size_t triangle) const {
    const size_t j = first[object] + triangle;
    return {index.data() + start[j], index.data() + start[j + 1]};
  }
};

// The listed keys' distinct values, sorted: R's keys.
std::vector<uint64_t> DistinctSorted(const std::vector<uint64_t>& listed) {
  KeyIndex seen(listed.size() / 8);
  for (const uint64_t key : listed) seen.Insert(key, 0);
  std::vector<uint64_t> keys;
  seen.ForEachKey([&](uint64_t key) { keys.push_back(key); });
  std::sort(keys.begin(), keys.end());
  return keys;
}

// Fills cells->index from R's sorted keys.
void IndexAmong(std::span<const uint64_t> r_keys, TargetCells* cells) {
  VANTAGE_CHECK(r_keys.size() < static_cast<size_t>(INT32_MAX));
  KeyIndex index(r_keys.size());
  for (size_t i = 0; i < r_keys.size(); ++i) index.Insert(r_keys[i], static_cast<int32_t>(i));
  cells->index.resize(cells->keys.size());
  tbb::parallel_for(tbb::blocked_range<size_t>(0, cells->keys.size(), 4096),
                    [&](const tbb::blocked_range<size_t>& range) {
                      for (size_t k = range.begin(); k != range.end(); ++k)
                        cells->index[k] = index.At(cells->keys[k]);
                    });
}

// The targets must fit the packed grid (CheckTargetsFitGrid).
TargetCells ListTargetCells(const Scene& scene, double cell_size) {
  TargetCells cells;
  struct Tri {
    const TriangleMesh* mesh;
    size_t index;
  };
  std::vector<Tri> triangles;
  cells.first.assign(scene.objects.size(), 0);
  for (size_t o = 0; o < scene.objects.size(); ++o) {
    cells.first[o] = triangles.size();
    if (!scene.objects[o].is_target()) continue;
    const TriangleMesh& mesh = scene.objects[o].mesh;
    for (size_t i = 0; i < mesh.triangles.size(); ++i) triangles.push_back({&mesh, i});
  }
  struct Local {
    std::vector<uint64_t> keys;
    std::vector<std::pair<size_t, size_t>> ends;  // (triangle, one past its last key)
  };
  tbb::enumerable_thread_specific<Local> per_thread;
  tbb::parallel_for(tbb::blocked_range<size_t>(0, triangles.size(), 1024),
                    [&](const tbb::blocked_range<size_t>& range) {
                      Local& local = per_thread.local();
                      for (size_t i = range.begin(); i != range.end(); ++i) {
                        const TriangleMesh& mesh = *triangles[i].mesh;
                        const auto& t = mesh.triangles[triangles[i].index];
                        AppendTriangleCells(mesh.vertices[t[0]], mesh.vertices[t[1]],
                                            mesh.vertices[t[2]], cell_size, &local.keys);
                        local.ends.emplace_back(i, local.keys.size());
                      }
                    });
  cells.start.assign(triangles.size() + 1, 0);
  for (const Local& local : per_thread) {
    size_t begin = 0;
    for (const auto& [i, end] : local.ends) {
      cells.start[i + 1] = end - begin;
      begin = end;
    }
  }
  for (size_t i = 1; i < cells.start.size(); ++i) cells.start[i] += cells.start[i - 1];
  cells.keys.resize(cells.start.back());
  for (const Local& local : per_thread) {
    size_t begin = 0;
    for (const auto& [i, end] : local.ends) {
      std::copy(local.keys.begin() + static_cast<ptrdiff_t>(begin),
                local.keys.begin() + static_cast<ptrdiff_t>(end),
                cells.keys.begin() + static_cast<ptrdiff_t>(cells.start[i]));
      begin = end;
    }
  }
  return cells;
}

}  // namespace

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

double EstimateReferenceCells(const Scene& scene, double cell_size, bool fine_triangles_by_cell) {
  if (!std::isfinite(cell_size) || cell_size <= 0) return 0.0;
  // The fine triangles' box cells, packed relative to the targets' lowest cell (21 bits an axis;
  // a wider box counts every triangle the plain way).
  Vec3 low = Vec3::Constant(std::numeric_limits<double>::infinity());
  Vec3 high = -low;
  if (fine_triangles_by_cell) {
    for (const SceneObject& object : scene.objects) {
      if (!object.is_target() || object.mesh.triangles.empty()) continue;
      const Aabb box = object.mesh.Bounds();
      low = low.cwiseMin(box.min);
      high = high.cwiseMax(box.max);
    }
    constexpr double kAxisCells = double{1 << 21} - 2;
    fine_triangles_by_cell = low.allFinite() && high.allFinite() &&
                             ((high - low) / cell_size).maxCoeff() < kAxisCells;
  }
  const Vec3 origin = fine_triangles_by_cell ? Vec3((low / cell_size).array().floor() * cell_size)
                                             : Vec3::Zero();
  std::vector<uint64_t> fine_cells;
  double area_cells = 0, edge_cells = 0, triangles = 0;
  for (const SceneObject& object : scene.objects) {
    if (!object.is_target()) continue;
    const TriangleMesh& mesh = object.mesh;
    for (const auto& t : mesh.triangles) {
      const Vec3& a = mesh.vertices[t[0]];
      const Vec3& b = mesh.vertices[t[1]];
      const Vec3& c = mesh.vertices[t[2]];
      if (fine_triangles_by_cell) {
        const Vec3 lo = a.cwiseMin(b).cwiseMin(c), hi = a.cwiseMax(b).cwiseMax(c);
        if ((hi - lo).maxCoeff() < cell_size) {
          const Eigen::Array3d first = ((lo - origin) / cell_size).array().floor().max(0.0);
          const Eigen::Array3d last = ((hi - origin) / cell_size).array().floor().max(0.0);
          for (double x = first.x(); x <= last.x(); ++x)
            for (double y = first.y(); y <= last.y(); ++y)
              for (double z = first.z(); z <= last.z(); ++z)
                fine_cells.push_back(static_cast<uint64_t>(x) << 42 |
                                     static_cast<uint64_t>(y) << 21 | static_cast<uint64_t>(z));
          continue;
        }
      }
      // |cross| = 2 · area; its 1-norm is 2 · area · (|nx| + |ny| + |nz|).
      area_cells += 0.5 * (b - a).cross(c - a).lpNorm<1>();
      edge_cells += (b - a).norm() + (c - b).norm() + (a - c).norm();
      triangles += 1;
    }
  }
  std::sort(fine_cells.begin(), fine_cells.end());
  const auto distinct = std::unique(fine_cells.begin(), fine_cells.end()) - fine_cells.begin();
  return area_cells / (cell_size * cell_size) + std::sqrt(3.0) * edge_cells / cell_size +
         triangles + static_cast<double>(distinct);
}

namespace {

// Exposure (issue 46). A point of a target's surface is exposed when, on one side of it, the point
// kContactDistance along its normal is free space (inside no closed object, no other object's
// surface in between) that reaches beyond the targets' box. The reach is decided on a grid of
// cells: the targets' box with kExposureMargin cells around it, flooded from its faces through
// the cells no surface touches and no closed object holds. A cell of R is exposed when a sample
// of its surface is.
constexpr int64_t kExposureMargin = 2;
constexpr double kContactDistance = 0.25;  // in cells: nearer geometry is contact
enum : uint8_t { kFree = 0, kWall = 1, kSolid = 2, kOutside = 3, kStateBits = 3 };
// Above the state bits, once the flood is done: the cell or a neighbour along z is outside, then
// along z and y, then in all 26 directions (ReachesOutside's question, answered per cell).
enum : uint8_t { kOutsideAlongZ = 4, kOutsideAlongZY = 8, kNearOutside = 16 };

struct ExposureBox {
  Cell lo{}, hi{};
  std::array<int64_t, 3> n{};
  uint64_t Size() const { return static_cast<uint64_t>(n[0] * n[1] * n[2]); }
  uint64_t Index(const Cell& c) const {
    return static_cast<uint64_t>(((c[0] - lo[0]) * n[1] + (c[1] - lo[1])) * n[2] + (c[2] - lo[2]));
  }
  uint64_t Column(int64_t x, int64_t y) const {
    return static_cast<uint64_t>((x - lo[0]) * n[1] + (y - lo[1]));
  }
  bool Contains(const Cell& c) const {
    for (int a = 0; a < 3; ++a)
      if (c[a] < lo[a] || c[a] > hi[a]) return false;
    return true;
  }
};

// Empty when there is no target, or the box would exceed kMaxExposureGridCells.
std::optional<ExposureBox> ExposureBoxOf(const Scene& scene, double cell_size) {
  const Aabb bounds = scene.TargetBounds();
  if (bounds.IsEmpty() || !bounds.min.allFinite() || !bounds.max.allFinite()) return std::nullopt;
  ExposureBox box;
  double cells = 1;
  for (int a = 0; a < 3; ++a) {
    box.lo[a] = FloorToInt(bounds.min[a] / cell_size) - kExposureMargin;
    box.hi[a] = FloorToInt(bounds.max[a] / cell_size) + kExposureMargin;
    cells *= static_cast<double>(box.hi[a] - box.lo[a] + 1);
    box.n[a] = box.hi[a] - box.lo[a] + 1;
  }
  if (!VoxelIndexFits(box.lo) || !VoxelIndexFits(box.hi) ||
      cells > static_cast<double>(kMaxExposureGridCells))
    return std::nullopt;
  return box;
}

// A closed, consistently oriented mesh (vertices welded by position): every directed edge a->b
// is matched by as many b->a. Its winding number tells inside from outside whichever way it
// faces: an outward box holds its inside, an inward room mesh holds nothing.
bool IsClosed(const TriangleMesh& mesh) {
  if (mesh.triangles.empty()) return false;
  VANTAGE_CHECK(mesh.vertices.size() < (size_t{1} << 31));  // a vertex and a direction: 32 bits
  const std::vector<uint32_t> welded =
      FirstEqualPositions(mesh.vertices.size(), [&](uint32_t i) { return mesh.vertices[i]; });
  // Each edge listed under its smaller vertex as (other << 1 | direction): a->b is matched by as
  // many b->a exactly when, in every list, each other vertex's directions cancel. The lists are
  // built by counting (no sort of all the edges: that was most of this test on a 53 k-triangle
  // part), and each short list is sorted alone.
  std::vector<uint32_t> start(mesh.vertices.size() + 1, 0);
  const auto for_each_edge = [&](const auto& visit) {
    for (const auto& t : mesh.triangles) {
      for (int e = 0; e < 3; ++e) {
        const uint32_t a = welded[t[e]], b = welded[t[(e + 1) % 3]];
        if (a != b) visit(std::min(a, b), std::max(a, b) << 1 | (a < b ? 0u : 1u));
      }
    }
  };
  for_each_edge([&](uint32_t low, uint32_t) { ++start[low + 1]; });
  for (size_t v = 1; v < start.size(); ++v) start[v] += start[v - 1];
  std::vector<uint32_t> listed(start.back());
  std::vector<uint32_t> filled(start.begin(), start.end() - 1);
  for_each_edge([&](uint32_t low, uint32_t entry) { listed[filled[low]++] = entry; });
  std::atomic<bool> closed = true;
  tbb::parallel_for(tbb::blocked_range<size_t>(0, mesh.vertices.size(), 4096),
                    [&](const tbb::blocked_range<size_t>& range) {
    for (size_t v = range.begin(); v != range.end() && closed.load(std::memory_order_relaxed);
         ++v) {
      const auto first = listed.begin() + start[v], last = listed.begin() + start[v + 1];
      std::sort(first, last);
      for (auto i = first; i != last;) {
        int64_t sum = 0;
        auto j = i;
        for (; j != last && *j >> 1 == *i >> 1; ++j) sum += (*j & 1) ? -1 : 1;
        if (sum != 0) {
          closed.store(false, std::memory_order_relaxed);
          return;
        }
        i = j;
      }
    }
  });
  return closed.load();
}

// A triangle in cell units, with its object and whether that object is closed.
struct CellTri {
  Vec3 v[3];
  uint32_t object;
  bool closed;
};

// Signed crossing of the vertical line through (px, py) with a triangle: its z and +1 when the
// triangle faces up (the line leaves an outward solid upwards there), -1 down; 0: no crossing.
int VerticalCrossing(const CellTri& t, double px, double py, double* z) {
  const auto edge = [](const Vec3& u, const Vec3& v, double x, double y) {
    return (v.x() - u.x()) * (y - u.y()) - (v.y() - u.y()) * (x - u.x());
  };
  const double area = edge(t.v[0], t.v[1], t.v[2].x(), t.v[2].y());
  if (area == 0 || !std::isfinite(area)) return 0;  // vertical: the line runs beside it
  const double w0 = edge(t.v[1], t.v[2], px, py) / area;
  const double w1 = edge(t.v[2], t.v[0], px, py) / area;
  const double w2 = edge(t.v[0], t.v[1], px, py) / area;
  if (w0 < 0 || w1 < 0 || w2 < 0) return 0;
  *z = w0 * t.v[0].z() + w1 * t.v[1].z() + w2 * t.v[2].z();
  return area > 0 ? 1 : -1;
}

// Whether the segment p -> q meets the closed triangle (touching counts: contact).
bool SegmentMeetsTriangle(const Vec3& p, const Vec3& q, const CellTri& t) {
  constexpr double kSlack = 1e-9;
  const Vec3 d = q - p;
  const Vec3 e1 = t.v[1] - t.v[0], e2 = t.v[2] - t.v[0];
  const Vec3 normal = e1.cross(e2);
  const double scale = normal.norm();
  if (!(scale > 0)) return false;
  const double denom = normal.dot(d);
  const double dist = normal.dot(p - t.v[0]);
  double s = 0;
  if (std::abs(denom) <= kSlack * scale * d.norm()) {
    if (std::abs(dist) > kSlack * scale) return false;  // parallel beside it
    s = 0;  // in its plane: test p itself (the segment is short; its start decides)
  } else {
    s = -dist / denom;
    if (s < -kSlack || s > 1 + kSlack) return false;
  }
  const Vec3 x = p + std::clamp(s, 0.0, 1.0) * d - t.v[0];
  // Barycentric coordinates of x in the triangle's plane.
  const double d00 = e1.dot(e1), d01 = e1.dot(e2), d11 = e2.dot(e2);
  const double d20 = x.dot(e1), d21 = x.dot(e2);
  const double det = d00 * d11 - d01 * d01;
  if (!(det > 0)) return false;
  const double v = (d11 * d20 - d01 * d21) / det;
  const double w = (d00 * d21 - d01 * d20) / det;
  return v >= -kSlack && w >= -kSlack && v + w <= 1 + kSlack;
}

// A closed object's surface crossing a vertical line: +1 facing up, -1 down (VerticalCrossing).
struct Crossing {
  uint32_t object;
  int sign;
  double z;
  bool operator<(const Crossing& o) const { return std::tie(object, z) < std::tie(o.object, o.z); }
};

// Inside a closed object: its winding number above height z (the signs of its crossings above,
// `crossings` sorted by object) is positive for one of them.
bool IsInside(const std::vector<Crossing>& crossings, double z) {
  for (size_t i = 0; i < crossings.size();) {
    int winding = 0;
    size_t j = i;
    for (; j < crossings.size() && crossings[j].object == crossings[i].object; ++j)
      if (crossings[j].z > z) winding += crossings[j].sign;
    if (winding > 0) return true;
    i = j;
  }
  return false;
}

// The triangles listed by grid cell or by column: (key << 32 | triangle), sorted by cell then
// triangle; one integer sorts twice as fast as the pair (the grid's key is < 2^26 cells).
using Listing = std::vector<uint64_t>;
static_assert(kMaxExposureGridCells <= (uint64_t{1} << 32));
uint64_t Listed(uint64_t key, uint32_t triangle) { return key << 32 | triangle; }

// Sorts a listing by its entries' value: an LSD radix sort over the bits that can vary (the
// triangle's lowest `triangle_bits`, the key's `key_bits` above bit 32), 11 at a time, in place
// of a comparison sort (the walls' listing sort was a seventh of the reference stage).
void SortListing(Listing* listing, int triangle_bits, int key_bits) {
  constexpr int kDigit = 11;
  std::vector<uint64_t> scratch(listing->size());
  const auto pass = [&](int shift, int bits) {
    std::array<uint32_t, (1 << kDigit) + 1> start{};
    const uint64_t mask = (uint64_t{1} << bits) - 1;
    for (const uint64_t entry : *listing) ++start[((entry >> shift) & mask) + 1];
    for (size_t d = 1; d < start.size(); ++d) start[d] += start[d - 1];
    for (const uint64_t entry : *listing) scratch[start[(entry >> shift) & mask]++] = entry;
    listing->swap(scratch);
  };
  for (int low = 0; low < triangle_bits; low += kDigit) pass(low, std::min(kDigit, triangle_bits - low));
  for (int low = 0; low < key_bits; low += kDigit) pass(32 + low, std::min(kDigit, key_bits - low));
}

// The bits that hold every value below `count`.
int BitsFor(uint64_t count) { return count <= 1 ? 0 : std::bit_width(count - 1); }

template <typename Visit>
void ForEachListed(const Listing& listing, uint64_t key, const Visit& visit) {
  auto it = std::lower_bound(listing.begin(), listing.end(), Listed(key, 0));
  for (; it != listing.end() && *it >> 32 == key; ++it) visit(static_cast<uint32_t>(*it));
}

class ExposureGrid {
 public:
  // The grid's first half, which needs no target cell listed: the closed objects, the triangles
  // near the box, every wall but the targets' (Finish) and the columns. It can run while
  // BuildReference lists the target cells.
  ExposureGrid(const Scene& scene, double cell_size, const ExposureBox& box)
      : scene_(scene),
        cell_size_(cell_size),
        box_(box),
        grid_(box.Size(), kFree) {
    // Closed only matters for an object reaching the box's columns (NearBox): the others are not
    // welded and sorted at all, and the rest side by side.
    closed_.assign(scene.objects.size(), 0);
    tbb::parallel_for(size_t{0}, scene.objects.size(), [&](size_t o) {
      const TriangleMesh& mesh = scene.objects[o].mesh;
      if (mesh.triangles.empty()) return;
      const Aabb bounds = mesh.Bounds();
      for (int a = 0; a < 2; ++a) {
        if (!(bounds.max[a] / cell_size >= static_cast<double>(box.lo[a]) &&
              bounds.min[a] / cell_size < static_cast<double>(box.hi[a] + 1)))
          return;
      }
      closed_[o] = IsClosed(mesh);
    });
    // Triangles are kept as references (8 bytes each), their cell coordinates made when needed.
    std::vector<TriRef> all;
    for (uint32_t o = 0; o < scene.objects.size(); ++o) {
      for (uint32_t t = 0; t < scene.objects[o].mesh.triangles.size(); ++t) all.push_back({o, t});
    }
    std::vector<uint8_t> near(all.size());
    tbb::parallel_for(tbb::blocked_range<size_t>(0, all.size(), 4096),
                      [&](const tbb::blocked_range<size_t>& range) {
                        for (size_t i = range.begin(); i != range.end(); ++i)
                          near[i] = NearBox(Tri(all[i]));
                      });
    for (size_t i = 0; i < all.size(); ++i)
      if (near[i]) tris_.push_back(all[i]);
    // In cell units once: the column and cell walks read each triangle many times.
    cell_tris_.resize(tris_.size());
    tbb::parallel_for(tbb::blocked_range<size_t>(0, tris_.size(), 4096),
                      [&](const tbb::blocked_range<size_t>& range) {
                        for (size_t i = range.begin(); i != range.end(); ++i)
                          cell_tris_[i] = Tri(tris_[i]);
                      });
    ListAndWall();
  }

  // The targets' walls from their listed cells (the same blocks BuildReference visited, not
  // clipped again), then the solids, the flood and the near-outside flags.
  void Finish(const TargetCells& target_cells) {
    tbb::enumerable_thread_specific<Listing> per_thread;
    tbb::parallel_for(tbb::blocked_range<size_t>(0, target_walls_.size(), 256),
                      [&](const tbb::blocked_range<size_t>& range) {
                        Listing& cells = per_thread.local();
                        for (size_t j = range.begin(); j != range.end(); ++j) {
                          const uint32_t i = target_walls_[j];
                          for (const uint64_t key : target_cells.Of(tris_[i].object, tris_[i].index))
                            Wall(UnpackVoxel(key), i, &cells);
                        }
                      });
    for (const Listing& cells : per_thread) cells_.insert(cells_.end(), cells.begin(), cells.end());
    // Sorted: the same listing whatever the threads did (the pairs are distinct).
    SortListing(&cells_, BitsFor(tris_.size()), BitsFor(box_.Size()));
    FillSolids();
    Flood();
    MarkNearOutside();
  }

  // Whether the surface point p (cell units) of object `object`, with unit normal n, is exposed.
  bool IsExposed(const Vec3& p, const Vec3& n, uint32_t object) const {
    for (const double side : {1.0, -1.0}) {
      const Vec3 q = p + side * kContactDistance * n;
      // The three tests are independent: the cheapest (27 grid cells) first.
      if (ReachesOutside(q) && !IsSolid(q) && !IsBlocked(p, q, object)) return true;
    }
    return false;
  }

  // Whether any sample of a surface part inside cell k can reach outside: each lies within a
  // quarter cell of the part, so its cell is one of k's 27 and its neighbours one of k's 125.
  bool MayReachOutside(const Cell& k) const {
    for (int dx = -1; dx <= 1; ++dx)
      for (int dy = -1; dy <= 1; ++dy)
        for (int dz = -1; dz <= 1; ++dz)
          if (NearOutside({k[0] + dx, k[1] + dy, k[2] + dz})) return true;
    return false;
  }

 private:
  // Triangles that matter: those reaching the box, in xy for the closed ones (their insides).
  bool NearBox(const CellTri& t) const {
    for (int a = 0; a < 3; ++a) {
      if (t.closed && a == 2) break;
      const double mn = std::min({t.v[0][a], t.v[1][a], t.v[2][a]});
      const double mx = std::max({t.v[0][a], t.v[1][a], t.v[2][a]});
      if (!(mx >= static_cast<double>(box_.lo[a]) && mn < static_cast<double>(box_.hi[a] + 1)))
        return false;
    }
    return true;
  }

  // A cell of triangle i's surface: a wall, listed.
  void Wall(const Cell& c, uint32_t i, Listing* cells) {
    const uint64_t index = box_.Index(c);
    std::atomic_ref<uint8_t>(grid_[index]).store(kWall, std::memory_order_relaxed);
    cells->push_back(Listed(index, i));
  }

  // Every surface is a wall; each cell lists its triangles, each column its closed ones. A
  // target triangle whose cells all lie in the box is left to Finish.
  void ListAndWall() {
    struct Local {
      Listing cells, columns;
      std::vector<uint32_t> target_walls;
    };
    tbb::enumerable_thread_specific<Local> per_thread;
    tbb::parallel_for(tbb::blocked_range<size_t>(0, tris_.size(), 256),
                      [&](const tbb::blocked_range<size_t>& range) {
      Local& local = per_thread.local();
      Polygon poly;
      for (size_t i = range.begin(); i != range.end(); ++i) {
        const CellTri& t = cell_tris_[i];
        Cell lo, hi;
        bool inside = true, whole = true;  // whole: the triangle's cells all lie in the box
        for (int a = 0; a < 3; ++a) {
          const int64_t low = FloorToInt(std::min({t.v[0][a], t.v[1][a], t.v[2][a]}));
          const int64_t high = FloorToInt(std::max({t.v[0][a], t.v[1][a], t.v[2][a]}));
          lo[a] = std::max(box_.lo[a], low);
          hi[a] = std::min(box_.hi[a], high);
          inside = inside && lo[a] <= hi[a];
          whole = whole && lo[a] == low && hi[a] == high;
        }
        if (inside && whole && scene_.objects[tris_[i].object].is_target()) {
          local.target_walls.push_back(static_cast<uint32_t>(i));
        } else if (inside) {
          VisitBlock(t.v, lo, hi, &poly,
                     [&](const Cell& c) { Wall(c, static_cast<uint32_t>(i), &local.cells); });
        }
        if (!t.closed) continue;
        for (int64_t x = lo[0]; x <= hi[0]; ++x)
          for (int64_t y = lo[1]; y <= hi[1]; ++y)
            local.columns.push_back(Listed(box_.Column(x, y), static_cast<uint32_t>(i)));
      }
    });
    for (const Local& local : per_thread) {
      cells_.insert(cells_.end(), local.cells.begin(), local.cells.end());
      target_walls_.insert(target_walls_.end(), local.target_walls.begin(),
                           local.target_walls.end());
    }
    // Columns as offsets into one array (each column's triangles by index), read without a
    // search: every free cell's column is asked for its crossings.
    column_start_.assign(static_cast<size_t>(box_.n[0] * box_.n[1]) + 1, 0);
    for (const Local& local : per_thread)
      for (const uint64_t entry : local.columns) ++column_start_[(entry >> 32) + 1];
    for (size_t c = 1; c < column_start_.size(); ++c) column_start_[c] += column_start_[c - 1];
    column_tris_.resize(column_start_.back());
    std::vector<uint32_t> filled(column_start_.begin(), column_start_.end() - 1);
    for (const Local& local : per_thread)
      for (const uint64_t entry : local.columns)
        column_tris_[filled[entry >> 32]++] = static_cast<uint32_t>(entry);
    tbb::parallel_for(tbb::blocked_range<size_t>(0, column_start_.size() - 1, 1024),
                      [&](const tbb::blocked_range<size_t>& range) {
                        for (size_t c = range.begin(); c != range.end(); ++c)
                          std::sort(column_tris_.begin() + column_start_[c],
                                    column_tris_.begin() + column_start_[c + 1]);
                      });
  }

  // The crossings of the vertical line through (px, py) with the closed objects over `column`.
  void CrossingsAt(double px, double py, uint64_t column, std::vector<Crossing>* out) const {
    out->clear();
    for (uint32_t k = column_start_[column]; k < column_start_[column + 1]; ++k) {
      const CellTri& t = cell_tris_[column_tris_[k]];
      double z = 0;
      if (const int sign = VerticalCrossing(t, px, py, &z); sign != 0)
        out->push_back({t.object, sign, z});
    }
    std::sort(out->begin(), out->end());
  }

  bool IsSolid(const Vec3& q) const {
    const Cell c{FloorToInt(q.x()), FloorToInt(q.y()), FloorToInt(q.z())};
    if (!box_.Contains(c)) return false;
    // The line runs a hair beside q, so that a diagonal laid out on the grid is not met twice.
    thread_local std::vector<Crossing> crossings;
    CrossingsAt(q.x() + 3.1e-6, q.y() + 7.3e-6, box_.Column(c[0], c[1]), &crossings);
    return IsInside(crossings, q.z());
  }

  // Another object's surface between p and q (the object's own inside is IsSolid's).
  bool IsBlocked(const Vec3& p, const Vec3& q, uint32_t object) const {
    Cell lo, hi;
    for (int a = 0; a < 3; ++a) {
      lo[a] = std::max(box_.lo[a], FloorToInt(std::min(p[a], q[a])));
      hi[a] = std::min(box_.hi[a], FloorToInt(std::max(p[a], q[a])));
    }
    bool blocked = false;
    for (int64_t x = lo[0]; x <= hi[0] && !blocked; ++x)
      for (int64_t y = lo[1]; y <= hi[1] && !blocked; ++y)
        for (int64_t z = lo[2]; z <= hi[2] && !blocked; ++z) {
          ForEachListed(cells_, box_.Index({x, y, z}), [&](uint32_t i) {
            if (!blocked && tris_[i].object != object)
              blocked = SegmentMeetsTriangle(p, q, cell_tris_[i]);
          });
        }
    return blocked;
  }

  // The cell of q, or one of its 26 neighbours, is free space reached from the box's faces.
  bool ReachesOutside(const Vec3& q) const {
    return NearOutside({FloorToInt(q.x()), FloorToInt(q.y()), FloorToInt(q.z())});
  }

  // The cell c or one of its 26 neighbours is outside; a cell beyond the box asks its
  // neighbours inside it.
  bool NearOutside(const Cell& c) const {
    if (box_.Contains(c)) return (grid_[box_.Index(c)] & kNearOutside) != 0;
    for (int dx = -1; dx <= 1; ++dx)
      for (int dy = -1; dy <= 1; ++dy)
        for (int dz = -1; dz <= 1; ++dz) {
          const Cell n{c[0] + dx, c[1] + dy, c[2] + dz};
          if (box_.Contains(n) && (grid_[box_.Index(n)] & kStateBits) == kOutside) return true;
        }
    return false;
  }

  // kNearOutside on every cell of the box with an outside cell among it and its 26 neighbours
  // (inside the box), by three passes along z, y and x: a sample asks it instead of 27 cells
  // (nine in ten samples of a bin's hidden surface asked all 27 in vain).
  void MarkNearOutside() {
    const int64_t stride[3] = {box_.n[1] * box_.n[2], box_.n[2], 1};
    const auto pass = [&](int axis, uint8_t has, uint8_t mark) {
      // Each thread takes whole lines along `axis` (split by another axis), so a cell is read
      // and written by the one thread whose line holds it.
      const int split = axis == 0 ? 1 : 0;
      tbb::parallel_for(int64_t{0}, box_.n[split], [&](int64_t s) {
        int64_t at[3] = {0, 0, 0};
        at[split] = s;
        const int other_axis = 3 - axis - split;
        for (at[other_axis] = 0; at[other_axis] < box_.n[other_axis]; ++at[other_axis])
          for (at[axis] = 0; at[axis] < box_.n[axis]; ++at[axis]) {
            const int64_t index = at[0] * stride[0] + at[1] * stride[1] + at[2];
            bool near = false;
            for (int step = -1; step <= 1 && !near; ++step) {
              if (at[axis] + step < 0 || at[axis] + step >= box_.n[axis]) continue;
              const uint8_t other = grid_[static_cast<size_t>(index + step * stride[axis])];
              near = has == 0 ? (other & kStateBits) == kOutside : (other & has) != 0;
            }
            if (near) grid_[static_cast<size_t>(index)] |= mark;
          }
      });
    };
    pass(2, 0, kOutsideAlongZ);
    pass(1, kOutsideAlongZ, kOutsideAlongZY);
    pass(0, kOutsideAlongZY, kNearOutside);
  }

  // The free cells whose centre (a little off, so that a mesh laid out on the grid never passes
  // exactly through the line) lies inside a closed object.
  void FillSolids() {
    constexpr double kOffX = 0.5 + 0.0137, kOffY = 0.5 + 0.0291;
    tbb::parallel_for(tbb::blocked_range<int64_t>(box_.lo[0], box_.hi[0] + 1),
                      [&](const tbb::blocked_range<int64_t>& range) {
      std::vector<Crossing> crossings;
      for (int64_t x = range.begin(); x != range.end(); ++x) {
        for (int64_t y = box_.lo[1]; y <= box_.hi[1]; ++y) {
          const uint64_t column = box_.Column(x, y);
          CrossingsAt(static_cast<double>(x) + kOffX, static_cast<double>(y) + kOffY, column,
                      &crossings);
          if (crossings.empty()) continue;
          for (int64_t z = box_.lo[2]; z <= box_.hi[2]; ++z) {
            uint8_t& cell = grid_[box_.Index({x, y, z})];
            if (cell == kFree && IsInside(crossings, static_cast<double>(z) + 0.5)) cell = kSolid;
          }
        }
      }
    });
  }

  // Free space reached from the box's faces, layer by layer (6-connected).
  void Flood() {
    std::vector<uint32_t> frontier, next;
    for (int64_t x = box_.lo[0]; x <= box_.hi[0]; ++x)
      for (int64_t y = box_.lo[1]; y <= box_.hi[1]; ++y)
        for (int64_t z = box_.lo[2]; z <= box_.hi[2]; ++z) {
          const bool on_face = x == box_.lo[0] || x == box_.hi[0] || y == box_.lo[1] ||
                               y == box_.hi[1] || z == box_.lo[2] || z == box_.hi[2];
          if (!on_face) continue;
          const uint64_t index = box_.Index({x, y, z});
          if (grid_[index] != kFree) continue;
          grid_[index] = kOutside;
          frontier.push_back(static_cast<uint32_t>(index));
        }
    const int64_t stride[3] = {box_.n[1] * box_.n[2], box_.n[2], 1};
    while (!frontier.empty()) {
      next.clear();
      for (const uint32_t index : frontier) {
        const int64_t at[3] = {index / stride[0], (index % stride[0]) / stride[1],
                               index % stride[1]};
        for (int a = 0; a < 3; ++a) {
          for (const int step : {-1, 1}) {
            if (at[a] + step < 0 || at[a] + step >= box_.n[a]) continue;
            const uint64_t neighbour = static_cast<uint64_t>(index + step * stride[a]);
            if (grid_[neighbour] != kFree) continue;
            grid_[neighbour] = kOutside;
            next.push_back(static_cast<uint32_t>(neighbour));
          }
        }
      }
      frontier.swap(next);
    }
  }

  struct TriRef {
    uint32_t object, index;
  };
  CellTri Tri(const TriRef& r) const {
    const TriangleMesh& mesh = scene_.objects[r.object].mesh;
    const auto& t = mesh.triangles[r.index];
    return {{mesh.vertices[t[0]] / cell_size_, mesh.vertices[t[1]] / cell_size_,
             mesh.vertices[t[2]] / cell_size_},
            r.object,
            static_cast<bool>(closed_[r.object])};
  }

  const Scene& scene_;
  double cell_size_;
  std::vector<char> closed_;  // per object: IsClosed
  ExposureBox box_;
  std::vector<uint8_t> grid_;
  std::vector<TriRef> tris_;
  std::vector<CellTri> cell_tris_;     // tris_ in cell units
  Listing cells_;                      // grid index -> triangles touching the cell
  std::vector<uint32_t> target_walls_;  // tris_ whose walls Finish takes from the listed cells
  std::vector<uint32_t> column_start_;  // column -> its first entry in column_tris_
  std::vector<uint32_t> column_tris_;   // closed triangles over each column, by index
};

}  // namespace

uint64_t ExposureGridCells(const Scene& scene, double cell_size) {
  if (!std::isfinite(cell_size) || cell_size <= 0) return 0;
  const std::optional<ExposureBox> box = ExposureBoxOf(scene, cell_size);
  return box ? box->Size() : 0;
}

namespace {

// ComputeExposure with the targets' cells listed already (`cells`, in `box`).
std::vector<uint8_t> ExposureOf(const Scene& scene, const Reference& reference,
                                const ExposureGrid& grid, const TargetCells& cells) {
  const double cell_size = reference.cell_size;
  struct Tri {
    uint32_t object;
    size_t index;
  };
  std::vector<Tri> targets;
  for (uint32_t o = 0; o < scene.objects.size(); ++o) {
    if (!scene.objects[o].is_target()) continue;
    for (size_t i = 0; i < scene.objects[o].mesh.triangles.size(); ++i) targets.push_back({o, i});
  }
  // Each triangle's part in each of its cells is sampled at its centroid and halfway from there
  // to each corner; a cell is exposed once any sample is. Bytes only ever go from 0 to 1.
  std::vector<uint8_t> exposed(reference.keys.size(), 0);
  // Cells none of whose samples can reach outside stay unexposed without being sampled.
  std::vector<uint8_t> reach(reference.keys.size());
  tbb::parallel_for(size_t{0}, reach.size(), [&](size_t i) {
    reach[i] = grid.MayReachOutside(UnpackVoxel(reference.keys[i]));
  });
  tbb::parallel_for(tbb::blocked_range<size_t>(0, targets.size(), 256),
                    [&](const tbb::blocked_range<size_t>& range) {
    Polygon poly;
    for (size_t i = range.begin(); i != range.end(); ++i) {
      const TriangleMesh& mesh = scene.objects[targets[i].object].mesh;
      const auto& t = mesh.triangles[targets[i].index];
      const Vec3 tri[3] = {mesh.vertices[t[0]] / cell_size, mesh.vertices[t[1]] / cell_size,
                           mesh.vertices[t[2]] / cell_size};
      const Vec3 normal = (tri[1] - tri[0]).cross(tri[2] - tri[0]).normalized();
      if (!normal.allFinite()) continue;  // degenerate: no side to be seen from
      Cell lo, hi;
      for (int a = 0; a < 3; ++a) {
        lo[a] = FloorToInt(std::min({tri[0][a], tri[1][a], tri[2][a]}));
        hi[a] = FloorToInt(std::max({tri[0][a], tri[1][a], tri[2][a]}));
      }
      // The triangle's cells as BuildReference listed them; a cell another triangle found
      // exposed already is not clipped again (most cells of a fine mesh are shared by several
      // triangles). A triangle inside one cell is its own part there, as VisitWantedBlock has it.
      const bool in_one_cell = lo == hi && InsideCell(tri, lo);
      const std::span<const uint64_t> keys = cells.Of(targets[i].object, targets[i].index);
      const std::span<const int32_t> indices = cells.IndexOf(targets[i].object, targets[i].index);
      for (size_t k = 0; k < keys.size(); ++k) {
        const uint64_t key = keys[k];
        const int32_t index = indices[k];
        // Negative: left out already (never: R holds every touched cell).
        if (index < 0 || std::atomic_ref<uint8_t>(exposed[static_cast<size_t>(index)])
                             .load(std::memory_order_relaxed))
          continue;
        const Cell cell = UnpackVoxel(key);
        if (!reach[static_cast<size_t>(index)]) continue;
        if (in_one_cell) {
          poly.Assign(tri);
        } else if (!TriangleTouchesHalfOpenCell(tri, cell, &poly)) {
          continue;  // never: the cell was listed as touched
        }
        const std::span<const Vec3> part = poly.Corners();
        std::atomic_ref<uint8_t> flag(exposed[static_cast<size_t>(index)]);
        Vec3 centroid = Vec3::Zero();
        for (const Vec3& v : part) centroid += v;
        centroid /= static_cast<double>(part.size());
        bool is_exposed = grid.IsExposed(centroid, normal, targets[i].object);
        for (size_t v = 0; v < part.size() && !is_exposed; ++v)
          is_exposed = grid.IsExposed(0.5 * (centroid + part[v]), normal, targets[i].object);
        if (is_exposed) flag.store(1, std::memory_order_relaxed);
      }
    }
  });
  return exposed;
}

}  // namespace

std::vector<uint8_t> ComputeExposure(const Scene& scene, const Reference& reference) {
  const std::optional<ExposureBox> box = ExposureBoxOf(scene, reference.cell_size);
  if (!box) return {};
  TargetCells cells = ListTargetCells(scene, reference.cell_size);
  IndexAmong(reference.keys, &cells);
  ExposureGrid grid(scene, reference.cell_size, *box);
  grid.Finish(cells);
  return ExposureOf(scene, reference, grid, cells);
}

Reference BuildReference(const Scene& scene, const ReferenceOptions& options) {
  options.Validate();
  struct Tri {
    const TriangleMesh* mesh;
    size_t index;
    uint32_t part;
  };
  Reference reference;
  reference.cell_size = options.cell_size;
  std::vector<Tri> triangles;
  for (const SceneObject& object : scene.objects) {
    if (!object.is_target()) continue;
    auto part = std::find(reference.part_names.begin(), reference.part_names.end(), object.name);
    if (part == reference.part_names.end())
      part = reference.part_names.insert(reference.part_names.end(), object.name);
    const auto part_index = static_cast<uint32_t>(part - reference.part_names.begin());
    for (size_t i = 0; i < object.mesh.triangles.size(); ++i)
      triangles.push_back({&object.mesh, i, part_index});
  }
  if (triangles.empty())
    throw InputError("the scene has no target surface — mark at least one object as a target");
  CheckTargetsFitGrid(scene, options.cell_size);
  const std::optional<ExposureBox> exposure_box = ExposureBoxOf(scene, options.cell_size);
  if (options.exposed_only) {
    if (!exposure_box)
      throw InputError(fmt::format(
          "--exposed-only: the targets' box spans more than {} cells of {} m, too many to find "
          "their exposed surface — give a larger --cell-size",
          kMaxExposureGridCells, options.cell_size));
  }

  // The exposure grid is built beside the target cells' listing and then beside R's keys: only
  // its targets' walls need the listed cells (the two halves keep both cores busy where the
  // listing's or the keys' work is serial).
  std::optional<ExposureGrid> grid;
  tbb::task_group building;
  if (exposure_box) building.run([&] { grid.emplace(scene, options.cell_size, *exposure_box); });
  TargetCells cells = ListTargetCells(scene, options.cell_size);
  building.wait();
  if (grid) building.run([&] { grid->Finish(cells); });
  // Sorted: the result does not depend on how the work was split between threads.
  reference.keys = DistinctSorted(cells.keys);
  IndexAmong(reference.keys, &cells);
  // A cell on two parts' surfaces belongs to the first: the smallest part index.
  reference.part_of.assign(reference.keys.size(), UINT32_MAX);
  for (size_t i = 0; i < triangles.size(); ++i) {
    for (size_t k = cells.start[i]; k < cells.start[i + 1]; ++k) {
      uint32_t& part = reference.part_of[static_cast<size_t>(cells.index[k])];
      part = std::min(part, triangles[i].part);
    }
  }
  // ComputeExposure on the cells just listed (empty without a box).
  building.wait();
  if (grid) reference.exposed = ExposureOf(scene, reference, *grid, cells);
  if (options.exposed_only) {
    VANTAGE_CHECK(reference.exposed.size() == reference.keys.size());
    reference.exposed_only = true;
    reference.left_out.assign(reference.part_names.size(), 0);
    size_t kept = 0;
    for (size_t i = 0; i < reference.keys.size(); ++i) {
      if (!reference.exposed[i]) {
        ++reference.left_out[reference.part_of[i]];
        continue;
      }
      reference.keys[kept] = reference.keys[i];
      reference.part_of[kept] = reference.part_of[i];
      reference.exposed[kept] = 1;
      ++kept;
    }
    reference.keys.resize(kept);
    reference.part_of.resize(kept);
    reference.exposed.resize(kept);
    if (reference.keys.empty())
      throw InputError("--exposed-only: no cell of the targets' surface is exposed — every face "
                       "rests on or is enclosed by other geometry");
  }
  return reference;
}

}  // namespace vantage
