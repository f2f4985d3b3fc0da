// Measurement quality (issue 9): the incidence and depth-noise filters drop exactly the pixels an
// analytic ray-plane computation says they must, and the catalog's noise models give the values
// of the papers and datasheets they cite (docs/sensor-models.md).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <numbers>

#include "vantage/error.hpp"
#include "vantage/observe.hpp"
#include "vantage/visibility_file.hpp"
#include "vantage/reference.hpp"
#include "vantage/sensors.hpp"

namespace vantage {
namespace {

constexpr double kPi = std::numbers::pi;

// A 4 m x 4 m target plane through the origin whose normal is (cos a, sin a, 0): the plane
// x = 0 turned by `a` about z, seen from (1, 0, 0) along -x.
struct TiltedPlane {
  double a;
  Vec3 normal() const { return Vec3(std::cos(a), std::sin(a), 0); }
  Scene MakeScene() const {
    TriangleMesh mesh = MakePlane(4, 4);  // normal +z in its own frame
    const Quat to_x(Eigen::AngleAxisd(kPi / 2, Vec3::UnitY()));  // +z -> +x
    const Quat turn(Eigen::AngleAxisd(a, Vec3::UnitZ()));
    mesh.Transform(Pose{Vec3::Zero(), turn * to_x});
    Scene scene;
    scene.objects.push_back({"plane", Role::kTarget, std::move(mesh), {}});
    return scene;
  }
};

Candidate Camera(int width, double hfov) {
  Candidate c;
  c.name = "cam";
  c.sensor = SensorType::FromFov("test", width, width, hfov, std::nullopt, 0.1, 5.0);
  c.type_id = "test";
  c.world_from_body = Pose{Vec3(1, 0, 0), Quat(Eigen::AngleAxisd(kPi, Vec3::UnitZ()))};
  return c;
}

// The analytic side: for every pixel, the world ray (depth component 1), its hit depth on the
// plane and the cosine of its incidence angle.
struct PixelHit {
  double depth, cos_incidence;
  Vec3 point;
};

std::vector<PixelHit> AnalyticHits(const Candidate& cam, const TiltedPlane& plane) {
  std::vector<PixelHit> hits;
  const Mat3 r = cam.world_from_body.rotation.toRotationMatrix();
  const Vec3 o = cam.world_from_body.position;
  const Vec3 n = plane.normal();
  for (int v = 0; v < cam.sensor.height; ++v) {
    for (int u = 0; u < cam.sensor.width; ++u) {
      const Vec3 d = r * PixelRayInBody(cam.sensor, u, v);
      const double t = -n.dot(o) / n.dot(d);  // plane through the origin
      hits.push_back({t, std::abs(n.dot(d)) / d.norm(), o + t * d});
    }
  }
  return hits;
}

TEST(Quality, IncidenceLimitDropsExactlyThePixelsBeyondIt) {
  const TiltedPlane plane{50 * kPi / 180};
  const Candidate cam = Camera(120, 0.8);
  const Scene scene = plane.MakeScene();
  const Reference reference = BuildReference(scene, {0.02});
  const double limit_deg = 55;
  const double cos_limit = std::cos(limit_deg * kPi / 180);
  uint64_t expected = 0;
  double margin = 1;
  for (const PixelHit& h : AnalyticHits(cam, plane)) {
    ASSERT_LT(h.point.cwiseAbs().maxCoeff(), 1.9);  // every pixel hits the 4 m plane
    expected += h.cos_incidence >= cos_limit ? 1 : 0;
    margin = std::min(margin, std::abs(h.cos_incidence - cos_limit));
  }
  ASSERT_GT(margin, 1e-5);  // no pixel sits on the limit, so float rays cannot flip one
  ASSERT_GT(expected, 1000u);
  ASSERT_LT(expected, 120u * 120 - 1000);  // the limit cuts through the image

  ObserveOptions options;
  options.quality.max_incidence_deg = limit_deg;
  const Observation o = Observe(scene, reference, {&cam, 1}, options).front();
  EXPECT_EQ(o.target_pixels, 120u * 120);
  EXPECT_EQ(o.quality_pixels, expected);
  // The filtered cells are a proper subset of the plain ones.
  EXPECT_TRUE(std::includes(o.plain_reference_indices.begin(), o.plain_reference_indices.end(),
                            o.reference_indices.begin(), o.reference_indices.end()));
  EXPECT_LT(o.reference_indices.size(), o.plain_reference_indices.size());
  EXPECT_GT(o.reference_indices.size(), 0u);

  // 90 degrees filters nothing: the same cells as no filter at all.
  const Observation plain = Observe(scene, reference, {&cam, 1}).front();
  options.quality.max_incidence_deg = 90;
  const Observation all = Observe(scene, reference, {&cam, 1}, options).front();
  EXPECT_EQ(all.reference_indices, plain.reference_indices);
  EXPECT_EQ(all.plain_reference_indices, plain.reference_indices);
  EXPECT_TRUE(plain.plain_reference_indices.empty());
  EXPECT_EQ(plain.quality_pixels, plain.target_pixels);
}

TEST(Quality, DepthNoiseLimitKeepsThePixelsNearerThanItsDepth) {
  const TiltedPlane plane{35 * kPi / 180};
  Candidate cam = Camera(100, 1.0);
  cam.sensor.depth_noise = DepthNoise{0, 0, 0.002, "test: 2 mm at 1 m, growing with z^2"};
  const Scene scene = plane.MakeScene();
  const Reference reference = BuildReference(scene, {0.02});
  // sigma(z) = 0.002 z^2 <= 0.0025  <=>  z <= sqrt(1.25).
  const double limit = 0.0025, z_limit = std::sqrt(1.25);
  uint64_t expected = 0;
  double margin = 1;
  for (const PixelHit& h : AnalyticHits(cam, plane)) {
    expected += h.depth <= z_limit ? 1 : 0;
    margin = std::min(margin, std::abs(h.depth - z_limit));
  }
  ASSERT_GT(margin, 1e-5);
  ASSERT_GT(expected, 500u);
  ASSERT_LT(expected, 100u * 100 - 500);

  ObserveOptions options;
  options.quality.max_depth_noise = limit;
  const Observation o = Observe(scene, reference, {&cam, 1}, options).front();
  EXPECT_EQ(o.target_pixels, 100u * 100);
  EXPECT_EQ(o.quality_pixels, expected);

  // A type without a noise model is not filtered by depth noise.
  cam.sensor.depth_noise.reset();
  const Observation unknown = Observe(scene, reference, {&cam, 1}, options).front();
  EXPECT_EQ(unknown.quality_pixels, unknown.target_pixels);
}

TEST(Quality, CatalogNoiseModelsMatchTheirSources) {
  // Nguyen et al. 2012: sigma = 0.0012 + 0.0019 (z - 0.4)^2 m.
  const SensorType* kinect = FindCatalogType("kinect_xbox_360");
  ASSERT_TRUE(kinect && kinect->depth_noise);
  EXPECT_NEAR(kinect->depth_noise->Sigma(0.4), 0.0012, 1e-12);
  EXPECT_NEAR(kinect->depth_noise->Sigma(1.4), 0.0031, 1e-12);
  EXPECT_NEAR(kinect->depth_noise->Sigma(3.0), 0.0012 + 0.0019 * 2.6 * 2.6, 1e-12);
  // Intel D400: z^2 * 0.08 px / (fx * baseline); D415 fx = 640 / tan(hfov / 2), baseline 55 mm.
  const SensorType* d415 = FindCatalogType("intel_realsense_d415");
  ASSERT_TRUE(d415 && d415->depth_noise);
  const double fx = 640 / std::tan(1.106539 / 2);
  EXPECT_NEAR(d415->depth_noise->Sigma(2.0), 4 * 0.08 / (fx * 0.055), 1e-12);
  EXPECT_NEAR(d415->depth_noise->Sigma(1.0), 0.0014, 0.0001);  // about 1.4 mm at 1 m
  // Kinect for Xbox One (Fankhauser et al. 2015): 1.5 - 0.5 z + 0.3 z^2 mm.
  EXPECT_NEAR(FindCatalogType("kinect_xbox_one")->depth_noise->Sigma(2.0), 0.0017, 1e-12);
  // Azure Kinect: constant 17 mm (datasheet bound).
  EXPECT_DOUBLE_EQ(FindCatalogType("azure_kinect_nfov")->depth_noise->Sigma(3.0), 0.017);
  // Types without a published model carry none rather than a guess.
  EXPECT_FALSE(FindCatalogType("intel_realsense_sr300")->depth_noise.has_value());

  // A candidate whose type matched a catalog id takes that entry's model.
  Candidate c;
  c.type_id = "intel_realsense_d415";
  c.sensor = *d415;
  c.sensor.depth_noise.reset();
  ASSERT_NE(NoiseModelOf(c), nullptr);
  EXPECT_DOUBLE_EQ(NoiseModelOf(c)->c, d415->depth_noise->c);
}

// Nguyen, Izadi and Lovell 2012, evaluated by hand at chosen (z, theta): sigma_z = 0.0012 +
// 0.0019 (z - 0.4)^2 + 0.0001 / sqrt(z) theta^2 / (pi/2 - theta)^2 [m].
TEST(Quality, KinectNoiseGrowsWithIncidenceAsNguyenEtAlFit) {
  const SensorType* kinect = FindCatalogType("kinect_xbox_360");
  ASSERT_TRUE(kinect && kinect->depth_noise);
  const DepthNoise& n = *kinect->depth_noise;
  EXPECT_DOUBLE_EQ(n.incidence, 0.0001);
  EXPECT_NE(n.source.find("Nguyen"), std::string::npos);
  EXPECT_NEAR(n.Sigma(1.0, 0.0), 0.001884, 1e-12);           // no incidence term at 0
  EXPECT_NEAR(n.Sigma(1.0, kPi / 4), 0.001884 + 0.0001, 1e-12);  // theta / (pi/2 - theta) = 1
  // z = 0.64, theta = 60 deg: ratio 2, 0.0001 / 0.8 * 4 = 0.5 mm.
  EXPECT_NEAR(n.Sigma(0.64, kPi / 3), 0.0012 + 0.0019 * 0.24 * 0.24 + 0.0005, 1e-12);
  // z = 2.25, theta = 80 deg: ratio 8, 0.0001 / 1.5 * 64.
  EXPECT_NEAR(n.Sigma(2.25, 80 * kPi / 180), 0.0012 + 0.0019 * 1.85 * 1.85 + 0.0064 / 1.5, 1e-12);
  EXPECT_TRUE(std::isinf(n.Sigma(1.0, kPi / 2)));  // grazing: no depth
  // A model without the term ignores the angle.
  const DepthNoise flat{0.001, 0, 0.002, "test"};
  EXPECT_DOUBLE_EQ(flat.Sigma(1.5, 1.5), flat.Sigma(1.5));
}

// A plane tilted by 60 deg seen by a Kinect: --max-depth-noise keeps exactly the pixels whose
// analytic sigma(z, theta) is within the limit, and the incidence term drops grazing pixels the
// depth alone would keep.
TEST(Quality, DepthNoiseLimitDropsGrazingPixelsWhereSigmaOfZAndThetaExceedsIt) {
  const TiltedPlane plane{60 * kPi / 180};
  Candidate cam = Camera(100, 0.7);
  cam.sensor.depth_noise = FindCatalogType("kinect_xbox_360")->depth_noise;
  const DepthNoise& noise = *cam.sensor.depth_noise;
  const Scene scene = plane.MakeScene();
  const Reference reference = BuildReference(scene, {0.02});
  const double limit = 0.0025;
  uint64_t expected = 0, by_depth_alone = 0;
  double margin = 1;
  for (const PixelHit& h : AnalyticHits(cam, plane)) {
    ASSERT_LT(h.point.cwiseAbs().maxCoeff(), 1.9);  // every pixel hits the 4 m plane
    const double sigma = noise.Sigma(h.depth, std::acos(h.cos_incidence));
    expected += sigma <= limit ? 1 : 0;
    by_depth_alone += noise.Sigma(h.depth) <= limit ? 1 : 0;
    margin = std::min(margin, std::abs(sigma - limit));
  }
  ASSERT_GT(margin, 1e-8);  // no pixel within float rounding of the limit
  ASSERT_GT(expected, 1000u);
  ASSERT_GT(by_depth_alone, expected + 500);  // the term matters on this plane

  ObserveOptions options;
  options.quality.max_depth_noise = limit;
  const Observation o = Observe(scene, reference, {&cam, 1}, options).front();
  EXPECT_EQ(o.target_pixels, 100u * 100);
  EXPECT_EQ(o.quality_pixels, expected);
  // Without the term, the depth alone decides.
  cam.sensor.depth_noise->incidence = 0;
  EXPECT_EQ(Observe(scene, reference, {&cam, 1}, options).front().quality_pixels, by_depth_alone);
}

TEST(Quality, RejectsLimitsOutOfRange) {
  for (double deg : {0.0, -5.0, 91.0, std::nan("")}) {
    QualityFilter q;
    q.max_incidence_deg = deg;
    EXPECT_THROW(q.Validate(), InputError) << deg;
  }
  QualityFilter q;
  q.max_depth_noise = -0.001;
  EXPECT_THROW(q.Validate(), InputError);
  SensorType t = *FindCatalogType("intel_realsense_d415");
  t.depth_noise = DepthNoise{-0.01, 0, 0.001, ""};  // negative at the near end
  EXPECT_THROW(t.Validate(), InputError);
  for (double incidence : {-0.0001, std::nan(""), HUGE_VAL}) {
    t.depth_noise = DepthNoise{0.001, 0, 0.001, "", incidence};
    EXPECT_THROW(t.Validate(), InputError) << incidence;
  }
}

}  // namespace
}  // namespace vantage
