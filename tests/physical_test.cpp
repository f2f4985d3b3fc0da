// The physical sensor model (issue 43): a pixel's hit counts only where the type's second
// aperture (projector, second imager) sees the point and stereo can match it. Each test checks
// observe against geometry worked out by hand: a step's projector shadow, stereo's nearest depth
// f·B/d_max, an aperture looking elsewhere; and bad apertures refused at their line.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <numbers>
#include <set>

#include <nlohmann/json.hpp>

#include "test_util.hpp"
#include "vantage/observe.hpp"
#include "vantage/reference.hpp"
#include "vantage/sensors.hpp"

namespace vantage {
namespace {

constexpr double kPi = std::numbers::pi;

ObserveOptions Model(bool physical) {
  ObserveOptions options;
  options.physical = physical;
  return options;
}

std::set<uint64_t> CellsOf(const Observation& o, const Reference& reference) {
  std::set<uint64_t> cells;
  for (uint32_t i : o.reference_indices) cells.insert(reference.keys[i]);
  return cells;
}

// A box of height h on a plane, a camera at height H looking straight down with its image's
// right along +x, and a projector offset by B along +x. The box covers x >= 0 (beyond the image),
// so its edge at x = 0 lies under the camera. The projector's rays over that edge reach the plane
// at x = -h B / (H - h): the strip [-hB/(H-h), 0] is seen by the camera but unlit.
struct Step {
  double H = 2.0, h = 0.5, baseline = 0.3, cell = 0.02;

  Scene MakeScene() const {
    Scene scene;
    scene.objects.push_back({"floor", Role::kTarget, MakePlane(4, 4), {}});
    TriangleMesh box = MakeBox(Vec3(2, 4, h));
    box.Transform(Pose{Vec3(1, 0, h / 2), Quat::Identity()});
    scene.objects.push_back({"step", Role::kOccluder, std::move(box), {}});
    return scene;
  }

