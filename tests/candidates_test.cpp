// Candidates: population regions and distributions (GAZEBO.md, with Gazebo's Population.cc
// quirks), k-means, look-at, random roll, mount offset, errors. Expected values are derived by
// hand in the comments, never copied from the code's output.
#include "vantage/candidates.hpp"

#include <fmt/format.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <numbers>
#include <set>
#include <string>
#include <tuple>
#include <vector>

#include "candidates/kmeans.hpp"
#include "vantage/error.hpp"
#include "vantage/sensors.hpp"
#include "vantage/types.hpp"

namespace vantage {
namespace {

constexpr double kPi = std::numbers::pi;

Population BoxPopulation(Distribution distribution, const Pose& pose, const Vec3& size, int count) {
  Population p;
  p.name = "box_pop";
  p.sensor_type = "kinect_xbox_360";
  p.pose = pose;
  p.region = RegionShape::kBox;
  p.box_size = size;
  p.count = count;
  p.distribution = distribution;
  p.file = "cell.world";
  p.line = 41;
  return p;
}

Population CylinderPopulation(
    Distribution distribution, const Pose& pose, double radius, double length, int count) {
  Population p;
  p.name = "cyl_pop";
  p.sensor_type = "kinect_xbox_360";
  p.pose = pose;
  p.region = RegionShape::kCylinder;
  p.radius = radius;
  p.length = length;
  p.count = count;
  p.distribution = distribution;
  p.file = "cell.world";
  p.line = 55;
  return p;
}

bool Inside(const Vec3& p, const Vec3& lo, const Vec3& hi, double tol = 1e-12) {
  return (p.array() >= lo.array() - tol).all() && (p.array() <= hi.array() + tol).all();
}

size_t DistinctCount(const std::vector<Vec3>& points) {
  std::set<std::tuple<double, double, double>> set;
  for (const Vec3& p : points) set.emplace(p.x(), p.y(), p.z());
  return set.size();
}

/// Expects an InputError whose message starts with `prefix` and contains `needle`.
template <typename F>
void ExpectInputError(F&& f, const std::string& prefix, const std::string& needle) {
  try {
    f();
    ADD_FAILURE() << "no InputError thrown (expected " << prefix << " ... " << needle << ")";
  } catch (const InputError& e) {
    const std::string what = e.what();
    EXPECT_EQ(what.rfind(prefix, 0), 0u) << what;
    EXPECT_NE(what.find(needle), std::string::npos) << what;
  }
}

// ---------------------------------------------------------------------------------------------
// Box regions

TEST(Candidates, BoxRandomStaysInsideTheShiftedBox) {
  // P = (1, 2, 3), size (0.4, 0.6, 0.2): P.pos − size/2 = (0.8, 1.7, 2.9), offsets in [0, size),
  // so the region is [0.8, 1.2] x [1.7, 2.3] x [2.9, 3.1]: centred on P for an unrotated P.
  const Population p = BoxPopulation(Distribution::kRandom, Pose::FromXyzRpy(1, 2, 3, 0, 0, 0),
                                     Vec3(0.4, 0.6, 0.2), 300);
  const std::vector<Vec3> positions = PopulationPositions(p, 7, 0);
  ASSERT_EQ(positions.size(), 300u);
  Aabb box;
  for (const Vec3& x : positions) {
    EXPECT_TRUE(Inside(x, Vec3(0.8, 1.7, 2.9), Vec3(1.2, 2.3, 3.1))) << x.transpose();
    box.Extend(x);
  }
  // 300 uniform draws fill the region: each side within 5 % of its face.
  EXPECT_LT(box.min.x(), 0.82);
  EXPECT_GT(box.max.x(), 1.18);
  EXPECT_LT(box.min.y(), 1.73);
  EXPECT_GT(box.max.y(), 2.27);
  EXPECT_LT(box.min.z(), 2.91);
  EXPECT_GT(box.max.z(), 3.09);
}

TEST(Candidates, RotatedBoxIsShiftedInWorldAxesNotCentredOnPose) {
  // P = (1, 2, 3, yaw 90°), size (0.4, 0.6, 0.2). Shift first in world axes: origin
  // (0.8, 1.7, 2.9). Rz(90°) maps the offset (a, b, c) to (−b, a, c) with a ∈ [0, 0.4],
  // b ∈ [0, 0.6], c ∈ [0, 0.2]: x = 0.8 − b ∈ [0.2, 0.8], y = 1.7 + a ∈ [1.7, 2.1],
  // z ∈ [2.9, 3.1]. Its centre (0.5, 1.9, 3.0) is not P.
  const Population p = BoxPopulation(
      Distribution::kRandom, Pose::FromXyzRpy(1, 2, 3, 0, 0, kPi / 2), Vec3(0.4, 0.6, 0.2), 300);
  const std::vector<Vec3> positions = PopulationPositions(p, 7, 0);
  ASSERT_EQ(positions.size(), 300u);
  Aabb box;
  Vec3 mean = Vec3::Zero();
  for (const Vec3& x : positions) {
    EXPECT_TRUE(Inside(x, Vec3(0.2, 1.7, 2.9), Vec3(0.8, 2.1, 3.1), 1e-9)) << x.transpose();
    box.Extend(x);
    mean += x / 300.0;
  }
  EXPECT_LT(box.min.x(), 0.23);
  EXPECT_GT(box.max.x(), 0.77);
  EXPECT_LT(box.min.y(), 1.72);
  EXPECT_GT(box.max.y(), 2.08);
  EXPECT_NEAR(mean.x(), 0.5, 0.05);
  EXPECT_NEAR(mean.y(), 1.9, 0.05);
  EXPECT_GT((mean - Vec3(1, 2, 3)).norm(), 0.4);
}

TEST(Candidates, LinearOffsetsAreSizeTimesIOverN) {
  // P = (1, 2, 3), size (0.4, 0.6, 0.8), n = 4: origin (0.8, 1.7, 2.6); Population.cc's offsets
  // are size·i/n along the axis (the last stops one step short of the far face) and size/2 on
  // the other two axes.
  const Pose pose = Pose::FromXyzRpy(1, 2, 3, 0, 0, 0);
  const Vec3 size(0.4, 0.6, 0.8);
  const std::vector<Vec3> x =
      PopulationPositions(BoxPopulation(Distribution::kLinearX, pose, size, 4), 1, 0);
  const std::vector<Vec3> y =
      PopulationPositions(BoxPopulation(Distribution::kLinearY, pose, size, 4), 1, 0);
  const std::vector<Vec3> z =
      PopulationPositions(BoxPopulation(Distribution::kLinearZ, pose, size, 4), 1, 0);
  ASSERT_EQ(x.size(), 4u);
  ASSERT_EQ(y.size(), 4u);
  ASSERT_EQ(z.size(), 4u);
  const std::array<double, 4> xs = {0.8, 0.9, 1.0, 1.1};
  const std::array<double, 4> ys = {1.7, 1.85, 2.0, 2.15};
  const std::array<double, 4> zs = {2.6, 2.8, 3.0, 3.2};
  for (int i = 0; i < 4; ++i) {
    EXPECT_TRUE(x[i].isApprox(Vec3(xs[i], 2.0, 3.0), 1e-12)) << x[i].transpose();
    EXPECT_TRUE(y[i].isApprox(Vec3(1.0, ys[i], 3.0), 1e-12)) << y[i].transpose();
    EXPECT_TRUE(z[i].isApprox(Vec3(1.0, 2.0, zs[i]), 1e-12)) << z[i].transpose();
  }
}

TEST(Candidates, LinearWithRotatedPoseRotatesTheOffsetsNotTheShift) {
  // Same box with yaw 90°: origin (0.8, 1.7, 2.6), offset (0.1·i, 0.3, 0.4) rotated by Rz(90°)
  // is (−0.3, 0.1·i, 0.4): positions (0.5, 1.7 + 0.1·i, 3.0).
  const std::vector<Vec3> x = PopulationPositions(
      BoxPopulation(Distribution::kLinearX, Pose::FromXyzRpy(1, 2, 3, 0, 0, kPi / 2),
                    Vec3(0.4, 0.6, 0.8), 4),
      1, 0);
  ASSERT_EQ(x.size(), 4u);
  for (int i = 0; i < 4; ++i)
    EXPECT_LT((x[i] - Vec3(0.5, 1.7 + 0.1 * i, 3.0)).norm(), 1e-12) << x[i].transpose();
}

TEST(Candidates, BoxUniformGivesDistinctCentroidsInsideTheLattice) {
  // P = (0, 0, 1), size (0.55, 0.45, 0.2): origin (−0.275, −0.225, 0.9). Lattice x = 0 … 0.5
  // (6 values), y = 0 … 0.4 (5 values): 30 points; centroids lie in the lattice's hull
  // x ∈ [−0.275, 0.225], y ∈ [−0.225, 0.175], z ∈ [0.9, 1.1].
  const Population p = BoxPopulation(Distribution::kUniform, Pose::FromXyzRpy(0, 0, 1, 0, 0, 0),
                                     Vec3(0.55, 0.45, 0.2), 6);
  const std::vector<Vec3> positions = PopulationPositions(p, 3, 0);
  ASSERT_EQ(positions.size(), 6u);
  EXPECT_EQ(DistinctCount(positions), 6u);
  for (const Vec3& x : positions)
    EXPECT_TRUE(Inside(x, Vec3(-0.275, -0.225, 0.9), Vec3(0.225, 0.175, 1.1), 1e-9))
        << x.transpose();
}

TEST(Candidates, BoxUniformWithAsManyClustersAsLatticePointsReturnsTheLattice) {
  // size (0.15, 0.15, 0.1): x ∈ {0, 0.1}, y ∈ {0, 0.1}: 4 lattice points, in Gazebo's order
  // (y outer, x inner). With n = 4 every point is its own cluster (k-means starts from the first
  // k points), so the positions are P − size/2 + (x, y, z): (−0.075 + x, −0.075 + y, 1.95 + z).
  const Population p = BoxPopulation(Distribution::kUniform, Pose::FromXyzRpy(0, 0, 2, 0, 0, 0),
                                     Vec3(0.15, 0.15, 0.1), 4);
  const std::vector<Vec3> positions = PopulationPositions(p, 5, 0);
  ASSERT_EQ(positions.size(), 4u);
  const std::array<Vec3, 4> xy = {Vec3(-0.075, -0.075, 0), Vec3(0.025, -0.075, 0),
                                  Vec3(-0.075, 0.025, 0), Vec3(0.025, 0.025, 0)};
  for (int i = 0; i < 4; ++i) {
    EXPECT_NEAR(positions[i].x(), xy[i][0], 1e-12);
    EXPECT_NEAR(positions[i].y(), xy[i][1], 1e-12);
    EXPECT_GE(positions[i].z(), 1.95);
    EXPECT_LE(positions[i].z(), 2.05);
  }
  // One more clone than lattice points: Gazebo's k-means refuses (and Population.cc then reads an
  // empty vector); vantage reports it.
  Population too_many = p;
  too_many.count = 5;
  ExpectInputError([&] { PopulationPositions(too_many, 5, 0); }, "cell.world:41: ", "lattice");
}

// ---------------------------------------------------------------------------------------------
// Cylinder regions

TEST(Candidates, CylinderRandomIsUniformInRadiusNotArea) {
  // P = (0.5, −0.5, 1), r = 0.3, l = 0.2; no shift: ρ ≤ 0.3 around the axis, z ∈ [1, 1.2].
  // ρ = U(0, r): half the points have ρ < r/2 (uniform in area would give a quarter).
  const Population p = CylinderPopulation(Distribution::kRandom,
                                          Pose::FromXyzRpy(0.5, -0.5, 1, 0, 0, 0), 0.3, 0.2, 2000);
  const std::vector<Vec3> positions = PopulationPositions(p, 11, 2);
  ASSERT_EQ(positions.size(), 2000u);
  int inner = 0;
  double max_rho = 0;
  for (const Vec3& x : positions) {
    const double rho = std::hypot(x.x() - 0.5, x.y() + 0.5);
    EXPECT_LE(rho, 0.3 + 1e-12);
    EXPECT_GE(x.z(), 1.0);
    EXPECT_LE(x.z(), 1.2);
    if (rho < 0.15) ++inner;
    max_rho = std::max(max_rho, rho);
  }
  EXPECT_NEAR(inner / 2000.0, 0.5, 0.05);
  EXPECT_GT(max_rho, 0.29);
}

TEST(Candidates, CylinderAxisFollowsThePoseRotation) {
  // roll 90°: Rx(90°)·(0, 0, 1) = (0, −1, 0), so the axis runs from P = (0, 1, 0) towards −y:
  // y ∈ [1 − l, 1] = [0.6, 1], and the distance to the axis sqrt(x² + z²) ≤ r = 0.2.
  const Population p = CylinderPopulation(Distribution::kRandom,
                                          Pose::FromXyzRpy(0, 1, 0, kPi / 2, 0, 0), 0.2, 0.4, 500);
  for (const Vec3& x : PopulationPositions(p, 1, 0)) {
    EXPECT_LE(std::hypot(x.x(), x.z()), 0.2 + 1e-12);
    EXPECT_GE(x.y(), 0.6 - 1e-12);
    EXPECT_LE(x.y(), 1.0 + 1e-12);
  }
}

TEST(Candidates, CylinderUniformGivesNDistinctPointsInside) {
  // bin_picking's population 2: P = (0, 0, 0.55), r = 0.35, l = 0.1, 20 clones. Centroids of
  // points inside the (convex) cylinder stay inside: ρ ≤ 0.35, z ∈ [0.55, 0.65].
  const Population p = CylinderPopulation(Distribution::kUniform,
                                          Pose::FromXyzRpy(0, 0, 0.55, 0, 0, 0), 0.35, 0.1, 20);
  const std::vector<Vec3> positions = PopulationPositions(p, 1, 1);
  ASSERT_EQ(positions.size(), 20u);
  EXPECT_EQ(DistinctCount(positions), 20u);
  double max_rho = 0;
  for (const Vec3& x : positions) {
    const double rho = std::hypot(x.x(), x.y());
    EXPECT_LE(rho, 0.35);
    EXPECT_GE(x.z(), 0.55);
    EXPECT_LE(x.z(), 0.65);
    max_rho = std::max(max_rho, rho);
  }
  // 20 clusters of a disc spread out: the outer ones sit well away from the axis.
  EXPECT_GT(max_rho, 0.15);
}

// ---------------------------------------------------------------------------------------------
// Grid

TEST(Candidates, GridExampleOfGazeboMd) {
  // pose 3.341 0 −0.35 0 −1.5707 0, 12 rows, 7 cols, step 0.3636: shift x by 0.3636·3 = 1.0908
  // → 2.2502, y by 0.3636·5.5 = 1.9998 → −1.9998. Ry(−1.5707) maps (x, 0, 0) to (x·cos, 0,
  // x·sin 1.5707 ≈ x) and leaves y: clone (i, j) = (2.2502 + ≈0, −1.9998 + 0.3636·i,
  // −0.35 + 0.3636·j). So x ≈ 2.2502, y from −2.0 to 2.0, z from −0.35 to 1.8316.
  Population p;
  p.name = "grid_pop";
  p.sensor_type = "kinect_xbox_360";
  p.pose = Pose::FromXyzRpy(3.341, 0, -0.35, 0, -1.5707, 0);
  p.region = RegionShape::kNone;
  p.distribution = Distribution::kGrid;
  p.rows = 12;
  p.cols = 7;
  p.step = Vec3(0.3636, 0.3636, 0);
  const std::vector<Vec3> positions = PopulationPositions(p, 1, 0);
  ASSERT_EQ(positions.size(), 84u);
  for (int i = 0; i < 12; ++i) {
    for (int j = 0; j < 7; ++j) {
      const Vec3& x = positions[i * 7 + j];
      EXPECT_NEAR(x.x(), 2.2502, 1e-3);
      EXPECT_NEAR(x.y(), -1.9998 + 0.3636 * i, 1e-3);
      EXPECT_NEAR(x.z(), -0.35 + 0.3636 * j, 1e-3);
    }
  }
  EXPECT_NEAR(positions.front().y(), -2.0, 1e-3);
  EXPECT_NEAR(positions.back().y(), 2.0, 1e-3);
  EXPECT_NEAR(positions.front().z(), -0.35, 1e-3);
  EXPECT_NEAR(positions.back().z(), 1.8316, 1e-3);

  // Gazebo reads no region for grid: a (default) box is ignored, not shifted.
  Population with_box = p;
  with_box.region = RegionShape::kBox;
  with_box.box_size = Vec3(1, 1, 1);
  const std::vector<Vec3> same = PopulationPositions(with_box, 1, 0);
  ASSERT_EQ(same.size(), 84u);
  for (size_t k = 0; k < 84; ++k) EXPECT_EQ(same[k], positions[k]);
}

TEST(Candidates, GridEvenColumnsCentreOnPose) {
  // 2 rows x 2 cols, step (1, 2, 5), identity pose at (10, 20, 30): shift x by 0.5, y by 1.
  // Clones (9.5, 19, 30), (10.5, 19, 30), (9.5, 21, 30), (10.5, 21, 30); dz is unused.
  Population p;
  p.name = "g";
  p.sensor_type = "kinect_xbox_360";
  p.pose = Pose::FromXyzRpy(10, 20, 30, 0, 0, 0);
  p.region = RegionShape::kNone;
  p.distribution = Distribution::kGrid;
  p.rows = 2;
  p.cols = 2;
  p.step = Vec3(1, 2, 5);
  const std::vector<Vec3> x = PopulationPositions(p, 1, 0);
  ASSERT_EQ(x.size(), 4u);
  EXPECT_EQ(x[0], Vec3(9.5, 19, 30));
  EXPECT_EQ(x[1], Vec3(10.5, 19, 30));
  EXPECT_EQ(x[2], Vec3(9.5, 21, 30));
  EXPECT_EQ(x[3], Vec3(10.5, 21, 30));
}

// ---------------------------------------------------------------------------------------------
// k-means (Gazebo's algorithm)

TEST(Candidates, KMeansFollowsGazebosLloydIterations) {
  // Points 0, 1, 10, 11 on x; k = 2 starts from the first two points (0 and 1).
  // Pass 1: 0 → c0, 1, 10, 11 → c1: c0 = 0, c1 = 22/3. Pass 2: 1 is nearer c0 (1 < 6.33):
  // c0 = 0.5, c1 = 10.5. Pass 3: nothing changes → stop.
  const std::vector<Vec3> points = {Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(10, 0, 0), Vec3(11, 0, 0)};
  const std::vector<Vec3> c = detail::KMeans(points, 2);
  ASSERT_EQ(c.size(), 2u);
  EXPECT_TRUE(c[0].isApprox(Vec3(0.5, 0, 0)));
  EXPECT_TRUE(c[1].isApprox(Vec3(10.5, 0, 0)));
  // k = number of points: every point is its own centroid, in order.
  const std::vector<Vec3> all = detail::KMeans(points, 4);
  for (size_t i = 0; i < 4; ++i) EXPECT_EQ(all[i], points[i]);
  // k = 1: the mean.
  EXPECT_TRUE(detail::KMeans(points, 1)[0].isApprox(Vec3(5.5, 0, 0)));
}

TEST(Candidates, KMeansReseedsAnEmptyCluster) {
  // Duplicates 0, 0 first: cluster 1 starts on the same point and loses the tie (lower index
  // wins), so it is empty after pass 1; Gazebo would produce NaN. Re-seeded at the point
  // farthest from its centroid (c0 = mean of 0, 0, 4, 5 = 2.25 → 5 is farthest), it ends with
  // {4, 5}: centroids 0 and 4.5.
  const std::vector<Vec3> points = {Vec3(0, 0, 0), Vec3(0, 0, 0), Vec3(4, 0, 0), Vec3(5, 0, 0)};
  const std::vector<Vec3> c = detail::KMeans(points, 2);
  ASSERT_EQ(c.size(), 2u);
  EXPECT_TRUE(c[0].allFinite());
  EXPECT_TRUE(c[1].allFinite());
  EXPECT_NEAR(c[0].x(), 0.0, 1e-12);
  EXPECT_NEAR(c[1].x(), 4.5, 1e-12);
}

// ---------------------------------------------------------------------------------------------
// Determinism

TEST(Candidates, SameSeedSamePositionsDifferentSeedDifferent) {
  for (Distribution d : {Distribution::kRandom, Distribution::kUniform}) {
    const Population box =
        BoxPopulation(d, Pose::FromXyzRpy(0, 0, 1, 0, 0, 0), Vec3(0.55, 0.45, 0.2), 10);
    const Population cyl = CylinderPopulation(d, Pose::FromXyzRpy(0, 0, 1, 0, 0, 0), 0.35, 0.1, 10);
    for (const Population& p : {box, cyl}) {
      const std::vector<Vec3> a = PopulationPositions(p, 42, 0);
      const std::vector<Vec3> b = PopulationPositions(p, 42, 0);
      const std::vector<Vec3> c = PopulationPositions(p, 43, 0);
      const std::vector<Vec3> other_population = PopulationPositions(p, 42, 1);
      EXPECT_EQ(a, b);
      EXPECT_NE(a, c);
      EXPECT_NE(a, other_population);
    }
  }
}

// ---------------------------------------------------------------------------------------------
// Bad populations

TEST(Candidates, BadPopulationsNameFileLineAndPopulation) {
  const Pose pose = Pose::FromXyzRpy(0, 0, 1, 0, 0, 0);
  const std::string where = "cell.world:41: ";
  const auto expect_bad = [&](Population p, const std::string& needle) {
    ExpectInputError([&] { PopulationPositions(p, 1, 0); }, where, "population 'box_pop'");
    ExpectInputError([&] { PopulationPositions(p, 1, 0); }, where, needle);
  };
  const Population good = BoxPopulation(Distribution::kRandom, pose, Vec3(1, 1, 1), 5);
  ASSERT_NO_THROW(PopulationPositions(good, 1, 0));

  Population p = good;
  p.count = 0;
  expect_bad(p, "model_count");
  p = good;
  p.count = -3;
  expect_bad(p, "model_count");
  p = good;
  p.box_size = Vec3(1, 0, 1);
  expect_bad(p, "size");
  p = good;
  p.box_size = Vec3(1, -1, 1);
  expect_bad(p, "size");
  p = good;
  p.box_size = Vec3(1, std::nan(""), 1);
  expect_bad(p, "size");
  p = good;
  p.region = RegionShape::kCylinder;
  p.radius = 0;
  p.length = 1;
  expect_bad(p, "radius");
  p.radius = 1;
  p.length = -1;
  expect_bad(p, "length");
  p = good;
  p.region = RegionShape::kCylinder;
  p.radius = 1;
  p.length = 1;
  p.distribution = Distribution::kGrid;
  p.rows = 2;
  p.cols = 2;
  expect_bad(p, "grid");
  p.distribution = Distribution::kLinearX;
  expect_bad(p, "linear-x");
  p = good;
  p.region = RegionShape::kNone;
  expect_bad(p, "random");
  p = good;
  p.distribution = Distribution::kGrid;
  p.region = RegionShape::kNone;
  p.rows = 0;
  p.cols = 3;
  expect_bad(p, "rows");
  p.rows = 3;
  p.step = Vec3(std::nan(""), 0, 0);
  expect_bad(p, "step");
  p = good;
  p.pose.position.x() = std::numeric_limits<double>::infinity();
  expect_bad(p, "pose");
}

// ---------------------------------------------------------------------------------------------
// Look-at

TEST(Candidates, LookAtColumnsAreFrontLeftUp) {
  // eye (2, 1, 1) → origin: front = (−2, −1, −1)/√6; left = Z × front ∝ (1, −2, 0)/√5 (horizontal);
  // up' = front × left has a positive z component.
  const Mat3 r = LookAt(Vec3(2, 1, 1), Vec3::Zero()).toRotationMatrix();
  EXPECT_TRUE(r.col(0).isApprox(Vec3(-2, -1, -1) / std::sqrt(6.0), 1e-12));
  EXPECT_TRUE(r.col(1).isApprox(Vec3(1, -2, 0) / std::sqrt(5.0), 1e-12));
  EXPECT_NEAR(r.col(1).z(), 0.0, 1e-15);
  EXPECT_TRUE(r.col(2).isApprox(r.col(0).cross(r.col(1)), 1e-12));
  EXPECT_GT(r.col(2).z(), 0.0);
  EXPECT_NEAR(r.determinant(), 1.0, 1e-12);
}

TEST(Candidates, LookAtStraightDownAndUpUsesPlusY) {
  // front = −Z: left = +Y, up' = (−Z) × Y = +X. front = +Z: up' = Z × Y = −X.
  const Mat3 down = LookAt(Vec3(0.3, 0.2, 2), Vec3(0.3, 0.2, 0)).toRotationMatrix();
  EXPECT_TRUE(down.col(0).isApprox(Vec3(0, 0, -1), 1e-12));
  EXPECT_TRUE(down.col(1).isApprox(Vec3(0, 1, 0), 1e-12));
  EXPECT_TRUE(down.col(2).isApprox(Vec3(1, 0, 0), 1e-12));
  const Mat3 up = LookAt(Vec3(0, 0, -1), Vec3(0, 0, 1)).toRotationMatrix();
  EXPECT_TRUE(up.col(0).isApprox(Vec3(0, 0, 1), 1e-12));
  EXPECT_TRUE(up.col(1).isApprox(Vec3(0, 1, 0), 1e-12));
  EXPECT_TRUE(up.col(2).isApprox(Vec3(-1, 0, 0), 1e-12));
}

TEST(Candidates, LookAtSamePointIsAnInputError) {
  EXPECT_THROW(LookAt(Vec3(1, 2, 3), Vec3(1, 2, 3)), InputError);
}

// ---------------------------------------------------------------------------------------------
// DeployCandidates

Population RandomBoxAbove(int count) {
  // A box above the origin (z ∈ [0.4, 0.6]), away from the observation point.
  return BoxPopulation(Distribution::kRandom, Pose::FromXyzRpy(0, 0, 0.5, 0, 0, 0),
                       Vec3(0.6, 0.6, 0.2), count);
}

TEST(Candidates, DeployNamesOrderTypesAndLookAt) {
  // A custom type with the Kinect 360's intrinsics matches the catalog; one with another range
  // keeps its own id.
  SensorType kinect = *FindCatalogType("kinect_xbox_360");
  kinect.id = "model_kinect";
  SensorType custom = kinect;
  custom.id = "my_cam";
  custom.far = 9.0;
  Population a = RandomBoxAbove(3);
  a.name = "pa";
  a.sensor_type = "model_kinect";
  Population b = RandomBoxAbove(2);
  b.name = "pb";
  b.sensor_type = "my_cam";
  ExplicitSensor s;
  s.name = "fixed";
  s.sensor_type = "my_cam";
  s.pose = Pose::FromXyzRpy(1, 0, 0, 0.3, 0.2, 0.1);

  DeployOptions options;
  options.observation_point = Vec3(0, 0, 0.1);
  const std::vector<Candidate> c = DeployCandidates({a, b}, {s}, {kinect, custom}, options);
  ASSERT_EQ(c.size(), 6u);
  const std::array<const char*, 6> names = {"pa_0", "pa_1", "pa_2", "pb_0", "pb_1", "fixed"};
  for (size_t i = 0; i < 6; ++i) EXPECT_EQ(c[i].name, names[i]);
  EXPECT_EQ(c[0].type_id, "kinect_xbox_360");
  EXPECT_EQ(c[3].type_id, "my_cam");
  EXPECT_EQ(c[5].type_id, "my_cam");
  EXPECT_EQ(c[0].population, "pa");
  EXPECT_EQ(c[4].population, "pb");
  EXPECT_EQ(c[5].population, "");
  EXPECT_DOUBLE_EQ(c[3].sensor.far, 9.0);

  // Positions are the population's; every body x axis points at the observation point and,
  // without roll, the y axis (left) is horizontal.
  const std::vector<Vec3> positions = PopulationPositions(a, options.seed, 0);
  for (size_t i = 0; i < 3; ++i) EXPECT_EQ(c[i].world_from_body.position, positions[i]);
  for (const Candidate& k : c) {
    const Mat3 r = k.world_from_body.rotation.toRotationMatrix();
    const Vec3 to_target = (options.observation_point - k.world_from_body.position).normalized();
    EXPECT_TRUE(r.col(0).isApprox(to_target, 1e-9)) << k.name;
    EXPECT_NEAR(r.col(1).z(), 0.0, 1e-12) << k.name;
    EXPECT_GT(r.col(2).z(), 0.0) << k.name;
  }
  // The explicit sensor's own rotation was replaced: front from (1, 0, 0) to (0, 0, 0.1).
  EXPECT_TRUE(c[5].world_from_body.position.isApprox(Vec3(1, 0, 0)));
}

TEST(Candidates, DeployLookingStraightDown) {
  // One clone right above the observation point: linear-z with n = 1 puts it at P's x and y:
  // origin (−0.05, −0.05, 0.95) + (0.05, 0.05, 0) = (0, 0, 0.95). Front −Z, left +Y.
  Population p = BoxPopulation(Distribution::kLinearZ, Pose::FromXyzRpy(0, 0, 1, 0, 0, 0),
                               Vec3(0.1, 0.1, 0.1), 1);
  const std::vector<Candidate> c = DeployCandidates({p}, {}, {}, DeployOptions{});
  ASSERT_EQ(c.size(), 1u);
  EXPECT_TRUE(c[0].world_from_body.position.isApprox(Vec3(0, 0, 0.95)));
  const Mat3 r = c[0].world_from_body.rotation.toRotationMatrix();
  EXPECT_TRUE(r.col(0).isApprox(Vec3(0, 0, -1), 1e-12));
  EXPECT_TRUE(r.col(1).isApprox(Vec3(0, 1, 0), 1e-12));
}

TEST(Candidates, MountOffsetComposesAfterOrientation) {
  // Model at (1, 0, 0) looking at the origin: front (−1, 0, 0), left = Z × front = (0, −1, 0),
  // up' = (0, 0, 1). Camera mounted at (0.1, 0, 0.05) with yaw 90° in the model: position
  // (1, 0, 0) + 0.1·front + 0.05·up' = (0.9, 0, 0.05) (a world-axes offset would give 1.1);
  // body x = R_lookat·Rz(90°)·X = R_lookat·Y = left = (0, −1, 0).
  ExplicitSensor s;
  s.name = "cam";
  s.sensor_type = "kinect_xbox_360";
  s.pose = Pose::FromXyzRpy(1, 0, 0, 0, 0, 0);
  s.model_from_camera = Pose::FromXyzRpy(0.1, 0, 0.05, 0, 0, kPi / 2);
  const std::vector<Candidate> c = DeployCandidates({}, {s}, {}, DeployOptions{});
  ASSERT_EQ(c.size(), 1u);
  EXPECT_LT((c[0].world_from_body.position - Vec3(0.9, 0, 0.05)).norm(), 1e-12);
  const Mat3 r = c[0].world_from_body.rotation.toRotationMatrix();
  EXPECT_TRUE(r.col(0).isApprox(Vec3(0, -1, 0), 1e-12));
  EXPECT_TRUE(r.col(2).isApprox(Vec3(0, 0, 1), 1e-12));

  // The same mount on a population clone.
  Population p = BoxPopulation(Distribution::kLinearX, Pose::FromXyzRpy(1, 0, 0, 0, 0, 0),
                               Vec3(0.2, 0.2, 0.2), 2);
  // Clone 0: origin (0.9, −0.1, −0.1) + (0, 0.1, 0.1) = (0.9, 0, 0): front (−1, 0, 0) again,
  // camera at (0.8, 0, 0.05).
  p.model_from_camera = s.model_from_camera;
  const std::vector<Candidate> pc = DeployCandidates({p}, {}, {}, DeployOptions{});
  ASSERT_EQ(pc.size(), 2u);
  EXPECT_LT((pc[0].world_from_body.position - Vec3(0.8, 0, 0.05)).norm(), 1e-12);
}

TEST(Candidates, ExplicitSensorWithoutLookAtKeepsItsRotation) {
  ExplicitSensor s;
  s.name = "fixed";
  s.sensor_type = "kinect_xbox_360";
  s.pose = Pose::FromXyzRpy(1, 2, 3, 0.1, 0.2, 0.3);
  s.look_at = false;
  DeployOptions options;
  options.random_roll = true;
  const std::vector<Candidate> c = DeployCandidates({}, {s}, {}, options);
  ASSERT_EQ(c.size(), 1u);
  EXPECT_TRUE(c[0].world_from_body.rotation.isApprox(s.pose.rotation, 1e-12));
  EXPECT_EQ(c[0].world_from_body.position, Vec3(1, 2, 3));
}

TEST(Candidates, RandomRollKeepsTheViewAndSpreadsTheRoll) {
  DeployOptions options;
  options.random_roll = true;
  options.seed = 9;
  const std::vector<Candidate> c = DeployCandidates({RandomBoxAbove(400)}, {}, {}, options);
  ASSERT_EQ(c.size(), 400u);
  std::vector<double> rolls;
  std::array<int, 4> quadrant{};
  for (const Candidate& k : c) {
    const Mat3 r = k.world_from_body.rotation.toRotationMatrix();
    const Vec3 to_target = (options.observation_point - k.world_from_body.position).normalized();
    EXPECT_TRUE(r.col(0).isApprox(to_target, 1e-9)) << k.name;
    // Roll = U(0, 4π) comes back from the decomposition wrapped into (−π, π].
    const double roll = RpyFromRotation(r).x();
    rolls.push_back(roll);
    const int q = std::clamp(static_cast<int>(std::floor((roll + kPi) / (kPi / 2))), 0, 3);
    ++quadrant[q];
  }
  EXPECT_LT(*std::min_element(rolls.begin(), rolls.end()), -2.9);
  EXPECT_GT(*std::max_element(rolls.begin(), rolls.end()), 2.9);
  // 400 uniform rolls: about 100 per quarter turn.
  for (int q = 0; q < 4; ++q) EXPECT_GT(quadrant[q], 60) << "quarter " << q;
  // Without roll the decomposed roll is 0 (left is horizontal).
  options.random_roll = false;
  for (const Candidate& k : DeployCandidates({RandomBoxAbove(20)}, {}, {}, options))
    EXPECT_NEAR(RpyFromRotation(k.world_from_body.rotation.toRotationMatrix()).x(), 0.0, 1e-9);
}

TEST(Candidates, RandomRollIsReproducibleAndSeeded) {
  // Explicit sensors keep their positions whatever the seed, so only the roll can change.
  std::vector<ExplicitSensor> sensors;
  for (int i = 0; i < 8; ++i) {
    ExplicitSensor s;
    s.name = fmt::format("s{}", i);
    s.sensor_type = "kinect_xbox_360";
    s.pose = Pose::FromXyzRpy(1.0 + 0.1 * i, 0.5, 0.8, 0, 0, 0);
    sensors.push_back(s);
  }
  DeployOptions options;
  options.random_roll = true;
  options.seed = 5;
  const std::vector<Candidate> a = DeployCandidates({}, sensors, {}, options);
  const std::vector<Candidate> b = DeployCandidates({}, sensors, {}, options);
  options.seed = 6;
  const std::vector<Candidate> c = DeployCandidates({}, sensors, {}, options);
  ASSERT_EQ(a.size(), 8u);
  int differ = 0;
  for (size_t i = 0; i < 8; ++i) {
    EXPECT_EQ(a[i].world_from_body.rotation.coeffs(), b[i].world_from_body.rotation.coeffs());
    EXPECT_EQ(a[i].world_from_body.position, c[i].world_from_body.position);
    if (!a[i].world_from_body.rotation.isApprox(c[i].world_from_body.rotation, 1e-9)) ++differ;
  }
  EXPECT_EQ(differ, 8);

  // An explicit sensor and a population clone at the same place do not share a roll stream.
  Population p = BoxPopulation(Distribution::kLinearZ, Pose::FromXyzRpy(1, 0.5, 0.8, 0, 0, 0),
                               Vec3(0.1, 0.1, 0.1), 1);
  // clone 0: (0.95, 0.45, 0.75) + (0.05, 0.05, 0) = (1, 0.5, 0.75).
  ExplicitSensor twin = sensors[0];
  twin.pose.position = Vec3(1, 0.5, 0.75);
  options.seed = 5;
  const std::vector<Candidate> both = DeployCandidates({p}, {twin}, {}, options);
  ASSERT_EQ(both.size(), 2u);
  EXPECT_TRUE(both[0].world_from_body.position.isApprox(both[1].world_from_body.position));
  EXPECT_FALSE(both[0].world_from_body.rotation.isApprox(both[1].world_from_body.rotation, 1e-9));
}

TEST(Candidates, DeployErrorsNameFileAndLine) {
  Population p = RandomBoxAbove(2);
  p.sensor_type = "no_such_camera";
  ExpectInputError([&] { DeployCandidates({p}, {}, {}, DeployOptions{}); },
                   "cell.world:41: ", "no_such_camera");

  ExplicitSensor s;
  s.name = "cam";
  s.sensor_type = "nope";
  s.file = "scene.yaml";
  s.line = 12;
  ExpectInputError([&] { DeployCandidates({}, {s}, {}, DeployOptions{}); },
                   "scene.yaml:12: ", "nope");

  // A sensor on the observation point has no viewing direction.
  s.sensor_type = "kinect_xbox_360";
  s.pose = Pose::FromXyzRpy(0.5, 0.5, 0.5, 0, 0, 0);
  DeployOptions options;
  options.observation_point = Vec3(0.5, 0.5, 0.5);
  ExpectInputError([&] { DeployCandidates({}, {s}, {}, options); }, "scene.yaml:12: ", "cam");

  // A bad population surfaces through DeployCandidates with its place.
  Population bad = RandomBoxAbove(0);
  ExpectInputError([&] { DeployCandidates({bad}, {}, {}, DeployOptions{}); },
                   "cell.world:41: ", "model_count");
}

}  // namespace
}  // namespace vantage
