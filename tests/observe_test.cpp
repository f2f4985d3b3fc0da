// Observe against analytic answers (SYSTEM.md coverage metric). Most boxes have faces mid-cell,
// one has them on grid planes; cameras have fine pixels (well below a cell) so that every
// visible cell receives a ray.
#include <gtest/gtest.h>
#include <tbb/global_control.h>

#include <algorithm>
#include <cmath>
#include <numbers>

#include "test_util.hpp"
#include "vantage/error.hpp"
#include "vantage/observe.hpp"
#include "vantage/visibility_file.hpp"
#include "vantage/reference.hpp"
#include "vantage/select.hpp"

namespace vantage {
namespace {

constexpr double kPi = std::numbers::pi;

SceneObject Box(const std::string& name, Role role, const Vec3& center, const Vec3& size) {
  TriangleMesh mesh = MakeBox(size);
  mesh.Transform(Pose{center, Quat::Identity()});
  return {name, role, std::move(mesh), {}};
}

// A camera at `eye` whose optical axis points along -x (body x -> world -x, body y -> -y).
Candidate CameraLookingMinusX(const Vec3& eye, int width, double hfov, double near, double far) {
  Candidate c;
  c.name = "cam";
  c.sensor = SensorType::FromFov("test", width, width, hfov, std::nullopt, near, far);
  c.type_id = "test";
  c.world_from_body = Pose{eye, Quat(Eigen::AngleAxisd(kPi, Vec3::UnitZ()))};
  return c;
}

// Rotates a camera built by CameraLookingMinusX about the world z axis through the origin.
Candidate RotatedAboutZ(Candidate c, double angle) {
  const Quat r(Eigen::AngleAxisd(angle, Vec3::UnitZ()));
  c.world_from_body = Pose{r * c.world_from_body.position, r * c.world_from_body.rotation};
  return c;
}

double CoverageOf(const Scene& scene, double cell, const std::vector<Candidate>& cameras) {
  const Reference reference = BuildReference(scene, {cell});
  const std::vector<Observation> obs = Observe(scene, reference, cameras);
  std::vector<uint32_t> all(cameras.size());
  for (size_t i = 0; i < all.size(); ++i) all[i] = static_cast<uint32_t>(i);
  return CoverageEvaluator(obs, reference.size()).Coverage(all);
}

// A cube centred at the origin with faces at ±2.5 F: mid-cell, in cell layers -3 and 2.
constexpr double kCell = 0.01;
constexpr double kHalf = 2.5 * kCell;  // faces at ±2.5 cells: mid-cell
// R: shell of the 6x6x6 block of cells -3..2 = 6³ - 4³ = 152 cells; one face: 6 x 6 = 36.
constexpr double kShell = 6 * 6 * 6 - 4 * 4 * 4;
constexpr double kFace = 6 * 6;

Scene CubeScene() {
  Scene scene;
  scene.objects.push_back(Box("cube", Role::kTarget, Vec3::Zero(), Vec3::Constant(2 * kHalf)));
  return scene;
}

TEST(Observe, CubeSeenHeadOnSeesExactlyOneFace) {
  // From (1, 0, 0) looking along -x only the face x = +2.5F faces the camera: its 36 cells.
  // Narrow 0.1 rad view at 1 m: 0.1 m wide over 400 px = 0.25 mm per pixel, far below F.
  const Candidate cam = CameraLookingMinusX(Vec3(1, 0, 0), 400, 0.1, 0.2, 3.0);
  EXPECT_DOUBLE_EQ(CoverageOf(CubeScene(), kCell, {cam}), kFace / kShell);
}

TEST(Observe, TwoOppositeCamerasSeeTheUnion) {
  const Candidate front = CameraLookingMinusX(Vec3(1, 0, 0), 400, 0.1, 0.2, 3.0);
  const Candidate back = RotatedAboutZ(front, kPi);
  EXPECT_DOUBLE_EQ(CoverageOf(CubeScene(), kCell, {back}), kFace / kShell);
  EXPECT_DOUBLE_EQ(CoverageOf(CubeScene(), kCell, {front, back}), 2 * kFace / kShell);
}

// Faces on grid planes: a cube with faces at ±3 F, F = 1/64 m so that q = p / F is exact and
// every face lies exactly on a cell boundary. The half-open cells put the face x = +3F in layer
// 3 and x = -3F in layer -3, both as R and as the hits (SYSTEM.md): R is the 7³ - 5³ = 218 cells
// of indices -3..3 with a ±3 among them. Head on, a face's hits have y and z inside (-3F, 3F):
// indices -3..2, 36 cells (its row and column at index 3 are touched only by the face's edges).
// Was: the hit origin + t d in float landed on either side of the plane ray by ray, and about
// half the face's cells were counted outside R.
TEST(Observe, FacesOnGridPlanesAreSeenInTheirOwnCells) {
  constexpr double kGridCell = 1.0 / 64;
  Scene scene;
  scene.objects.push_back(
      Box("cube", Role::kTarget, Vec3::Zero(), Vec3::Constant(6 * kGridCell)));
  const Candidate front = CameraLookingMinusX(Vec3(1, 0.001, 0.002), 400, 0.2, 0.2, 3.0);
  const Candidate back = RotatedAboutZ(front, kPi);
  ASSERT_EQ(BuildReference(scene, {kGridCell}).size(), 218u);
  EXPECT_DOUBLE_EQ(CoverageOf(scene, kGridCell, {front}), 36.0 / 218);
  EXPECT_DOUBLE_EQ(CoverageOf(scene, kGridCell, {back}), 36.0 / 218);
  EXPECT_DOUBLE_EQ(CoverageOf(scene, kGridCell, {front, back}), 72.0 / 218);
}

TEST(Observe, PlateHidingHalfTheFaceHalvesCoverage) {
  // A plate between camera and cube covering y >= 0: its edge plane y = 0 contains the camera,
  // so it hides exactly the cells with y index 0..2 (y >= 0): 18 of the 36.
  Scene scene = CubeScene();
  scene.objects.push_back(Box("plate", Role::kOccluder, Vec3(0.5, 0.25, 0), Vec3(0.01, 0.5, 0.5)));
  const Candidate cam = CameraLookingMinusX(Vec3(1, 0, 0), 400, 0.1, 0.2, 3.0);
  EXPECT_DOUBLE_EQ(CoverageOf(scene, kCell, {cam}), 0.5 * kFace / kShell);
}

// Point density (docs/constraints.md): a fronto-parallel plate seen head-on by two pinhole
// cameras at depths 0.5 m and 1 m. By hand: a pixel at depth t covers (t / f)² of the plate, so a
// cell of face F² holds F² f² / t² pixels: with F = 1 cm, f = 500 px, 100 at 0.5 m (1 mm pixels)
// and 25 at 1 m (2 mm pixels). The pixel centres sit at (j + 1/2) mm (near) and (2 j + 1) mm
// (far), never on a cell boundary, so each of the plate's 4 x 4 front cells holds exactly 10 x 10
// or 5 x 5 of them; no ray reaches the plate's sides.
TEST(Observe, PointCountsOfAPlateAtTwoDistances) {
  Scene scene;
  // Front face at x = F/2 (mid-cell of layer 0), y and z in [-2F, 2F] (cell boundaries).
  scene.objects.push_back(Box("plate", Role::kTarget, Vec3::Zero(), Vec3(kCell, 4 * kCell, 4 * kCell)));
  const auto camera = [](double depth, const std::string& name) {
    Candidate c = CameraLookingMinusX(Vec3(0.5 * kCell + depth, 0, 0), 60, 0.1, 0.1, 3.0);
    c.name = name;
    c.sensor.fx = c.sensor.fy = 500;
    c.sensor.cx = c.sensor.cy = 30;
    return c;
  };
  // The far camera first: plain coverage ties and keeps the lower index, the far one.
  const std::vector<Candidate> cameras = {camera(1.0, "far"), camera(0.5, "near")};
  const Reference reference = BuildReference(scene, {kCell});
  const std::vector<Observation> obs = Observe(scene, reference, cameras);
  const auto hits_in = [&](const Observation& o, int64_t y, int64_t z) -> int {
    const uint64_t key = PackVoxel({0, y, z});
    const auto r = std::lower_bound(reference.keys.begin(), reference.keys.end(), key);
    if (r == reference.keys.end() || *r != key) return -1;
    const auto cell = static_cast<uint32_t>(r - reference.keys.begin());
    const auto j = std::lower_bound(o.reference_indices.begin(), o.reference_indices.end(), cell);
    if (j == o.reference_indices.end() || *j != cell) return 0;
    return o.reference_hits.at(static_cast<size_t>(j - o.reference_indices.begin()));
  };
  for (int64_t y = -2; y < 2; ++y) {
    for (int64_t z = -2; z < 2; ++z) {
      EXPECT_EQ(hits_in(obs[0], y, z), 25) << y << " " << z;
      EXPECT_EQ(hits_in(obs[1], y, z), 100) << y << " " << z;
    }
  }
  for (const Observation& o : obs) {
    ASSERT_TRUE(o.has_point_counts());
    EXPECT_EQ(o.reference_indices.size(), 16u);  // the front face only
  }
  const double face = 16.0 / static_cast<double>(reference.size());
  const CoverageEvaluator evaluator(obs, reference.size());
  EXPECT_DOUBLE_EQ(evaluator.PointCoverage(std::vector<uint32_t>{0}, 25), face);
  EXPECT_DOUBLE_EQ(evaluator.PointCoverage(std::vector<uint32_t>{0}, 26), 0.0);
  EXPECT_DOUBLE_EQ(evaluator.PointCoverage(std::vector<uint32_t>{1}, 100), face);
  EXPECT_DOUBLE_EQ(evaluator.PointCoverage(std::vector<uint32_t>{0, 1}, 125), face);
  EXPECT_DOUBLE_EQ(evaluator.PointCoverage(std::vector<uint32_t>{0, 1}, 126), 0.0);
  // One sensor and 60 points a cell (60 per cm²: F² = 1 cm²): the near one only; plain coverage
  // cannot tell them apart and keeps the far one.
  for (const Method method : {Method::kGreedy, Method::kLocal, Method::kExact, Method::kRansac}) {
    SelectOptions options;
    options.method = method;
    options.n = 1;
    options.min_points = 60;
    const Selection s = Select(obs, reference.size(), options).front();
    EXPECT_EQ(s.chosen, std::vector<uint32_t>{1}) << s.method;
    EXPECT_DOUBLE_EQ(s.coverage, face) << s.method;
    options.min_points.reset();
    if (method == Method::kRansac) continue;  // its random draws break ties by draw order
    EXPECT_EQ(Select(obs, reference.size(), options).front().chosen, std::vector<uint32_t>{0});
  }
  // 120 points: neither alone (100, 25), both together (125).
  SelectOptions both;
  both.method = Method::kExact;
  both.n = 1;
  both.min_points = 120;
  EXPECT_DOUBLE_EQ(Select(obs, reference.size(), both).front().coverage, 0.0);
  both.n = 2;
  EXPECT_DOUBLE_EQ(Select(obs, reference.size(), both).front().coverage, face);
}

TEST(Observe, TargetBeyondFarIsNotSeen) {
  const Candidate cam = CameraLookingMinusX(Vec3(1, 0, 0), 400, 0.1, 0.2, 0.9);
  EXPECT_EQ(CoverageOf(CubeScene(), kCell, {cam}), 0.0);
}

TEST(Observe, GeometryNearerThanNearStillBlocks) {
  // The plate sits at depth 0.5, nearer than near = 0.6: the sensor is blind there, but the
  // plate still hides half of the face (it is not clipped away as in OpenGL).
  Scene scene = CubeScene();
  scene.objects.push_back(Box("plate", Role::kOccluder, Vec3(0.5, 0.25, 0), Vec3(0.01, 0.5, 0.5)));
  const Candidate cam = CameraLookingMinusX(Vec3(1, 0, 0), 400, 0.1, 0.6, 3.0);
  EXPECT_DOUBLE_EQ(CoverageOf(scene, kCell, {cam}), 0.5 * kFace / kShell);
}

TEST(Observe, TargetNearerThanNearIsNotSeen) {
  const Candidate cam = CameraLookingMinusX(Vec3(1, 0, 0), 400, 0.1, 1.0, 3.0);
  EXPECT_EQ(CoverageOf(CubeScene(), kCell, {cam}), 0.0);
}

// Share of the sphere's surface cells that lie on the cap n_x > c, by the density of cells a
// surface crosses per unit area, (|nx| + |ny| + |nz|) / F² (exact in the limit F << r).
double CapCellShare(double c) {
  const int steps = 1500;
  double cap = 0, all = 0;
  for (int i = 0; i < steps; ++i) {
    const double theta = kPi * (i + 0.5) / steps;
    for (int j = 0; j < steps; ++j) {
      const double phi = 2 * kPi * (j + 0.5) / steps;
      const double w = (std::abs(std::cos(theta)) +
                        std::sin(theta) * (std::abs(std::cos(phi)) + std::abs(std::sin(phi)))) *
                       std::sin(theta);
      all += w;
      if (std::cos(theta) > c) cap += w;
    }
  }
  return cap / all;
}

TEST(Observe, SphereSeenFromDistanceShowsItsCap) {
  // A camera at distance d sees the cap n_x > r/d: (1 - r/d)/2 of the area. In cells, the cap
  // is weighted by the cell density above. Tolerance 0.02: cells of the silhouette band, whose
  // visible sliver projects below one pixel (band ≈ sqrt(2 r · pixel) ≈ 2 cells wide along a
  // rim of ≈ 300 cells, against ≈ 47 000 cells of R ≈ 1.3 %), plus partly visible rim cells.
  const double r = 0.1, d = 0.5, cell = 0.002;
  Scene scene;
  scene.objects.push_back({"ball", Role::kTarget, MakeSphere(r, cell / 10), {}});
  const double hfov = 2 * std::asin(r / d) * 1.05;
  const Candidate cam = CameraLookingMinusX(Vec3(d, 0, 0), 2000, hfov, 0.1, 2.0);
  const double coverage = CoverageOf(scene, cell, {cam});
  RecordProperty("coverage", std::to_string(coverage));
  RecordProperty("cell_model", std::to_string(CapCellShare(r / d)));
  EXPECT_NEAR(coverage, CapCellShare(r / d), 0.02);
  // The headline area share, (1 - r/d)/2 = 0.4, differs from the cell share only by the
  // orientation weighting (the cap faces the x axis, where cells per area are fewest).
  EXPECT_NEAR(coverage, (1 - r / d) / 2, 0.03);
}

TEST(Observe, CullingGivesTheSameSetsAsTracingEveryPixel) {
  Scene scene = CubeScene();
  scene.objects.push_back(Box("plate", Role::kOccluder, Vec3(0.5, 0.25, 0), Vec3(0.01, 0.5, 0.5)));
  scene.objects.push_back(Box("cube2", Role::kTarget, Vec3(0, 0.3, 0.1), Vec3(0.05, 0.05, 0.05)));
  std::vector<Candidate> cams;
  for (int k = 0; k < 12; ++k) {
    Candidate c = RotatedAboutZ(CameraLookingMinusX(Vec3(0.8, 0.05 * k - 0.3, 0.1), 160, 1.2, 0.1, 2.0),
                                0.4 * k);
    c.name = "cam" + std::to_string(k);
    cams.push_back(c);
  }
  const Reference reference = BuildReference(scene, {kCell});
  ObserveOptions all_pixels;
  all_pixels.cull = false;
  const auto culled = Observe(scene, reference, cams);
  const auto full = Observe(scene, reference, cams, all_pixels);
  uint64_t culled_rays = 0, full_rays = 0;
  for (size_t i = 0; i < cams.size(); ++i) {
    EXPECT_EQ(culled[i].reference_indices, full[i].reference_indices) << i;
    EXPECT_EQ(culled[i].outside_keys, full[i].outside_keys) << i;
    culled_rays += culled[i].rays_traced;
    full_rays += full[i].rays_traced;
  }
  EXPECT_EQ(full_rays, uint64_t{12} * 160 * 160);
  size_t seen = 0;
  for (const Observation& o : full) seen += o.reference_indices.size();
  EXPECT_GT(seen, 100u);  // the comparison is not vacuous
  EXPECT_LT(culled_rays, full_rays);
}

// Issue 15 (found by the pipeline fuzzer): a field of view of 1e-300 rad is a focal length of
// about 1e302 px, so a box beside the optical axis projects to pixel 1e301, which was cast to int
// (undefined; in practice INT_MIN, and a whole image of rays traced for a box no pixel sees). All
// the pixels' rays are the optical axis to the float ray caster: one camera sees the one cell its
// axis meets, the other, whose axis passes 20 cm beside the cube, sees nothing and traces nothing.
TEST(Observe, FocalLengthsOfBillionsOfPixelsAreCulledExactly) {
  const Scene scene = CubeScene();
  // Axis hits the face x = +2.5 cells at (0.025, 0.005, 0.005): mid-cell, in cell (2, 0, 0).
  Candidate hits = CameraLookingMinusX(Vec3(0.5, 0.005, 0.005), 40, 1e-300, 0.1, 2.0);
  // The cube lies at body y = -0.2 m: projected to u = cx + 0.4 fx, about +1e301.
  Candidate misses = CameraLookingMinusX(Vec3(0.5, -0.2, 0), 40, 1e-300, 0.1, 2.0);
  ASSERT_GT(hits.sensor.fx, 1e300);
  hits.sensor.Validate("");
  const std::vector<Candidate> cams = {hits, misses};
  const Reference reference = BuildReference(scene, {kCell});
  ObserveOptions all_pixels;
  all_pixels.cull = false;
  const auto culled = Observe(scene, reference, cams);
  const auto full = Observe(scene, reference, cams, all_pixels);
  for (size_t i = 0; i < cams.size(); ++i) {
    EXPECT_EQ(culled[i].reference_indices, full[i].reference_indices) << i;
    EXPECT_EQ(culled[i].outside_keys, full[i].outside_keys) << i;
    EXPECT_EQ(full[i].rays_traced, uint64_t{40} * 40) << i;
  }
  ASSERT_EQ(full[0].reference_indices.size(), 1u);
  EXPECT_EQ(reference.keys[full[0].reference_indices[0]], PackVoxel({2, 0, 0}));
  EXPECT_TRUE(full[1].reference_indices.empty());
  EXPECT_EQ(culled[1].rays_traced, 0u);
}

TEST(Observe, SameSetsWithOneOrTwoThreads) {
  const Scene scene = CubeScene();
  std::vector<Candidate> cams;
  for (int k = 0; k < 8; ++k) cams.push_back(RotatedAboutZ(CameraLookingMinusX(Vec3(0.6, 0, 0.05 * k), 200, 0.5, 0.1, 2.0), 0.7 * k));
  const Reference reference = BuildReference(scene, {kCell});
  std::vector<Observation> one, two;
  {
    tbb::global_control limit(tbb::global_control::max_allowed_parallelism, 1);
    one = Observe(scene, reference, cams);
  }
  {
    tbb::global_control limit(tbb::global_control::max_allowed_parallelism, 2);
    two = Observe(scene, reference, cams);
  }
  size_t seen = 0;
  for (size_t i = 0; i < cams.size(); ++i) {
    EXPECT_EQ(one[i].reference_indices, two[i].reference_indices);
    EXPECT_EQ(one[i].outside_keys, two[i].outside_keys);
    seen += one[i].reference_indices.size();
  }
  EXPECT_GT(seen, 8u * 20);  // every camera sees at least part of a face
}

TEST(Camera, FocalLengthFromHorizontalFov) {
  // 90° over 640 px: fx = 320 / tan(45°) = 320.
  const SensorType t = SensorType::FromFov("t", 640, 480, kPi / 2, std::nullopt, 0.1, 1);
  EXPECT_NEAR(t.fx, 320.0, 1e-9);
  EXPECT_NEAR(t.fy, 320.0, 1e-9);
  EXPECT_DOUBLE_EQ(t.cx, 320.0);
  EXPECT_DOUBLE_EQ(t.cy, 240.0);
  // Vertical fov from the aspect ratio: 2 atan(240 / 320).
  EXPECT_NEAR(t.VerticalFov(), 2 * std::atan(0.75), 1e-12);
}

TEST(Camera, ProjectThenBackProjectLandsInTheSameVoxel) {
  const SensorType t = SensorType::FromFov("t", 640, 480, 1.0, std::nullopt, 0.1, 5);
  const Pose world_from_body{Vec3(0.3, -0.2, 1.1), Quat(Eigen::AngleAxisd(0.7, Vec3(1, 2, 3).normalized()))};
  const double cell = 0.005;
  int checked = 0;
  for (int u = 3; u < 640; u += 37) {
    for (int v = 5; v < 480; v += 41) {
      const double depth = 0.5 + 0.001 * (u + v);
      const Vec3 p_world = world_from_body * (depth * PixelRayInBody(t, u, v));
      const auto uv = ProjectBodyPoint(t, world_from_body.Inverse() * p_world);
      ASSERT_TRUE(uv.has_value());
      EXPECT_NEAR(uv->x(), u + 0.5, 1e-9);  // the pixel centre
      EXPECT_NEAR(uv->y(), v + 0.5, 1e-9);
      const Vec3 back = world_from_body * (depth * PixelRayInBody(t, static_cast<int>(uv->x()), static_cast<int>(uv->y())));
      EXPECT_EQ(VoxelKeyOf(back, cell), VoxelKeyOf(p_world, cell));
      ++checked;
    }
  }
  EXPECT_GT(checked, 100);
}

TEST(Camera, ImageAxesFollowTheBodyFrame) {
  // u grows to the right = -y of the body, v grows down = -z; depth along +x.
  const SensorType t = SensorType::FromFov("t", 100, 100, kPi / 2, std::nullopt, 0.1, 5);
  EXPECT_LT(PixelRayInBody(t, 99, 50).y(), 0);  // right column looks to -y
  EXPECT_GT(PixelRayInBody(t, 50, 0).z(), 0);   // top row looks up
  EXPECT_DOUBLE_EQ(PixelRayInBody(t, 10, 10).x(), 1.0);
}

}  // namespace
}  // namespace vantage