  Candidate Camera() const {
    Candidate c;
    c.name = "cam";
    c.type_id = "structured_light";
    // 301 px over 0.5 rad: pixel centres fall off the cell boundaries of the strip.
    c.sensor = SensorType::FromFov(c.type_id, 301, 301, 0.5, std::nullopt, 0.1, 5.0);
    SecondAperture projector;
    projector.kind = SecondAperture::Kind::kProjector;
    projector.baseline = baseline;
    projector.hfov = projector.vfov = 2.0;  // wide: the whole image is in its field
    c.sensor.second_aperture = projector;
    // Body x (forward) = -z, body -y (image right) = +x, body z = +y.
    Mat3 r;
    r.col(0) = Vec3(0, 0, -1);
    r.col(1) = Vec3(-1, 0, 0);
    r.col(2) = Vec3(0, 1, 0);
    c.world_from_body = Pose{Vec3(0, 0, H), Quat(r)};
    return c;
  }
};

TEST(Physical, StepShadowDropsExactlyTheStripGeometryGives) {
  const Step step;
  const double strip = step.h * step.baseline / (step.H - step.h);  // 0.1 m: 5 cells
  ASSERT_NEAR(strip, 0.1, 1e-12);
  const Scene scene = step.MakeScene();
  const Reference reference = BuildReference(scene, {step.cell});
  const std::vector<Candidate> cams = {step.Camera()};
  const std::set<uint64_t> ideal = CellsOf(Observe(scene, reference, cams, Model(false))[0], reference);
  const std::set<uint64_t> physical =
      CellsOf(Observe(scene, reference, cams, Model(true))[0], reference);
  ASSERT_GT(ideal.size(), 500u);
  // Cell by cell: a floor cell is dropped exactly when its x extent lies inside the strip.
  size_t expected_drops = 0;
  for (uint64_t key : ideal) {
    const VoxelIndex index = UnpackVoxel(key);
    const double x0 = index[0] * step.cell, x1 = x0 + step.cell;
    const bool in_strip = x0 >= -strip - 1e-9 && x1 <= 1e-9;
    expected_drops += in_strip ? 1 : 0;
    EXPECT_EQ(physical.count(key) == 0, in_strip)
        << "cell x in [" << x0 << ", " << x1 << "], y index " << index[1];
  }
  // Every observed row of the image crosses the strip: 5 cells per row.
  EXPECT_GT(expected_drops, 5u * 40);
  EXPECT_EQ(ideal.size() - physical.size(), expected_drops);
  for (uint64_t key : physical) EXPECT_EQ(ideal.count(key), 1u);  // nothing gained
}

TEST(Physical, ZeroBaselineDropsNothing) {
  Step step;
  step.baseline = 0;
  const Scene scene = step.MakeScene();
  const Reference reference = BuildReference(scene, {step.cell});
  const std::vector<Candidate> cams = {step.Camera()};
  const Observation ideal = Observe(scene, reference, cams, Model(false))[0];
  const Observation physical = Observe(scene, reference, cams, Model(true))[0];
  EXPECT_EQ(physical.reference_indices, ideal.reference_indices);
  EXPECT_EQ(physical.target_pixels, ideal.target_pixels);
  EXPECT_FALSE(physical.ideal_differs);
}

// A stereo camera at the origin looking along +x at a plane whose depth grows across the image.
// Stereo refuses exactly the pixels whose analytic depth is below f·B/d_max.
TEST(Physical, StereoRefusesExactlyThePointsNearerThanFBOverDmax) {
  Candidate cam;
  cam.name = "stereo";
  cam.type_id = "stereo";
  cam.sensor = SensorType::FromFov("stereo", 120, 90, 1.0, std::nullopt, 0.1, 5.0);
  SecondAperture imager;
  imager.kind = SecondAperture::Kind::kImager;
  imager.baseline = 0.05;
  imager.width = imager.height = 400;  // a wide right imager: its field holds every point
  imager.fx = imager.fy = 50;
  imager.cx = imager.cy = 200;
  imager.disparity_range = 8;
  cam.sensor.second_aperture = imager;
  cam.world_from_body = Pose{Vec3::Zero(), Quat::Identity()};
  const double nearest = cam.sensor.fx * 0.05 / 8;
  EXPECT_DOUBLE_EQ(StereoNearestDepth(cam.sensor, imager), nearest);
  ASSERT_GT(nearest, 0.5);
  ASSERT_LT(nearest, 0.7);

  // The plane through (0.6, 0, 0) with normal (1, -0.6, 0): depth 0.6 / (1 + 0.6 r) along the
  // ray (1, r, .), from about 0.46 m to 0.9 m over the image.
  const Vec3 normal = Vec3(1, -0.6, 0).normalized();
  TriangleMesh plane = MakePlane(6, 6);
  const Quat to_normal = Quat::FromTwoVectors(Vec3::UnitZ(), normal);
  plane.Transform(Pose{Vec3(0.6, 0, 0), to_normal});
  Scene scene;
  scene.objects.push_back({"plane", Role::kTarget, std::move(plane), {}});
  const Reference reference = BuildReference(scene, {0.01});

  uint64_t all = 0, far_enough = 0;
  double margin = 1;
  for (int v = 0; v < cam.sensor.height; ++v) {
    for (int u = 0; u < cam.sensor.width; ++u) {
      const Vec3 d = PixelRayInBody(cam.sensor, u, v);
      const double depth = normal.dot(Vec3(0.6, 0, 0)) / normal.dot(d);
      ++all;
      far_enough += depth >= nearest ? 1 : 0;
      margin = std::min(margin, std::abs(depth - nearest));
    }
  }
  ASSERT_GT(margin, 1e-5);  // no pixel within float rounding of the limit
  ASSERT_GT(far_enough, all / 5);
  ASSERT_LT(far_enough, all * 4 / 5);
  const std::vector<Candidate> cams = {cam};
  EXPECT_EQ(Observe(scene, reference, cams, Model(false))[0].target_pixels, all);
  const Observation physical = Observe(scene, reference, cams, Model(true))[0];
  EXPECT_EQ(physical.target_pixels, far_enough);
  EXPECT_TRUE(physical.ideal_differs);
}

// A projector with a 10 deg cone turned 45 deg toward +y from 0.2 m to the camera's right: at
// 1 m its cone is centred 0.8 m left of the camera's axis, radius about 0.1 m, and misses a
// 0.2 m target on the axis entirely.
TEST(Physical, ApertureLookingElsewhereDropsEverything) {
  Candidate cam;
  cam.name = "cam";
  cam.type_id = "cone";
  cam.sensor = SensorType::FromFov("cone", 100, 100, 0.6, std::nullopt, 0.1, 5.0);
  SecondAperture projector;
  projector.kind = SecondAperture::Kind::kProjector;
  projector.baseline = 0.2;
  projector.toe_in = kPi / 4;
  projector.cone = 10 * kPi / 180;
  cam.sensor.second_aperture = projector;
  cam.world_from_body = Pose{Vec3::Zero(), Quat::Identity()};
  TriangleMesh target = MakePlane(0.2, 0.2);
  target.Transform(Pose{Vec3(1, 0, 0), Quat::FromTwoVectors(Vec3::UnitZ(), -Vec3::UnitX())});
  Scene scene;
  scene.objects.push_back({"target", Role::kTarget, std::move(target), {}});
  const Reference reference = BuildReference(scene, {0.01});
  const std::vector<Candidate> cams = {cam};
  const Observation ideal = Observe(scene, reference, cams, Model(false))[0];
  const Observation physical = Observe(scene, reference, cams, Model(true))[0];
  EXPECT_GT(ideal.reference_indices.size(), reference.size() / 2);  // the ideal pinhole sees it
  EXPECT_TRUE(physical.reference_indices.empty());
  EXPECT_EQ(physical.target_pixels, 0u);
  EXPECT_EQ(physical.ideal_reference_indices, ideal.reference_indices);
  // Turned away (no toe-in) the same cone, centred 0.2 m right of the target, still misses it;
  // a cone wide enough to hold the target sees all of it.
  cam.sensor.second_aperture->toe_in = 0;
  cam.sensor.second_aperture->cone = 60 * kPi / 180;
  EXPECT_EQ(Observe(scene, reference, std::vector<Candidate>{cam}, Model(true))[0].reference_indices,
            ideal.reference_indices);
}

// The catalog's stereo apertures give the nearest depths the issue quotes, computed here from the
// datasheets' own numbers (depth field, baseline) and the 126-disparity search, independently of
// the catalog's focal lengths: D415 at 1280x720 about 0.44 m, D435 at 848x480 about 0.17 m.
TEST(Physical, CatalogStereoNearestDepthsMatchTheDatasheets) {
  const auto nearest = [](const char* id) {
    const SensorType* type = FindCatalogType(id);
    EXPECT_NE(type, nullptr) << id;
    if (!type) return 0.0;
    const SecondAperture* aperture = SecondApertureOf(*type, id);
    EXPECT_NE(aperture, nullptr) << id;
    return aperture ? StereoNearestDepth(*type, *aperture) : 0.0;
  };
  const auto by_hand = [](int width, double hfov_deg, double baseline) {
    return width / 2.0 / std::tan(hfov_deg / 2 * kPi / 180) * baseline / 126;
  };
  EXPECT_NEAR(nearest("intel_realsense_d415_1280x720"), by_hand(1280, 65, 0.055), 1e-9);
  EXPECT_NEAR(nearest("intel_realsense_d415_1280x720"), 0.44, 0.01);
  EXPECT_NEAR(nearest("intel_realsense_d435_848x480"), by_hand(848, 87, 0.050), 1e-9);
  EXPECT_NEAR(nearest("intel_realsense_d435_848x480"), 0.17, 0.01);
  // Halving the resolution halves f and with it the nearest depth (the whitepaper's advice).
  EXPECT_NEAR(nearest("intel_realsense_d415_848x480") / nearest("intel_realsense_d415_1280x720"),
              848.0 / 1280.0, 1e-9);
}

// Every entry validates; apertures only where a source gave them (structured light's projector,
// stereo's second imager, none for time of flight); the paper's types keep their intrinsics.
TEST(Physical, CatalogEntriesValidateAndKeepThePapersTypes) {
  for (const SensorType& type : Catalog()) {
    SCOPED_TRACE(type.id);
    EXPECT_NO_THROW(type.Validate());
    EXPECT_EQ(MatchCatalogId(type), type.id);  // no two entries share intrinsics and range
    if (!type.second_aperture) continue;
    const SecondAperture& a = *type.second_aperture;
    EXPECT_FALSE(a.source.empty());
    EXPECT_FALSE(type.technology.starts_with("time of flight"));
    EXPECT_EQ(a.kind == SecondAperture::Kind::kImager,
              type.technology.find("stereo") != std::string::npos);
  }
  // Gazebo's models of the original system (SENSORS.md): W, H, hfov, near, far.
  struct Paper {
    const char* id;
    int w, h;
    double hfov, near, far;
  };
  for (const Paper& p : {Paper{"kinect_xbox_360", 640, 480, 0.994838, 0.4, 4.0},
                         Paper{"intel_realsense_d415", 1280, 720, 1.106539, 0.16, 10.0},
                         Paper{"zed", 4416, 1242, 1.91986, 0.7, 20.0},
                         Paper{"multisense_s7", 2048, 1088, 1.39626, 0.4, 5.0}}) {
    const SensorType gazebo =
        SensorType::FromFov(p.id, p.w, p.h, p.hfov, std::nullopt, p.near, p.far);
    EXPECT_EQ(MatchCatalogId(gazebo), p.id);
  }
  // The paper's ZED is its Gazebo model (the side-by-side RGB pair), and its name says so.
  const SensorType* zed = FindCatalogType("zed");
  ASSERT_NE(zed, nullptr);
  EXPECT_NE(zed->name.find("Gazebo model"), std::string::npos) << zed->name;
  const SensorType* kinect = FindCatalogType("kinect_xbox_360");
  ASSERT_TRUE(kinect && kinect->second_aperture);
  EXPECT_EQ(kinect->second_aperture->kind, SecondAperture::Kind::kProjector);
  EXPECT_DOUBLE_EQ(kinect->second_aperture->baseline, 0.075);
  EXPECT_EQ(SecondApertureOf(*FindCatalogType("azure_kinect_wfov_unbinned"), "azure_kinect_wfov_unbinned"),
            nullptr);
}

// The Orbbec Femto Bolt's depth modes, as Orbbec's "Femto Bolt Hardware Specifications" lists
// them (docs/sensor-models.md): the fields of view derived from the catalog's focal lengths are
// the datasheet's, the ranges and rates are its own, and the camera is the Azure Kinect's
// (Orbbec: the same ToF depth camera), so its intrinsics equal that entry's. Time of flight needs
// no second aperture; no price is published, so none is carried.
TEST(Physical, FemtoBoltModesAreOrbbecsDatasheet) {
  struct Mode {
    const char* id;
    const char* azure;
    int w, h;
    double hfov_deg, vfov_deg, near, far, fps;
  };
  for (const Mode& m :
       {Mode{"femto_bolt_nfov_unbinned", "azure_kinect_nfov", 640, 576, 75, 65, 0.5, 3.86, 30},
        Mode{"femto_bolt_nfov_binned", "azure_kinect_nfov_binned", 320, 288, 75, 65, 0.5, 5.46, 30},
        Mode{"femto_bolt_wfov_binned", "azure_kinect_wfov", 512, 512, 120, 120, 0.25, 2.88, 30},
        Mode{"femto_bolt_wfov_unbinned", "azure_kinect_wfov_unbinned", 1024, 1024, 120, 120,
             0.25, 2.21, 25}}) {
    SCOPED_TRACE(m.id);
    const SensorType* type = FindCatalogType(m.id);
    ASSERT_NE(type, nullptr);
    EXPECT_EQ(type->width, m.w);
    EXPECT_EQ(type->height, m.h);
    EXPECT_NEAR(type->HorizontalFov() * 180 / kPi, m.hfov_deg, 1e-9);
    EXPECT_NEAR(type->VerticalFov() * 180 / kPi, m.vfov_deg, 1e-9);
    EXPECT_EQ(type->near, m.near);
    EXPECT_EQ(type->far, m.far);
    EXPECT_EQ(type->fps, m.fps);
    EXPECT_EQ(type->technology, "time of flight");
    EXPECT_EQ(SecondApertureOf(*type, m.id), nullptr);
    EXPECT_EQ(PhysicalModelGap(*type, m.id), "");  // ToF: nothing extra to model
    EXPECT_FALSE(UnitCostGiven(*type, m.id));
    // The Azure Kinect's depth camera: same pixels, same rays, same range.
    const SensorType* azure = FindCatalogType(m.azure);
    ASSERT_NE(azure, nullptr);
    EXPECT_EQ(azure->width, type->width);
    EXPECT_NEAR(azure->fx, type->fx, 1e-9);
    EXPECT_NEAR(azure->fy, type->fy, 1e-9);
    EXPECT_EQ(azure->near, type->near);
    EXPECT_EQ(azure->far, type->far);
    // Named after its entry it stays a Femto Bolt; a Gazebo model of the same camera under
    // another name is read as the first entry with its values, the Azure Kinect's.
    EXPECT_EQ(MatchCatalogId(*type), m.id);
    SensorType renamed = *type;
    renamed.id = "some_gazebo_model";
    EXPECT_EQ(MatchCatalogId(renamed), m.azure);
    // A price given in the scene is a price.
    SensorType priced = *type;  // as the scene reader makes it from `cost: 450`
    priced.cost = 450;
    priced.cost_given = true;
    EXPECT_TRUE(UnitCostGiven(priced, m.id));
  }
  for (const SensorType& type : Catalog()) {
    if (!type.id.starts_with("femto_bolt")) {
      EXPECT_TRUE(UnitCostGiven(type, type.id)) << type.id;
    }
  }
}

// Structured light and stereo need a second aperture: a type of that technology without one is
// not modelled (and says so), time of flight needs none, and a type that gives its own aperture
// (or `kind: none` on purpose) is modelled as given.
TEST(Physical, TypesWithoutAKnownApertureAreStatedNotModelled) {
  const auto gap = [](const char* id) {
    const SensorType* type = FindCatalogType(id);
    EXPECT_NE(type, nullptr) << id;
    return type ? PhysicalModelGap(*type, id) : std::string("?");
  };
  EXPECT_NE(gap("asus_xtion_pro_live").find("projector"), std::string::npos);
  EXPECT_NE(gap("photoneo_phoxi_s").find("projector"), std::string::npos);
  EXPECT_NE(gap("ensenso_n35").find("projector"), std::string::npos);
  EXPECT_EQ(gap("kinect_xbox_360"), "");
  EXPECT_EQ(gap("intel_realsense_d435"), "");
  EXPECT_EQ(gap("kinect_xbox_one"), "");
  SensorType stereo = SensorType::FromFov("my_stereo", 640, 480, 1.0, std::nullopt, 0.2, 3);
  stereo.technology = "passive stereo";
  EXPECT_NE(PhysicalModelGap(stereo, "my_stereo").find("second imager"), std::string::npos);
  stereo.second_aperture = SecondAperture{};  // kind: none, given on purpose
  EXPECT_EQ(PhysicalModelGap(stereo, "my_stereo"), "");
}

// A type without a price refuses --budget (exit 2 naming the flag and the type, before any ray)
// and reports no unit or total cost in --by-type, until the scene gives it one; under the
// physical model (on: the Kinect has a projector) the Xtion's row says it is not modelled.
TEST(Physical, UnpricedTypeRefusesABudgetUntilTheSceneGivesACost) {
  test::TempDir dir;
  const auto scene = [&](const std::string& name, const std::string& types,
                         const std::string& type) {
    const std::string path = dir.File(name);
    test::WriteText(path, "settings:\n  cell_size: 0.02\n  n: 1\n  observation_point: [0, 0, 0.06]\n" +
                              types + R"(objects:
  - name: cube
    role: target
    box: {size: [0.1, 0.1, 0.1]}
    pose: {xyz: [0, 0, 0.06]}
sensors:
  - {name: a, type: )" + type + R"(, position: [0, 0, 1.06], orientation: {rpy: [0, 1.5707963267948966, 0]}}
  - {name: b, type: asus_xtion_pro_live, position: [1.0, 0, 0.06], orientation: {rpy: [0, 0, 3.141592653589793]}}
  - {name: c, type: kinect_xbox_360, position: [-1.0, 0, 0.06], orientation: {rpy: [0, 0, 0]}}
)");
    return path;
  };
  const std::string bolt = scene("bolt.yaml", "", "femto_bolt_nfov_unbinned");
  const auto refused = test::RunVantage("optimize " + bolt + " --budget 1000 --out " + dir.File("r"));
  EXPECT_EQ(refused.exit_code, 2) << refused.err;
  EXPECT_NE(refused.err.find("--budget"), std::string::npos) << refused.err;
  EXPECT_NE(refused.err.find("'femto_bolt_nfov_unbinned' has no unit cost"), std::string::npos)
      << refused.err;
  EXPECT_EQ(refused.err.find("observe:"), std::string::npos) << "no ray before the refusal";
  EXPECT_FALSE(std::filesystem::exists(dir.File("r/report.json")));

  const std::string out = dir.File("by_type");
  const auto run = test::RunVantage("optimize " + bolt + " --by-type --physical --out " + out);
  ASSERT_EQ(run.exit_code, 0) << run.err;
  EXPECT_NE(run.out.find("femto_bolt_nfov_unbinned: unit cost not given"), std::string::npos)
      << run.out;
  EXPECT_NE(run.out.find("asus_xtion_pro_live: physical model not modelled"), std::string::npos)
      << run.out;
  const nlohmann::json report = nlohmann::json::parse(test::ReadText(out + "/report.json"));
  for (const nlohmann::json& t : report["by_type"]["types"]) {
    SCOPED_TRACE(t["type"].get<std::string>());
    const bool bolt_row = t["type"] == "femto_bolt_nfov_unbinned";
    EXPECT_EQ(t["unit_cost"].is_null(), bolt_row);
    for (const nlohmann::json& b : t["best"]) EXPECT_EQ(b["total_cost"].is_null(), bolt_row);
    EXPECT_EQ(t.contains("physical_model"), t["type"] == "asus_xtion_pro_live");
  }
  for (const nlohmann::json& t : report["sensor_model"]["types"]) {
    if (t["type"] == "femto_bolt_nfov_unbinned") {
      EXPECT_EQ(t["second_aperture"], "none");
    }
    if (t["type"] == "asus_xtion_pro_live") {
      EXPECT_EQ(t["second_aperture"], "not modelled");
      EXPECT_NE(t["physical_model"].get<std::string>().find("projector"), std::string::npos);
    }
  }

  const std::string priced = scene(
      "priced.yaml",
      "sensor_types:\n  - {id: my_bolt, base: femto_bolt_nfov_unbinned, cost: 400}\n", "my_bolt");
  const auto budget = test::RunVantage("optimize " + priced + " --budget 1000 --out " +
                                       dir.File("p"));
  EXPECT_EQ(budget.exit_code, 0) << budget.err;
}

// When no candidate's type has a physical model, the physical model asked for (the YAML default)
// changes nothing and the run is recorded as ideal — and it says which types it could not judge.
// A .vis keeps the unpriced type: `vantage select --budget` refuses it as optimize does.
TEST(Physical, RunWithoutAnyPhysicalModelSaysWhichTypesAreNotModelled) {
  test::TempDir dir;
  const std::string scene = dir.File("no_model.yaml");
  test::WriteText(scene, R"(settings:
  cell_size: 0.02
  n: 1
  observation_point: [0, 0, 0.06]
objects:
  - name: cube
    role: target
    box: {size: [0.1, 0.1, 0.1]}
    pose: {xyz: [0, 0, 0.06]}
sensors:
  - {name: a, type: femto_bolt_nfov_unbinned, position: [0, 0, 1.06], orientation: {rpy: [0, 1.5707963267948966, 0]}}
  - {name: b, type: asus_xtion_pro_live, position: [1.0, 0, 0.06], orientation: {rpy: [0, 0, 3.141592653589793]}}
)");
  const auto run = test::RunVantage("optimize " + scene + " --out " + dir.File("out"));
  ASSERT_EQ(run.exit_code, 0) << run.err;
  EXPECT_NE(run.err.find("no candidate's type has a physical model"), std::string::npos) << run.err;
  EXPECT_NE(run.err.find("asus_xtion_pro_live (not modelled"), std::string::npos) << run.err;
  EXPECT_EQ(run.err.find("femto_bolt_nfov_unbinned (not modelled"), std::string::npos) << run.err;
  const nlohmann::json report = nlohmann::json::parse(test::ReadText(dir.File("out/report.json")));
  EXPECT_FALSE(report.contains("sensor_model"));  // the ideal pinhole's run, recorded as such

  const std::string vis = dir.File("m.vis");
  ASSERT_EQ(test::RunVantage("observe " + scene + " --out " + vis).exit_code, 0);
  const auto refused = test::RunVantage("select " + vis + " --budget 1000 --out " + dir.File("s"));
  EXPECT_EQ(refused.exit_code, 2) << refused.err;
  EXPECT_NE(refused.err.find("'femto_bolt_nfov_unbinned' has no unit cost"), std::string::npos)
      << refused.err;
}

// A custom type based on an unpriced entry, without a `cost:`, has no price either; its .vis
// (format 9) keeps that, so `vantage select --budget` and `--cheapest` refuse it naming the
// type, as optimize does, and a price given in the scene is kept as one.
TEST(Physical, VisKeepsACustomTypesMissingCostForSelect) {
  test::TempDir dir;
  const auto scene = [&](const std::string& name, const std::string& cost) {
    const std::string path = dir.File(name);
    test::WriteText(path, R"(settings:
  cell_size: 0.02
  n: 1
  observation_point: [0, 0, 0.06]
sensor_types:
  - {id: my_bolt, base: femto_bolt_nfov_unbinned)" + cost + R"(}
objects:
  - name: cube
    role: target
    box: {size: [0.1, 0.1, 0.1]}
    pose: {xyz: [0, 0, 0.06]}
sensors:
  - {name: a, type: my_bolt, position: [0, 0, 1.06], orientation: {rpy: [0, 1.5707963267948966, 0]}}
  - {name: b, type: kinect_xbox_one, position: [1.0, 0, 0.06], orientation: {rpy: [0, 0, 3.141592653589793]}}
)");
    return path;
  };
  const std::string unpriced = scene("unpriced.yaml", "");
  const auto optimize =
      test::RunVantage("optimize " + unpriced + " --budget 1000 --out " + dir.File("o"));
  EXPECT_EQ(optimize.exit_code, 2) << optimize.err;
  EXPECT_NE(optimize.err.find("'my_bolt' has no unit cost"), std::string::npos) << optimize.err;

  const std::string vis = dir.File("unpriced.vis");
  ASSERT_EQ(test::RunVantage("observe " + unpriced + " --out " + vis).exit_code, 0);
  for (const char* flag : {"--budget 1000", "--cheapest --goal 0.1"}) {
    SCOPED_TRACE(flag);
    const auto refused =
        test::RunVantage("select " + vis + " " + flag + " --out " + dir.File("s"));
    EXPECT_EQ(refused.exit_code, 2) << refused.err;
    EXPECT_NE(refused.err.find("'my_bolt' has no unit cost"), std::string::npos) << refused.err;
    EXPECT_FALSE(std::filesystem::exists(dir.File("s/report.json")));
  }
  // Without a budget the same file selects as before.
  EXPECT_EQ(test::RunVantage("select " + vis + " --out " + dir.File("plain")).exit_code, 0);

  const std::string priced_vis = dir.File("priced.vis");
  ASSERT_EQ(test::RunVantage("observe " + scene("priced.yaml", ", cost: 400") + " --out " +
                             priced_vis).exit_code, 0);
  const auto budget =
      test::RunVantage("select " + priced_vis + " --budget 1000 --out " + dir.File("p"));
  EXPECT_EQ(budget.exit_code, 0) << budget.err;
}

// --by-type on a scene whose answer is known by construction: a floating 0.1 m cube (faces in
// the middle of 2 cm cells: R is the 6 x 6 x 6 shell, 152 cells), two `top` cameras at the same
// pose 0.5 m above its top face and one `side` camera 0.5 m from its +x face. Each sees one face
// (36 cells); the two faces share a row of 6 edge cells. So `top` alone covers 36 cells with one
// camera or two, `side` 36 with its one, the mix of one of each 66: a gain of 30 cells.
TEST(Physical, ByTypeFindsEachTypesBestAndTheMixGain) {
  test::TempDir dir;
  const std::string scene = dir.File("two_types.yaml");
  test::WriteText(scene, R"(settings:
  cell_size: 0.02
  n: 2
  observation_point: [0, 0, 0.06]
sensor_types:
  - {id: top, resolution: [160, 120], hfov: 1.0, range: [0.1, 3.0], cost: 100}
  - {id: side, resolution: [160, 120], hfov: 1.0, range: [0.1, 3.0], cost: 30}
objects:
  - name: cube
    role: target
    box: {size: [0.1, 0.1, 0.1]}
    pose: {xyz: [0, 0, 0.06]}
sensors:
  - {name: top_a, type: top, position: [0, 0, 0.61], orientation: {rpy: [0, 1.5707963267948966, 0]}}
  - {name: top_b, type: top, position: [0, 0, 0.61], orientation: {rpy: [0, 1.5707963267948966, 0]}}
  - {name: side_a, type: side, position: [0.55, 0, 0.06], orientation: {rpy: [0, 0, 3.141592653589793]}}
)");
  const std::string out = dir.File("out");
  const auto run = test::RunVantage("optimize " + scene + " --by-type --out " + out);
  ASSERT_EQ(run.exit_code, 0) << run.err;
  EXPECT_NE(run.out.find("by type"), std::string::npos) << run.out;
  const nlohmann::json report = nlohmann::json::parse(test::ReadText(out + "/report.json"));
  const double cells = 152;
  ASSERT_EQ(report["reference_voxels"].get<double>(), cells);
  const nlohmann::json& types = report["by_type"]["types"];
  ASSERT_EQ(types.size(), 2u);
  EXPECT_EQ(types[0]["type"], "top");
  EXPECT_EQ(types[0]["candidates"], 2);
  EXPECT_EQ(types[0]["unit_cost"], 100.0);
  ASSERT_EQ(types[0]["best"].size(), 2u);  // n = 1 and 2
  for (int n = 1; n <= 2; ++n) {
    const nlohmann::json& best = types[0]["best"][n - 1];
    EXPECT_EQ(best["n"], n);
    EXPECT_NEAR(best["coverage"].get<double>() * cells, 36, 1e-9);
    EXPECT_EQ(best["total_cost"], 100.0 * n);
    EXPECT_EQ(best["optimal"], true);  // --method all proves it with exact
  }
  EXPECT_EQ(types[1]["type"], "side");
  ASSERT_EQ(types[1]["best"].size(), 1u);  // one candidate: no pair of its own
  EXPECT_NEAR(types[1]["best"][0]["coverage"].get<double>() * cells, 36, 1e-9);
  const nlohmann::json& mix = report["by_type"]["mix"];
  ASSERT_EQ(mix.size(), 2u);
  EXPECT_NEAR(mix[0]["coverage"].get<double>() * cells, 36, 1e-9);
  EXPECT_NEAR(mix[0]["gain"].get<double>(), 0, 1e-12);
  EXPECT_NEAR(mix[1]["coverage"].get<double>() * cells, 66, 1e-9);
  EXPECT_NEAR(mix[1]["gain"].get<double>() * cells, 30, 1e-9);
  EXPECT_EQ(mix[1]["best_single_type"], "top");
  EXPECT_EQ(mix[1]["types"], nlohmann::json::array({"top", "side"}));
  EXPECT_EQ(mix[1]["total_cost"], 130.0);
  EXPECT_EQ(mix[1]["optimal"], true);

  // Objectives that do not choose n are refused before any ray, naming --by-type.
  const auto goal = test::RunVantage("optimize " + scene + " --by-type --goal 0.2 --out " +
                                     dir.File("goal"));
  EXPECT_EQ(goal.exit_code, 2) << goal.err;
  EXPECT_NE(goal.err.find("--by-type"), std::string::npos) << goal.err;
  EXPECT_EQ(goal.err.find("observe:"), std::string::npos) << goal.err;
}

// A time-of-flight camera 1 m above a floor looking straight down, its image's right along +x,
// over the edge x = 0 of a 0.2 m box (x >= 0): every pixel sees the box top at depth 0.8 m or
// the floor at 1 m (the camera stands over the box, so no ray meets its side). The level of
// column u follows from its ray alone; with a flying-pixel threshold below 0.2 m exactly the
// pixels with a 4-neighbour on the other level (the two columns beside the edge) are dropped, and
// none with a threshold above it.
struct FlyingStep {
  double H = 1.0, h = 0.2, camera_x = 0.0123;
  int width = 101, height = 61;
  double hfov = 0.6;

