// R must be exactly the set of half-open cells the targets' surface passes through
// (SYSTEM.md, coverage metric). Expected sets are enumerated by hand from the geometry.
#include <gtest/gtest.h>

#include <cmath>
#include <set>

#include "vantage/error.hpp"
#include "vantage/reference.hpp"
#include "vantage/scene.hpp"

namespace vantage {
namespace {

Scene TargetScene(TriangleMesh mesh) {
  Scene scene;
  scene.objects.push_back({"target", Role::kTarget, std::move(mesh), {}});
  return scene;
}

// Axis-aligned box [lo, hi]³ whose every face is split into `split` x `split` quads.
TriangleMesh SplitCube(double lo, double hi, int split) {
  TriangleMesh mesh;
  const double step = (hi - lo) / split;
  for (int axis = 0; axis < 3; ++axis) {
    for (double fixed : {lo, hi}) {
      for (int i = 0; i < split; ++i) {
        for (int j = 0; j < split; ++j) {
          const auto corner = [&](int di, int dj) {
            Vec3 p;
            p[axis] = fixed;
            p[(axis + 1) % 3] = lo + (i + di) * step;
            p[(axis + 2) % 3] = lo + (j + dj) * step;
            return p;
          };
          const uint32_t base = static_cast<uint32_t>(mesh.vertices.size());
          mesh.vertices.insert(mesh.vertices.end(), {corner(0, 0), corner(1, 0), corner(1, 1), corner(0, 1)});
          mesh.triangles.push_back({base, base + 1, base + 2});
          mesh.triangles.push_back({base, base + 2, base + 3});
        }
      }
    }
  }
  return mesh;
}

// Cells (i, j, k) in [first, last]³ with at least one index on the boundary: the shell.
std::set<uint64_t> Shell(int64_t first, int64_t last) {
  std::set<uint64_t> cells;
  for (int64_t i = first; i <= last; ++i)
    for (int64_t j = first; j <= last; ++j)
      for (int64_t k = first; k <= last; ++k) {
        const bool on_shell = i == first || i == last || j == first || j == last || k == first || k == last;
        if (on_shell) cells.insert(PackVoxel({i, j, k}));
      }
  return cells;
}

std::set<uint64_t> AsSet(const Reference& r) { return {r.keys.begin(), r.keys.end()}; }

TEST(Reference, BoxWithMidCellFacesIsExactlyItsShell) {
  // Faces at 0.5 and 4.5 cells: every face lies inside cell layer 0 or 4.
  const Reference r = BuildReference(TargetScene(SplitCube(0.5, 4.5, 1)), {1.0});
  EXPECT_EQ(r.size(), 5u * 5 * 5 - 3u * 3 * 3);
  EXPECT_EQ(AsSet(r), Shell(0, 4));
}

TEST(Reference, FaceOnAGridPlaneCountsOneLayer) {
  // Faces on the grid planes x = 1 and x = 4: a point at x = 1 is in cell 1 only (half-open
  // cells), so the shell is {1..4}³ minus its inside {2, 3}³: 64 - 8 = 56 cells, not 6³ - 4³.
  const Reference r = BuildReference(TargetScene(SplitCube(1.0, 4.0, 1)), {1.0});
  EXPECT_EQ(r.size(), 56u);
  EXPECT_EQ(AsSet(r), Shell(1, 4));
}

TEST(Reference, SameSurfaceSplitIntoMoreTrianglesGivesSameSet) {
  const double cell = 0.25;
  for (const auto& [lo, hi] : {std::pair{0.125, 1.125}, std::pair{0.0, 1.0}, std::pair{-0.3, 0.7}}) {
    const Reference coarse = BuildReference(TargetScene(SplitCube(lo, hi, 1)), {cell});
    for (int split : {2, 3, 8}) {
      const Reference fine = BuildReference(TargetScene(SplitCube(lo, hi, split)), {cell});
      EXPECT_EQ(fine.keys, coarse.keys) << "lo " << lo << " split " << split;
    }
  }
}

TEST(Reference, DiagonalTriangleTouchesExactlyTheCellsItCrosses) {
  // The triangle (0,0,0) (2,0,0) (0,2,0) in the plane z = 0 with unit cells: its points have
  // x + y <= 2, so it reaches the cells (0,0), (1,0), (0,1), and (1,1) only at the corner point
  // (1,1), which belongs to cell (1,1): half-open cells count it. Cell (2,0) holds the vertex
  // (2,0,0) and (0,2) the vertex (0,2,0).
  std::vector<uint64_t> keys;
  AppendTriangleCells(Vec3(0, 0, 0), Vec3(2, 0, 0), Vec3(0, 2, 0), 1.0, &keys);
  const std::set<uint64_t> got(keys.begin(), keys.end());
  const std::set<uint64_t> expected = {PackVoxel({0, 0, 0}), PackVoxel({1, 0, 0}), PackVoxel({0, 1, 0}),
                                       PackVoxel({1, 1, 0}), PackVoxel({2, 0, 0}), PackVoxel({0, 2, 0})};
  EXPECT_EQ(got, expected);
}

TEST(Reference, LargeTiltedTriangleMatchesPointSampling) {
  // Every cell holding a sampled point of the triangle must be in R, and every cell of R must be
  // within one cell of a sample (dense sampling at 1/50 of a cell).
  const Vec3 a(0.13, 0.21, 0.37), b(7.9, 1.3, 3.1), c(2.2, 6.7, 5.9);
  std::vector<uint64_t> keys;
  AppendTriangleCells(a, b, c, 1.0, &keys);
  const std::set<uint64_t> got(keys.begin(), keys.end());
  std::set<uint64_t> sampled;
  const int steps = 500;
  for (int i = 0; i <= steps; ++i)
    for (int j = 0; i + j <= steps; ++j) {
      const double u = static_cast<double>(i) / steps, v = static_cast<double>(j) / steps;
      sampled.insert(PackVoxel(VoxelKeyOf(a + u * (b - a) + v * (c - a), 1.0)));
    }
  for (uint64_t key : sampled) EXPECT_TRUE(got.count(key)) << "sampled cell missing from R";
  EXPECT_GE(got.size(), sampled.size());
  EXPECT_LE(got.size(), sampled.size() * 11 / 10);  // only cells the surface merely grazes are extra
}

TEST(Reference, RejectsNonPositiveCellSize) {
  const Scene scene = TargetScene(SplitCube(0, 1, 1));
  EXPECT_THROW(BuildReference(scene, {0.0}), InputError);
  EXPECT_THROW(BuildReference(scene, {-0.01}), InputError);
  EXPECT_THROW(BuildReference(scene, {std::nan("")}), InputError);
}

TEST(Reference, RejectsSceneWithoutTarget) {
  Scene scene;
  scene.objects.push_back({"wall", Role::kOccluder, SplitCube(0, 1, 1), {}});
  EXPECT_THROW(BuildReference(scene, {0.1}), InputError);
}

}  // namespace
}  // namespace vantage

