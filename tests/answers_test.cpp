// Answers a user can act on (issue 46): R's target parts and the surface no viewpoint can see,
// counted by hand on boxes; the ceiling and each part as report.json gives them, checked against
// `evaluate` and against the whole.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <memory>
#include <numbers>
#include <nlohmann/json.hpp>
#include <set>

#include "test_util.hpp"
#include <tbb/global_control.h>

#include "vantage/candidates.hpp"
#include "vantage/error.hpp"
#include "vantage/observe.hpp"
#include "vantage/pipeline.hpp"
#include "vantage/pose_tolerance.hpp"
#include "vantage/ray_scene.hpp"
#include "vantage/reference.hpp"
#include "vantage/scene.hpp"

namespace vantage {
namespace {

using nlohmann::json;
using test::RunVantage;

TriangleMesh BoxAt(const Vec3& lo, const Vec3& hi) {
  TriangleMesh mesh = MakeBox(hi - lo);
  mesh.Transform(Pose{0.5 * (lo + hi), Quat::Identity()});
  return mesh;
}

// The same box with every triangle turned over: a room's inside, facing in.
TriangleMesh Inverted(TriangleMesh mesh) {
  for (auto& t : mesh.triangles) std::swap(t[1], t[2]);
  return mesh;
}

SceneObject Object(const std::string& name, Role role, TriangleMesh mesh) {
  SceneObject object;
  object.name = name;
  object.role = role;
  object.mesh = std::move(mesh);
  return object;
}

// A cube [0, 4]³ (cells of 1 m) resting on the floor. R is the shell of cells [0, 4]³ (half-open
// cells: the faces at 4 lie in the cells 4): 5³ - 3³ = 98 cells. The bottom face lies in the
// layer z = 0; of its 5 x 5 cells, those at x or y = 0 or 4 also hold a side face, which the
// cameras see. The 3 x 3 cells (1..3, 1..3, 0) hold nothing but the resting face: unexposed.
std::set<uint64_t> RestingFaceCells() {
  std::set<uint64_t> cells;
  for (int64_t x = 1; x <= 3; ++x)
    for (int64_t y = 1; y <= 3; ++y) cells.insert(PackVoxel({x, y, 0}));
  return cells;
}

std::set<uint64_t> Unexposed(const Reference& r) {
  EXPECT_EQ(r.exposed.size(), r.keys.size());
  std::set<uint64_t> cells;
  for (size_t i = 0; i < r.keys.size() && i < r.exposed.size(); ++i)
    if (!r.exposed[i]) cells.insert(r.keys[i]);
  return cells;
}

Scene CubeOn(TriangleMesh floor) {
  Scene scene;
  scene.objects.push_back(Object("cube", Role::kTarget, BoxAt({0, 0, 0}, {4, 4, 4})));
  scene.objects.push_back(Object("floor", Role::kOccluder, std::move(floor)));
  return scene;
}

TEST(Exposure, ACubeRestingOnABoxFloorHidesExactlyItsBottomFace) {
  const Reference r = BuildReference(CubeOn(BoxAt({-3, -3, -2}, {7, 7, 0})), {1.0});
  ASSERT_EQ(r.size(), 98u);
  EXPECT_EQ(Unexposed(r), RestingFaceCells());
}

// A ground plane is one open rectangle: nothing below it is solid, but the face resting on it
// touches it, so the cells stay unexposed.
TEST(Exposure, ACubeRestingOnAGroundPlaneHidesExactlyItsBottomFace) {
  TriangleMesh plane = MakePlane(10, 10);
  plane.Transform(Pose{Vec3(2, 2, 0), Quat::Identity()});
  const Reference r = BuildReference(CubeOn(std::move(plane)), {1.0});
  ASSERT_EQ(r.size(), 98u);
  EXPECT_EQ(Unexposed(r), RestingFaceCells());
}

TEST(Exposure, AFreeCubeIsExposedEverywhereAndAnEnclosedOneNowhere) {
  Scene free;
  free.objects.push_back(Object("cube", Role::kTarget, BoxAt({0, 0, 0}, {4, 4, 4})));
  EXPECT_TRUE(Unexposed(BuildReference(free, {1.0})).empty());

  // A hollow box (outer faces out, inner faces in: closed and consistently oriented) around it,
  // 2 cells of air between: the air is enclosed, no viewpoint reaches it.
  Scene enclosed = free;
  TriangleMesh shell = BoxAt({-4, -4, -4}, {8, 8, 8});
  shell.Append(Inverted(BoxAt({-2, -2, -2}, {6, 6, 6})));
  enclosed.objects.push_back(Object("crate", Role::kOccluder, std::move(shell)));
  const Reference r = BuildReference(enclosed, {1.0});
  EXPECT_EQ(Unexposed(r).size(), r.size());

  // A room facing in (a closed mesh whose inside is the air) hides nothing.
  Scene room = free;
  room.objects.push_back(Object("room", Role::kOccluder, Inverted(BoxAt({-3, -3, -3}, {7, 7, 7}))));
  EXPECT_TRUE(Unexposed(BuildReference(room, {1.0})).empty());
}

TEST(Exposure, ExposedOnlyLeavesTheRestingFaceOutOfR) {
  ReferenceOptions options{1.0};
  options.exposed_only = true;
  const Reference r = BuildReference(CubeOn(BoxAt({-3, -3, -2}, {7, 7, 0})), options);
  EXPECT_EQ(r.size(), 98u - 9u);
  EXPECT_TRUE(r.exposed_only);
  EXPECT_EQ(r.left_out, std::vector<uint64_t>{9});
  for (uint64_t key : RestingFaceCells()) EXPECT_LT(r.IndexOf(key), 0);
}

// Two cubes side by side share the face x = 2: its 3 x 3 cells belong to the first target.
TEST(Parts, ACellOnTwoPartsBelongsToTheFirst) {
  Scene scene;
  scene.objects.push_back(Object("left", Role::kTarget, BoxAt({0, 0, 0}, {2, 2, 2})));
  scene.objects.push_back(Object("right", Role::kTarget, BoxAt({2, 0, 0}, {4, 2, 2})));
  const Reference r = BuildReference(scene, {1.0});
  ASSERT_EQ(r.size(), 26u + 26u - 9u);
  ASSERT_EQ(r.part_names, (std::vector<std::string>{"left", "right"}));
  ASSERT_EQ(r.part_of.size(), r.size());
  size_t left = 0;
  for (size_t i = 0; i < r.size(); ++i) {
    const VoxelIndex c = UnpackVoxel(r.keys[i]);
    EXPECT_EQ(r.part_of[i], c[0] <= 2 ? 0u : 1u);
    left += r.part_of[i] == 0;
  }
  EXPECT_EQ(left, 26u);
  // Resting against each other: the shared face's 1 x 1 inner cell (2, 1, 1) is enclosed.
  EXPECT_EQ(Unexposed(r), (std::set<uint64_t>{PackVoxel({2, 1, 1})}));
}

// Mounting tolerance on two square plates 0.19 m wide (cells of 1 cm, edges mid-cell, the plates
// mid-cell at x = 0.005 facing +x): camera A, 1 m in front of the first, sees it with 12 degrees
// of margin on every side, so 2 cm and 2 degrees never cost it a cell; camera B, 0.5 m in front of
// the second, sees exactly that plate edge to edge (its half field of view atan(0.095 / 0.5)), so
// any turn or sideways shift, or coming closer, pushes part of the plate out of its image.
struct TwoPlates {
  Scene scene;
  VisibilityFile data;
  std::unique_ptr<RayScene> rays;
  std::vector<Selection> results;
};

Candidate CameraAt(const std::string& name, const Vec3& eye, const Vec3& target, double hfov) {
  Candidate c;
  c.name = name;
  c.sensor = SensorType::FromFov("test", 400, 400, hfov, std::nullopt, 0.1, 3.0);
  c.type_id = "test";
  c.world_from_body = Pose{eye, LookAt(eye, target)};
  return c;
}

TwoPlates MakeTwoPlates() {
  TwoPlates t;
  const Quat facing_x(Eigen::AngleAxisd(std::numbers::pi / 2, Vec3::UnitY()));
  for (const auto& [name, y] : {std::pair<const char*, double>{"near", 0.0}, {"edge", 2.0}}) {
    TriangleMesh plate = MakePlane(0.19, 0.19);
    plate.Transform(Pose{Vec3(0.005, y, 0.0), facing_x});
    t.scene.objects.push_back(Object(name, Role::kTarget, std::move(plate)));
  }
  t.data.reference = BuildReference(t.scene, {0.01});
  t.data.candidates = {
      CameraAt("A", {1.005, 0.0, 0.0}, {0.005, 0.0, 0.0}, 0.6),
      CameraAt("B", {0.505, 2.0, 0.0}, {0.005, 2.0, 0.0}, 2 * std::atan(0.095 / 0.5))};
  t.rays = std::make_unique<RayScene>(t.scene);
  t.data.observations = Observe(*t.rays, t.data.reference, t.data.candidates, {});
  const CoverageEvaluator evaluator(t.data.observations, t.data.reference.size());
  for (const std::vector<uint32_t>& chosen : {std::vector<uint32_t>{0}, std::vector<uint32_t>{0, 1}}) {
    Selection s;
    s.method = "given";
    s.chosen = chosen;
    s.n = static_cast<int>(chosen.size());
    s.coverage = evaluator.Coverage(chosen);
    t.results.push_back(s);
  }
  return t;
}

TEST(PoseTolerance, ZeroToleranceGivesThePlannedCoverage) {
  const TwoPlates t = MakeTwoPlates();
  // Each camera sees its whole plate: half of R each.
  ASSERT_DOUBLE_EQ(t.results[0].coverage, 0.5);
  ASSERT_DOUBLE_EQ(t.results[1].coverage, 1.0);
  PoseToleranceOptions none;
  none.samples = 8;
  const PoseTolerance tolerance = AssessPoseTolerance(t.data, t.results, *t.rays, {}, none);
  ASSERT_EQ(tolerance.results.size(), 2u);
  for (size_t i = 0; i < 2; ++i) {
    const PoseSpread& s = tolerance.results[i];
    EXPECT_DOUBLE_EQ(s.nominal, t.results[i].coverage);
    EXPECT_DOUBLE_EQ(s.mean, s.nominal);
    EXPECT_DOUBLE_EQ(s.p5, s.nominal);
    EXPECT_DOUBLE_EQ(s.worst, s.nominal);
    for (double loss : s.sensor_loss) EXPECT_DOUBLE_EQ(loss, 0.0);
  }
  // The same with the results reversed: the pair first chosen in the order (1, 0), so that the
  // sensors' first-seen order differs from their index order.
  std::vector<Selection> reversed = {t.results[1], t.results[0]};
  std::reverse(reversed[0].chosen.begin(), reversed[0].chosen.end());
  ASSERT_GT(reversed[0].chosen[0], reversed[0].chosen[1]);
  const PoseTolerance again = AssessPoseTolerance(t.data, reversed, *t.rays, {}, none);
  ASSERT_EQ(again.results.size(), 2u);
  for (size_t i = 0; i < 2; ++i) {
    EXPECT_DOUBLE_EQ(again.results[i].nominal, reversed[i].coverage) << i;
    EXPECT_DOUBLE_EQ(again.results[i].worst, reversed[i].coverage) << i;
    // Each sensor moved by nothing beside the others as planned loses nothing (a planned
    // observation read from another sensor's place lost half of R here).
    for (double loss : again.results[i].sensor_loss) EXPECT_DOUBLE_EQ(loss, 0.0) << i;
  }
}

TEST(PoseTolerance, TheSensorWithoutMarginCostsTheMost) {
  const TwoPlates t = MakeTwoPlates();
  PoseToleranceOptions options;
  options.position = 0.02;
  options.angle_deg = 2;
  options.samples = 32;
  options.seed = 7;
  const PoseTolerance tolerance = AssessPoseTolerance(t.data, t.results, *t.rays, {}, options);
  // A alone never loses a cell.
  const PoseSpread& a = tolerance.results[0];
  EXPECT_DOUBLE_EQ(a.worst, 0.5);
  EXPECT_DOUBLE_EQ(a.mean, 0.5);
  // With B: B's error costs, A's does not.
  const PoseSpread& both = tolerance.results[1];
  ASSERT_EQ(both.sensor_loss.size(), 2u);
  EXPECT_DOUBLE_EQ(both.sensor_loss[0], 0.0);
  EXPECT_GT(both.sensor_loss[1], 0.0);
  EXPECT_EQ(both.costliest, 1u);
  EXPECT_LT(both.worst, 1.0);
  EXPECT_LE(both.worst, both.p5);
  EXPECT_LE(both.p5, both.mean);
  EXPECT_LT(both.mean, 1.0);
  // Only B moves the union: its loss alone is the whole loss.
  EXPECT_NEAR(both.sensor_loss[1], both.nominal - both.mean, 1e-12);

  // Offsets within the ball and turns within the angle, whatever the sample.
  for (uint32_t sample = 0; sample < 32; ++sample) {
    const Pose& planned = t.data.candidates[1].world_from_body;
    const Pose moved = PerturbedPose(planned, options, 1, sample);
    EXPECT_LE((moved.position - planned.position).norm(), 0.02 + 1e-12);
    EXPECT_LE(planned.rotation.angularDistance(moved.rotation), 2 * std::numbers::pi / 180 + 1e-9);
  }

  // The same layouts on one thread.
  tbb::global_control one(tbb::global_control::max_allowed_parallelism, 1);
  const PoseTolerance again = AssessPoseTolerance(t.data, t.results, *t.rays, {}, options);
  EXPECT_EQ(again.results[1].mean, both.mean);
  EXPECT_EQ(again.results[1].worst, both.worst);
  EXPECT_EQ(again.results[1].sensor_loss, both.sensor_loss);
}

TEST(PoseTolerance, OptionsOutOfRangeNameTheOption) {
  PoseToleranceOptions bad;
  bad.position = -0.01;
  EXPECT_THROW(bad.Validate(), InputError);
  bad.position = 0.02;
  bad.angle_deg = 200;
  EXPECT_THROW(bad.Validate(), InputError);
  bad.angle_deg = 2;
  bad.samples = 0;
  try {
    bad.Validate();
    FAIL();
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("--pose-samples"), std::string::npos);
  }
}

std::string Example() {
  return std::string(VANTAGE_SOURCE_DIR) + "/examples/scenes/bin_picking_cell.yaml";
}

json ReadJson(const std::string& path) { return json::parse(test::ReadText(path)); }

// Per-part coverages, weighted by each part's cells, add up to the whole; the ceiling is what
// `evaluate` gives every candidate together.
TEST(Ceiling, PartsSumToTheWholeAndTheCeilingIsEvaluateOfAllCandidates) {
  test::TempDir dir;
  const std::string targets = " --target motor --target pipe --target gear_block";
  const auto optimize = RunVantage("-q optimize " + Example() + targets +
                                   " -n 2 --method greedy --out " + dir.File("run"));
  ASSERT_EQ(optimize.exit_code, 0) << optimize.err;
  json report = ReadJson(dir.File("run/report.json"));
  const double cells = report["reference_voxels"].get<double>();
  const json& ceiling = report["ceiling"];
  ASSERT_EQ(ceiling["parts"].size(), 3u);
  const auto weighted = [&](const auto& coverage_of) {
    double sum = 0, voxels = 0;
    for (const json& part : ceiling["parts"]) {
      sum += coverage_of(part) * part["voxels"].get<double>() / cells;
      voxels += part["voxels"].get<double>();
    }
    EXPECT_EQ(voxels, cells);
    return sum;
  };
  EXPECT_NEAR(weighted([](const json& p) { return p["coverage"].get<double>(); }),
              ceiling["coverage"].get<double>(), 1e-12);
  for (const json& result : report["results"]) {
    EXPECT_NEAR(weighted([&](const json& p) {
                  return result["part_coverage"][p["name"].get<std::string>()].get<double>();
                }),
                result["coverage"].get<double>(), 1e-12);
  }
  // Unexposed cells are none of the coverage: the ceiling stays below the exposed share.
  EXPECT_LE(ceiling["coverage"].get<double>(), 1.0 - ceiling["unexposed"].get<double>());

  // Every candidate at once: a report.json without results.
  report.erase("results");
  report.erase("primary_result");
  test::WriteText(dir.File("all.json"), report.dump());
  const auto evaluate = RunVantage("-q evaluate --constellation " + dir.File("all.json") +
                                   " --out " + dir.File("all"));
  ASSERT_EQ(evaluate.exit_code, 0) << evaluate.err;
  const json all = ReadJson(dir.File("all/report.json"));
  EXPECT_EQ(all["results"][0]["n"], report["candidates"].size());
  EXPECT_DOUBLE_EQ(all["results"][0]["coverage"].get<double>(), ceiling["coverage"].get<double>());
  EXPECT_DOUBLE_EQ(all["ceiling"]["coverage"].get<double>(), ceiling["coverage"].get<double>());
}

// rpy holds radians: an angle beyond a full turn is degrees written where radians belong,
// refused at its line with the key that takes degrees.
TEST(Words, RpyInDegreesIsRefusedAtItsLineWithAHint) {
  test::TempDir dir;
  test::WriteText(dir.File("scene.yaml"),
                  "settings: {cell_size: 0.01, n: 1}\n"
                  "objects:\n"
                  "  - name: part\n"
                  "    role: target\n"
                  "    box: {size: [0.1, 0.1, 0.1]}\n"
                  "    pose: {xyz: [0, 0, 0.05],\n"
                  "           rpy: [0, 90, -10]}\n"
                  "populations:\n"
                  "  - name: cams\n"
                  "    type: intel_realsense_d415\n"
                  "    distribution: random\n"
                  "    count: 2\n"
                  "    box: {size: [0.5, 0.5, 0.2]}\n"
                  "    pose: {xyz: [0, 0, 0.9]}\n");
  const auto run = RunVantage("optimize " + dir.File("scene.yaml") + " --out " + dir.File("out"));
  EXPECT_EQ(run.exit_code, 2) << run.err;
  EXPECT_NE(run.err.find("scene.yaml:7:"), std::string::npos) << run.err;
  EXPECT_NE(run.err.find("rpy_deg: [0, 90, -10]"), std::string::npos) << run.err;
  EXPECT_FALSE(std::filesystem::exists(dir.File("out")));
}

// A gz-sim world without the original plugin: its population looks at the targets' centre, and
// a note says so (was: at the world's origin, silently).
TEST(Words, AGzWorldWithoutThePluginAimsAtTheTargetsCentre) {
  test::TempDir dir;
  const std::string gz = test::DataPath("worlds/gz/");
  std::string text = test::ReadText(gz + "cell.sdf");
  text.replace(text.find("  </world>"), 10,
               test::ReadText(gz + "population.sdf.part") + "  </world>");
  test::WriteText(dir.File("cell.sdf"), text);
  SceneInput input;
  input.path = dir.File("cell.sdf");
  input.load.model_paths = {gz + "models"};
  const PreparedScene prepared = Prepare(input);
  const Aabb bounds = prepared.problem.scene.TargetBounds();
  const Vec3 centre = 0.5 * (bounds.min + bounds.max);
  EXPECT_TRUE(prepared.problem.observation_point.isApprox(centre, 1e-12));
  EXPECT_GT(centre.norm(), 0.01);  // not the origin: the test tells the two apart
  bool noted = false;
  for (const std::string& note : prepared.problem.notes)
    noted = noted || note.find("candidates look at the centre of the targets' bounds") !=
                         std::string::npos;
  EXPECT_TRUE(noted);
  size_t ring = 0;
  for (const Candidate& c : prepared.candidates) {
    if (c.population.empty()) continue;
    ++ring;
    const Vec3 forward = c.world_from_body.rotation * Vec3::UnitX();  // the body looks along x
    EXPECT_GT(forward.dot((centre - c.world_from_body.position).normalized()), 1 - 1e-9) << c.name;
  }
  EXPECT_EQ(ring, 12u);
}

// --pose-tolerance through the CLI: report.json and the summary carry it; 0,0 is the plan.
TEST(PoseTolerance, OptimizeReportsItAndZeroIsThePlan) {
  test::TempDir dir;
  const auto run = RunVantage("optimize " + Example() +
                              " -n 2 --method all --pose-tolerance 0,0 --pose-samples 4 --out " +
                              dir.File("run"));
  ASSERT_EQ(run.exit_code, 0) << run.err;
  EXPECT_NE(run.out.find("pose tolerance"), std::string::npos) << run.out;
  const json report = ReadJson(dir.File("run/report.json"));
  const json& tolerance = report["pose_tolerance"];
  ASSERT_EQ(tolerance["results"].size(), report["results"].size());
  for (const json& r : tolerance["results"]) {
    const double planned = report["results"][r["result"].get<size_t>()]["coverage"].get<double>();
    EXPECT_DOUBLE_EQ(r["nominal"].get<double>(), planned);
    EXPECT_DOUBLE_EQ(r["mean"].get<double>(), planned);
    EXPECT_DOUBLE_EQ(r["worst"].get<double>(), planned);
  }
  EXPECT_EQ(report["inputs"]["pose_samples"], 4);
  const auto bad = RunVantage("optimize " + Example() + " --pose-tolerance 2cm --out " +
                              dir.File("bad"));
  EXPECT_EQ(bad.exit_code, 2);
  EXPECT_NE(bad.err.find("--pose-tolerance"), std::string::npos) << bad.err;
}

}  // namespace
}  // namespace vantage