  Scene MakeScene(Role box_role) const {
    Scene scene;
    scene.objects.push_back({"floor", Role::kTarget, MakePlane(4, 4), {}});
    TriangleMesh box = MakeBox(Vec3(2, 4, h));
    box.Transform(Pose{Vec3(1, 0, h / 2), Quat::Identity()});
    scene.objects.push_back({"box", box_role, std::move(box), {}});
    return scene;
  }

  Candidate Camera(std::optional<double> threshold) const {
    Candidate c;
    c.name = "tof";
    c.type_id = "tof";
    c.sensor = SensorType::FromFov("tof", width, height, hfov, std::nullopt, 0.1, 5.0);
    c.sensor.technology = "time of flight";
    c.sensor.flying_pixel_threshold = threshold;
    Mat3 r;
    r.col(0) = Vec3(0, 0, -1);
    r.col(1) = Vec3(-1, 0, 0);
    r.col(2) = Vec3(0, 1, 0);
    c.world_from_body = Pose{Vec3(camera_x, 0, H), Quat(r)};
    return c;
  }

  // Whether column u's rays meet the box top: x at the top's height is >= 0.
  bool OnTop(const SensorType& s, int u) const {
    const double slope = (u + 0.5 - s.cx) / s.fx;  // image right = +x per unit depth
    return camera_x + slope * (H - h) >= 0;
  }
};

TEST(Physical, FlyingPixelsAtAStepAreExactlyThoseBesideTheEdge) {
  const FlyingStep step;
  for (const Role box_role : {Role::kTarget, Role::kOccluder}) {
    SCOPED_TRACE(box_role == Role::kTarget ? "box is a target" : "box occludes");
    const Scene scene = step.MakeScene(box_role);
    const Reference reference = BuildReference(scene, {0.02});
    const Candidate cam = step.Camera(0.1);
    // By hand: the pixels counted (targets) and those dropped (a horizontal neighbour on the
    // other level; vertical neighbours share the column's level).
    uint64_t targets = 0, dropped = 0;
    for (int u = 0; u < step.width; ++u) {
      const bool top = step.OnTop(cam.sensor, u);
      const bool target = !top || box_role == Role::kTarget;
      const bool edge = (u > 0 && step.OnTop(cam.sensor, u - 1) != top) ||
                        (u + 1 < step.width && step.OnTop(cam.sensor, u + 1) != top);
      targets += target ? static_cast<uint64_t>(step.height) : 0;
      dropped += target && edge ? static_cast<uint64_t>(step.height) : 0;
    }
    ASSERT_GT(targets, 0u);
    ASSERT_EQ(dropped, static_cast<uint64_t>(step.height) * (box_role == Role::kTarget ? 2 : 1));
    const std::vector<Candidate> cams = {cam};
    EXPECT_EQ(Observe(scene, reference, cams, Model(false))[0].target_pixels, targets);
    ObserveOptions physical = Model(true);
    const Observation o = Observe(scene, reference, cams, physical)[0];
    EXPECT_EQ(o.target_pixels, targets - dropped);
    physical.cull = false;  // the whole image traced: the same pixels judged the same
    const Observation all = Observe(scene, reference, cams, physical)[0];
    EXPECT_EQ(all.target_pixels, o.target_pixels);
    EXPECT_EQ(all.reference_indices, o.reference_indices);
    // A threshold above the step drops nothing.
    const std::vector<Candidate> loose = {step.Camera(0.3)};
    const Observation kept = Observe(scene, reference, loose, Model(true))[0];
    EXPECT_EQ(kept.target_pixels, targets);
    EXPECT_FALSE(kept.ideal_differs);
  }
}

// The tiny CLI scene with the custom type given a second aperture.
std::string CubeCellWithAperture(const std::string& aperture) {
  std::string text = test::ReadText(test::DataPath("cli/cube_cell.yaml"));
  const std::string range = "    range: [0.1, 3.0]\n";
  const size_t at = text.find(range);
  EXPECT_NE(at, std::string::npos);
  text.insert(at + range.size(), aperture);
  return text;
}

TEST(Physical, BadApertureIsRefusedAtItsLineBeforeAnyRay) {
  test::TempDir dir;
  struct BadCase {
    std::string aperture;
    int line;
    std::string what;
  };
  // Line 15 is `second_aperture:`, its fields follow.
  const std::vector<BadCase> cases = {
      {"    second_aperture:\n      kind: imager\n      baseline: -0.05\n", 17, "baseline = -0.05"},
      {"    second_aperture:\n      kind: imager\n      baseline: .nan\n", 17, "baseline"},
      {"    second_aperture:\n      kind: projector\n      baseline: 3\n", 17, "no sensor body"},
      {"    second_aperture:\n      kind: imager\n      baseline: 0.05\n      disparity_range: -8\n",
       18, "disparity_range = -8"},
      {"    second_aperture:\n      kind: imager\n      baseline: 0.05\n      disparity_range: 1000\n",
       18, "the image's width"},
      {"    second_aperture:\n      kind: projector\n      baseline: 0.05\n      hfov_deg: 190\n",
       18, "hfov_deg = 190"},
      {"    second_aperture:\n      kind: projector\n      cone_deg: .nan\n", 17, "cone_deg"},
      {"    second_aperture:\n      kind: projector\n      toe_in_deg: -3\n", 17, "toe_in_deg = -3"},
      {"    second_aperture:\n      kind: laser\n", 16, "kind 'laser'"},
      {"    second_aperture:\n      kind: projector\n      disparity_range: 64\n", 15,
       "disparity_range belongs to a second imager"},
      {"    flying_pixel_threshold: -0.1\n", 15, "flying_pixel_threshold = -0.1"},
  };
  for (size_t i = 0; i < cases.size(); ++i) {
    const BadCase& c = cases[i];
    SCOPED_TRACE(c.aperture);
    const std::string path = dir.File("bad" + std::to_string(i) + ".yaml");
    test::WriteText(path, CubeCellWithAperture(c.aperture));
    const auto run = test::RunVantage("optimize " + path + " --out " + dir.File("out"));
    EXPECT_EQ(run.exit_code, 2) << run.err;
    EXPECT_NE(run.err.find(path + ":" + std::to_string(c.line) + ":"), std::string::npos) << run.err;
    EXPECT_NE(run.err.find(c.what), std::string::npos) << run.err;
    EXPECT_EQ(run.err.find("observe:"), std::string::npos) << "no ray before the refusal";
  }
  // A good aperture loads and runs.
  const std::string good = dir.File("good.yaml");
  test::WriteText(good, CubeCellWithAperture("    second_aperture:\n      kind: imager\n"
                                             "      baseline: 0.05\n      disparity_range: 64\n"));
  const auto run = test::RunVantage("optimize " + good + " --out " + dir.File("good_out"));
  EXPECT_EQ(run.exit_code, 0) << run.err;
}

}  // namespace
}  // namespace vantage