namespace vantage {

// The ray hits and R's cells must be keyed by the same floor; FloorToInt replaces std::floor there.
TEST(VoxelKey, FloorToIntIsFloorAndSaturates) {
  for (double x : {0.0, -0.0, 0.5, -0.5, 1.0, -1.0, 2.999999999, -2.000000001, 1e15 + 0.5, -1e15 - 0.5,
                   std::nextafter(-3.0, 0.0), std::nextafter(-3.0, -4.0)}) {
    EXPECT_EQ(FloorToInt(x), static_cast<int64_t>(std::floor(x))) << x;
  }
  EXPECT_EQ(FloorToInt(1e300), INT64_MAX);
  EXPECT_EQ(FloorToInt(-1e300), INT64_MIN);
  EXPECT_FALSE(VoxelIndexFits(VoxelKeyOf(Vec3(std::nan(""), 0, 0), 0.005)));
  const VoxelIndex i = VoxelKeyOf(Vec3(-0.0051, 0.0049, 0.005), 0.005);
  EXPECT_EQ(i, (VoxelIndex{-2, 0, 1}));
}

}  // namespace vantage

namespace vantage {
namespace {

// The memory check's estimate of |R| (issue 47's scale bench: a 200 k-triangle cell was
// estimated 28× its |R| and refused). A sphere of 0.1 m meshed to 10 µm chord error (triangles of
// about 3 mm) in cells of 1 cm: the plain estimate counts every triangle at least once, the
// second look counts the fine triangles' box cells, which hold the triangles and so bound |R|.
TEST(ReferenceEstimate, FineMeshesAreCountedByTheirCells) {
  const Scene scene = TargetScene(MakeSphere(0.1, 1e-5));
  ASSERT_GT(scene.objects[0].mesh.triangles.size(), 20000u);
  const double cells = static_cast<double>(BuildReference(scene, {0.01}).size());
  const double plain = EstimateReferenceCells(scene, 0.01);
  const double tight = EstimateReferenceCells(scene, 0.01, true);
  EXPECT_GE(tight, cells);
  EXPECT_LE(tight, 4 * cells);
  EXPECT_GT(plain, 10 * cells);
  // A box's faces are larger than a cell: nothing to count by cell, the two agree.
  const Scene box = TargetScene(MakeBox(Vec3(0.3, 0.2, 0.1)));
  EXPECT_EQ(EstimateReferenceCells(box, 0.01, true), EstimateReferenceCells(box, 0.01));
  EXPECT_GE(EstimateReferenceCells(box, 0.01), static_cast<double>(BuildReference(box, {0.01}).size()));
}

}  // namespace
}  // namespace vantage
