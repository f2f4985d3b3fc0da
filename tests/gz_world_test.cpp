// gz-sim worlds (issue 19): the cameras a world declares become candidates at the poses and with
// the intrinsics that libsdformat12 resolves (its own frame graph and Camera DOM, computed here
// through its API, for the SDF versions it reads), keeping their orientation in a world without
// the Classic plugin; model:// and Fuel URIs resolve as gz-sim resolves them.
//
// sdformat's headers pull in <regex>, whose inlined code GCC 12 flags as maybe-uninitialized
// under -fsanitize=address (a false positive in libstdc++): silenced for this file only.
#if defined(__GNUC__) && !defined(__clang__)
#pragma GCC diagnostic ignored "-Wmaybe-uninitialized"
#endif
#include <fmt/format.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <functional>
#include <map>
#include <sdf/sdf.hh>
#include <set>
#include <sstream>
#include <string>
#include <vector>

#include "test_util.hpp"
#include "vantage/candidates.hpp"
#include "vantage/error.hpp"
#include "vantage/pipeline.hpp"
#include "vantage/problem.hpp"
#include "vantage/visualize.hpp"

namespace vantage {
namespace {

namespace fs = std::filesystem;

constexpr double kTol = 1e-9;

// The tests run on one thread: changing the environment is safe here.
void SetEnv(const char* name, const std::string& value) {
  ::setenv(name, value.c_str(), 1);  // NOLINT(concurrency-mt-unsafe)
}
void UnsetEnv(const char* name) {
  ::unsetenv(name);  // NOLINT(concurrency-mt-unsafe)
}
void ClearPathEnv() {
  for (const char* name : {"GAZEBO_MODEL_PATH", "GAZEBO_RESOURCE_PATH", "GZ_SIM_RESOURCE_PATH",
                           "IGN_GAZEBO_RESOURCE_PATH", "GZ_FUEL_CACHE_PATH"})
    UnsetEnv(name);
}

std::string Gz(const std::string& name) { return test::DataPath("worlds/gz/" + name); }

Pose FromIgnition(const ignition::math::Pose3d& p) {
  return Pose{Vec3(p.Pos().X(), p.Pos().Y(), p.Pos().Z()),
              Quat(p.Rot().W(), p.Rot().X(), p.Rot().Y(), p.Rot().Z())};
}

/// A camera as libsdformat's DOM gives it: world pose and the pinhole it describes.
struct DomCamera {
  Pose world_from_camera;
  int width = 0, height = 0;
  double fx = 0, fy = 0, cx = 0, cy = 0, near = 0, far = 0;
};

bool IsCameraType(sdf::SensorType type) {
  return type == sdf::SensorType::DEPTH_CAMERA || type == sdf::SensorType::RGBD_CAMERA ||
         type == sdf::SensorType::CAMERA;
}

/// Every camera of `model` and what it nests, by vantage's candidate name ("scoped" or
/// "scoped/sensor" when a model holds several).
void CollectCameras(const sdf::Model& model,
                    const Pose& world_from_model,
                    const std::string& scoped,
                    std::map<std::string, DomCamera>* out) {
  std::vector<std::pair<std::string, DomCamera>> found;
  for (uint64_t l = 0; l < model.LinkCount(); ++l) {
    const sdf::Link* link = model.LinkByIndex(l);
    for (uint64_t s = 0; s < link->SensorCount(); ++s) {
      const sdf::Sensor* sensor = link->SensorByIndex(s);
      if (!IsCameraType(sensor->Type())) continue;
      ignition::math::Pose3d model_from_sensor;
      const sdf::Errors errors = sensor->SemanticPose().Resolve(model_from_sensor, "__model__");
      EXPECT_TRUE(errors.empty()) << scoped << "/" << sensor->Name();
      const sdf::Camera* camera = sensor->CameraSensor();
      EXPECT_NE(camera, nullptr);
      if (!camera) continue;
      DomCamera c;
      c.world_from_camera = world_from_model * FromIgnition(model_from_sensor);
      c.width = static_cast<int>(camera->ImageWidth());
      c.height = static_cast<int>(camera->ImageHeight());
      const double hfov = camera->HorizontalFov().Radian();
      // Gazebo's pinhole: square pixels from the horizontal field of view, centred, unless the
      // lens gives its intrinsics.
      c.fx = c.fy = c.width / (2 * std::tan(hfov / 2));
      c.cx = c.width / 2.0;
      c.cy = c.height / 2.0;
      if (camera->HasLensIntrinsics()) {
        c.fx = camera->LensIntrinsicsFx();
        c.fy = camera->LensIntrinsicsFy();
        c.cx = camera->LensIntrinsicsCx();
        c.cy = camera->LensIntrinsicsCy();
      }
      c.near = camera->HasDepthNearClip() ? camera->DepthNearClip() : camera->NearClip();
      c.far = camera->HasDepthFarClip() ? camera->DepthFarClip() : camera->FarClip();
      found.emplace_back(sensor->Name(), c);
    }
  }
  for (const auto& [name, camera] : found)
    (*out)[found.size() > 1 ? scoped + "/" + name : scoped] = camera;
  for (uint64_t m = 0; m < model.ModelCount(); ++m) {
    const sdf::Model* nested = model.ModelByIndex(m);
    ignition::math::Pose3d model_from_nested;
    const sdf::Errors errors = nested->SemanticPose().Resolve(model_from_nested, "__model__");
    EXPECT_TRUE(errors.empty()) << scoped << "::" << nested->Name();
    CollectCameras(*nested, world_from_model * FromIgnition(model_from_nested),
                   scoped + "::" + nested->Name(), out);
  }
}

/// The world's cameras through libsdformat; `find` resolves URIs as the loader is told to.
std::map<std::string, DomCamera> SdformatCameras(
    const std::string& path, const std::function<std::string(const std::string&)>& find) {
  sdf::Console::Instance()->SetQuiet(true);
  sdf::ParserConfig config;
  config.SetFindCallback(find);
  sdf::Root root;
  const sdf::Errors errors = root.Load(path, config);
  EXPECT_TRUE(errors.empty()) << errors.front().Message();
  std::map<std::string, DomCamera> cameras;
  if (root.WorldCount() != 1) return cameras;
  const sdf::World* world = root.WorldByIndex(0);
  for (uint64_t m = 0; m < world->ModelCount(); ++m) {
    const sdf::Model* model = world->ModelByIndex(m);
    ignition::math::Pose3d world_from_model;
    EXPECT_TRUE(model->SemanticPose().Resolve(world_from_model, "world").empty());
    CollectCameras(*model, FromIgnition(world_from_model), model->Name(), &cameras);
  }
  return cameras;
}

/// model:// against one folder (sdformat's own callback; vantage is given the same folder).
std::function<std::string(const std::string&)> ModelDir(const std::string& dir) {
  return [dir](const std::string& uri) -> std::string {
    if (uri.rfind("model://", 0) != 0) return "";
    const std::string candidate = dir + "/" + uri.substr(8);
    return fs::exists(candidate) ? candidate : "";
  };
}

std::vector<Candidate> Deploy(const Problem& problem) {
  DeployOptions options;
  options.observation_point = problem.observation_point;
  options.random_roll = problem.random_roll;
  options.seed = problem.seed;
  return DeployCandidates(problem.populations, problem.sensors, problem.sensor_types, options);
}

void ExpectSameCameras(const std::vector<Candidate>& candidates,
                       const std::map<std::string, DomCamera>& reference) {
  ASSERT_EQ(candidates.size(), reference.size());
  for (const Candidate& c : candidates) {
    const auto it = reference.find(c.name);
    ASSERT_NE(it, reference.end()) << c.name << " is not a camera of sdformat's DOM";
    const DomCamera& d = it->second;
    EXPECT_LT((c.world_from_body.position - d.world_from_camera.position).norm(), kTol) << c.name;
    EXPECT_LT(c.world_from_body.rotation.angularDistance(d.world_from_camera.rotation), kTol)
        << c.name;
    EXPECT_EQ(c.sensor.width, d.width) << c.name;
    EXPECT_EQ(c.sensor.height, d.height) << c.name;
    EXPECT_NEAR(c.sensor.fx, d.fx, kTol) << c.name;
    EXPECT_NEAR(c.sensor.fy, d.fy, kTol) << c.name;
    EXPECT_NEAR(c.sensor.cx, d.cx, kTol) << c.name;
    EXPECT_NEAR(c.sensor.cy, d.cy, kTol) << c.name;
    EXPECT_NEAR(c.sensor.near, d.near, kTol) << c.name;
    EXPECT_NEAR(c.sensor.far, d.far, kTol) << c.name;
  }
}

TEST(GzWorld, CamerasAreCandidatesWhereSdformatPutsThem) {
  ClearPathEnv();
  LoadOptions options;
  options.model_paths = {Gz("models")};
  const Problem problem = LoadGazeboWorld(Gz("cell.sdf"), options);
  const std::vector<Candidate> candidates = Deploy(problem);
  const auto reference = SdformatCameras(Gz("cell.sdf"), ModelDir(Gz("models")));
  EXPECT_EQ(reference.size(), 3u);
  ExpectSameCameras(candidates, reference);
  // The lens intrinsics replace the field of view (fx would be 233.9 from 1.2 rad).
  ASSERT_TRUE(reference.count("cam_a"));
  EXPECT_EQ(reference.at("cam_a").fx, 250);
  EXPECT_EQ(reference.at("cam_a").cx, 150);
}

// SDF 1.8's placement_frame (an include's element, a model's attribute, a nested model's) and
// poses relative_to world-level frames, models and named includes: every camera where
// libsdformat's own pose resolution puts it (issue 44: placement_frame was ignored, a camera
// 10 cm off; relative_to another model was refused).
TEST(GzWorld, PlacementFrameAndWorldLevelRelativeToAsSdformat) {
  ClearPathEnv();
  test::TempDir dir;
  const std::string world = R"(<?xml version="1.0"?>
<sdf version="1.9">
  <world name="frames">
    <model name="part">
      <static>true</static>
      <pose>0 0 0.05 0 0 0.3</pose>
      <link name="body">
        <visual name="v">
          <geometry><box><size>0.1 0.1 0.1</size></box></geometry>
          <material><diffuse>0 1 0 1</diffuse></material>
        </visual>
      </link>
    </model>
    <frame name="fixture">
      <pose relative_to="part">0.4 0.1 0.5 0.1 0.2 0.3</pose>
    </frame>
    <frame name="mount" attached_to="fixture">
      <pose>0.05 0 0.02 0 0.4 0</pose>
    </frame>
    <include>
      <name>cam_placed</name>
      <uri>model://gz_depth_cam</uri>
      <pose relative_to="mount">0 0 0 0 0.3 3.0</pose>
      <placement_frame>body</placement_frame>
    </include>
    <include>
      <name>cam_plain</name>
      <uri>model://gz_depth_cam</uri>
      <pose relative_to="fixture">0.1 -0.3 0.05 0 0.2 2.5</pose>
    </include>
    <include>
      <name>cam_beside</name>
      <uri>model://gz_depth_cam</uri>
      <pose relative_to="cam_plain">0 0.2 0 0 0 0</pose>
    </include>
    <model name="cam_attribute" placement_frame="lens">
      <static>true</static>
      <pose relative_to="fixture">-0.6 0.3 0 0 0.5 -0.4</pose>
      <link name="link">
        <pose>0.01 0.02 0.03 0 0.1 0</pose>
        <sensor name="depth" type="depth_camera">
          <pose>0.005 0 0.01 0 0 0.1</pose>
          <camera>
            <horizontal_fov>1.0</horizontal_fov>
            <image><width>160</width><height>120</height></image>
            <clip><near>0.1</near><far>4</far></clip>
          </camera>
        </sensor>
      </link>
      <frame name="lens" attached_to="link">
        <pose relative_to="link">0.02 0 0 0 0.2 0</pose>
      </frame>
    </model>
    <model name="rig">
      <static>true</static>
      <pose>-0.5 -0.4 0.6 0 0 0.8</pose>
      <link name="base"/>
      <model name="arm" placement_frame="tip">
        <pose>0.1 0 0.1 0 0.7 0</pose>
        <link name="tip">
          <pose>0.03 0.01 -0.02 0.2 0 0</pose>
        </link>
        <link name="link">
          <sensor name="depth" type="depth_camera">
            <camera>
              <horizontal_fov>1.0</horizontal_fov>
              <image><width>160</width><height>120</height></image>
              <clip><near>0.1</near><far>4</far></clip>
            </camera>
          </sensor>
        </link>
      </model>
    </model>
  </world>
</sdf>
)";
  test::WriteText(dir.File("frames.sdf"), world);
  const auto reference = SdformatCameras(dir.File("frames.sdf"), ModelDir(Gz("models")));
  ASSERT_EQ(reference.size(), 5u);
  LoadOptions options;
  options.model_paths = {Gz("models")};
  const Problem problem = LoadGazeboWorld(dir.File("frames.sdf"), options);
  ExpectSameCameras(Deploy(problem), reference);

  const auto line_of = [](const std::string& text, const std::string& needle) {
    const size_t at = text.find(needle);
    EXPECT_NE(at, std::string::npos) << needle;
    return 1 + std::count(text.begin(), text.begin() + static_cast<std::ptrdiff_t>(at), '\n');
  };
  const auto refused = [&](const std::string& text, const std::string& file) {
    test::WriteText(dir.File(file), text);
    try {
      LoadGazeboWorld(dir.File(file), options);
    } catch (const InputError& e) {
      return std::string(e.what());
    }
    return std::string("accepted");
  };
  // A pose relative to a model that its placement frame places: refused at the pose's line.
  std::string relative = world;
  relative.replace(relative.find("relative_to=\"cam_plain\""), 23, "relative_to=\"cam_placed\"");
  EXPECT_NE(refused(relative, "relative.sdf")
                .find(fmt::format("relative.sdf:{}: relative_to 'cam_placed' names a model placed "
                                  "by its placement_frame",
                                  line_of(relative, "relative_to=\"cam_placed\""))),
            std::string::npos)
      << refused(relative, "relative.sdf");
  // A name that is no world-level frame, model or named include: refused at its line.
  std::string unknown = world;
  unknown.replace(unknown.find("relative_to=\"mount\""), 19, "relative_to=\"nowhere\"");
  EXPECT_NE(refused(unknown, "unknown.sdf")
                .find(fmt::format("unknown.sdf:{}: relative_to 'nowhere' names no frame, model or "
                                  "named include of the world",
                                  line_of(unknown, "relative_to=\"nowhere\""))),
            std::string::npos)
      << refused(unknown, "unknown.sdf");
  // A placement frame that the model does not have: refused at its line.
  std::string missing = world;
  missing.replace(missing.find("<placement_frame>body<"), 22, "<placement_frame>lens<");
  EXPECT_NE(refused(missing, "missing.sdf")
                .find(fmt::format("missing.sdf:{}: placement_frame 'lens' names no link, model "
                                  "or frame of model 'cam_placed'",
                                  line_of(missing, "<placement_frame>lens<"))),
            std::string::npos)
      << refused(missing, "missing.sdf");
}

// The same world in SDF 1.11 (beyond libsdformat12): vantage's own reader, the same cameras.
TEST(GzWorld, NewerSdfVersionsReadTheSame) {
  ClearPathEnv();
  test::TempDir dir;
  std::string text = test::ReadText(Gz("cell.sdf"));
  text.replace(text.find("version=\"1.9\""), 13, "version=\"1.11\"");
  test::WriteText(dir.File("cell.sdf"), text);
  LoadOptions options;
  options.model_paths = {Gz("models")};
  const Problem problem = LoadGazeboWorld(dir.File("cell.sdf"), options);
  for (const std::string& note : problem.notes)
    EXPECT_EQ(note.find("SDF version"), std::string::npos);
  ExpectSameCameras(Deploy(problem), SdformatCameras(Gz("cell.sdf"), ModelDir(Gz("models"))));
}

// GZ_SIM_RESOURCE_PATH and IGN_GAZEBO_RESOURCE_PATH hold model folders, as gz-sim reads them.
TEST(GzWorld, ResourcePathVariablesFindModels) {
  const auto reference = SdformatCameras(Gz("cell.sdf"), ModelDir(Gz("models")));
  // A copy without the models/ folder beside it.
  test::TempDir dir;
  test::WriteText(dir.File("cell.sdf"), test::ReadText(Gz("cell.sdf")));
  for (const char* variable :
       {"GZ_SIM_RESOURCE_PATH", "IGN_GAZEBO_RESOURCE_PATH", "GAZEBO_MODEL_PATH"}) {
    ClearPathEnv();
    SetEnv(variable, "/nonexistent:" + Gz("models"));
    ExpectSameCameras(Deploy(LoadGazeboWorld(dir.File("cell.sdf"))), reference);
  }
  ClearPathEnv();
  EXPECT_THROW(LoadGazeboWorld(dir.File("cell.sdf")), InputError);  // model://gz_depth_cam
}

/// A HOME with the test's Fuel cache at HOME/.gz/fuel (gz-fuel-tools' layout).
struct FuelHome {
  test::TempDir home;
  std::string cache = home.File(".gz/fuel");
  FuelHome() {
    fs::create_directories(cache);
    fs::copy(Gz("fuel_cache"), cache, fs::copy_options::recursive);
  }
  /// Where gz-fuel-tools keeps a version of the test model, worked out by hand.
  std::string Model(int version) const {
    return fmt::format("{}/fuel.gazebosim.org/openrobotics/models/fuel cam/{}", cache, version);
  }
};

TEST(GzWorld, FuelUrisResolveFromTheLocalCache) {
  ClearPathEnv();
  const FuelHome fuel;
  const char* old_home = std::getenv("HOME");  // NOLINT(concurrency-mt-unsafe)
  const std::string saved = old_home ? old_home : "";
  SetEnv("HOME", fuel.home.path());
  // sdformat is told by hand where each URI lives: no version = the newest (2), owner and name
  // matched without case, %20 a space.
  const std::map<std::string, std::string> where = {
      {"https://fuel.gazebosim.org/1.0/OpenRobotics/models/Fuel%20Cam", fuel.Model(2)},
      {"https://fuel.gazebosim.org/1.0/openrobotics/models/fuel cam/1", fuel.Model(1)}};
  const auto reference = SdformatCameras(Gz("fuel.sdf"), [&](const std::string& uri) {
    const auto it = where.find(uri);
    return it == where.end() ? std::string() : it->second;
  });
  ASSERT_EQ(reference.size(), 2u);
  ExpectSameCameras(Deploy(LoadGazeboWorld(Gz("fuel.sdf"))), reference);
  // GZ_FUEL_CACHE_PATH replaces HOME/.gz/fuel.
  SetEnv("HOME", "/nonexistent");
  SetEnv("GZ_FUEL_CACHE_PATH", fuel.cache);
  ExpectSameCameras(Deploy(LoadGazeboWorld(Gz("fuel.sdf"))), reference);

  // A model that is not in the cache: file:line, the URI and the cache folder; exit 2 from the CLI.
  test::TempDir dir;
  std::string text = test::ReadText(Gz("fuel.sdf"));
  const std::string missing = "https://fuel.gazebosim.org/1.0/OpenRobotics/models/Not%20Here";
  text.replace(text.find("https://fuel.gazebosim.org/1.0/openrobotics/models/fuel cam/1"),
               std::string("https://fuel.gazebosim.org/1.0/openrobotics/models/fuel cam/1").size(),
               missing);
  test::WriteText(dir.File("w.sdf"), text);
  int line = 0;
  for (size_t at = 0; at < text.find(missing); at = text.find('\n', at) + 1) ++line;
  try {
    LoadGazeboWorld(dir.File("w.sdf"));
    ADD_FAILURE() << "no error";
  } catch (const InputError& e) {
    const std::string message = e.what();
    EXPECT_NE(message.find(fmt::format("{}:{}:", dir.File("w.sdf"), line)), std::string::npos)
        << message;
    EXPECT_NE(message.find(missing), std::string::npos) << message;
    EXPECT_NE(message.find(fuel.cache + "/fuel.gazebosim.org"), std::string::npos) << message;
  }
  const test::CommandResult cli =
      test::RunVantage("optimize '" + dir.File("w.sdf") + "' --out '" + dir.File("out") + "'");
  EXPECT_EQ(cli.exit_code, 2) << cli.err;
  EXPECT_NE(cli.err.find(missing), std::string::npos) << cli.err;
  EXPECT_FALSE(fs::exists(dir.File("out")));
  UnsetEnv("GZ_FUEL_CACHE_PATH");
  SetEnv("HOME", saved);
}

/// The YAML scene of cell.sdf: its objects by hand, its cameras from libsdformat's DOM.
std::string YamlEquivalent(const std::map<std::string, DomCamera>& cameras) {
  std::string yaml =
      "objects:\n"
      "  - {name: table, role: occluder, box: {size: [1, 1, 0.05]}, pose: {xyz: [0, 0, -0.025]}}\n"
      "  - {name: part, role: target, box: {size: [0.1, 0.1, 0.1]},\n"
      "     pose: {xyz: [0, 0, 0.05], rpy: [0, 0, 0.3]}}\n"
      "  - {name: post, role: occluder, cylinder: {radius: 0.02, length: 0.2},\n"
      "     pose: {xyz: [0.2, 0.15, 0.1]}}\n"
      "sensor_types:\n";
  std::string sensors = "sensors:\n";
  int i = 0;
  for (const auto& [name, c] : cameras) {
    yaml += fmt::format(
        "  - {{id: cam{}, resolution: [{}, {}], intrinsics: [{:.17g}, {:.17g}, {:.17g}, {:.17g}],"
        " range: [{:.17g}, {:.17g}]}}\n",
        i, c.width, c.height, c.fx, c.fy, c.cx, c.cy, c.near, c.far);
    const Pose& p = c.world_from_camera;
    sensors += fmt::format(
        "  - {{name: '{}', type: cam{}, position: [{:.17g}, {:.17g}, {:.17g}],\n"
        "     orientation: {{quaternion: [{:.17g}, {:.17g}, {:.17g}, {:.17g}]}}}}\n",
        name, i, p.position.x(), p.position.y(), p.position.z(), p.rotation.w(), p.rotation.x(),
        p.rotation.y(), p.rotation.z());
    ++i;
  }
  return yaml + sensors;
}

EvaluateResult EvaluateDeclared(const std::string& path, const std::vector<std::string>& models) {
  EvaluateOptions options;
  options.scene.path = path;
  options.scene.load.model_paths = models;
  return Evaluate(options);
}

// `vantage evaluate world.sdf` without --constellation scores the world's own layout; the YAML
// equivalent of the same scene gives the same coverage, sensor by sensor.
TEST(GzWorld, EvaluateScoresTheWorldsLayoutAsItsYamlEquivalent) {
  ClearPathEnv();
  const auto reference = SdformatCameras(Gz("cell.sdf"), ModelDir(Gz("models")));
  test::TempDir dir;
  test::WriteText(dir.File("cell.yaml"), YamlEquivalent(reference));
  const EvaluateResult world = EvaluateDeclared(Gz("cell.sdf"), {Gz("models")});
  const EvaluateResult yaml = EvaluateDeclared(dir.File("cell.yaml"), {});
  ASSERT_EQ(world.sensor_coverage.size(), 3u);
  ASSERT_EQ(yaml.sensor_coverage.size(), 3u);
  EXPECT_GT(world.run.report.results[0].coverage, 0.3);
  EXPECT_EQ(world.run.report.results[0].coverage, yaml.run.report.results[0].coverage);
  EXPECT_EQ(world.run.data->reference.size(), yaml.run.data->reference.size());
  const auto& a = world.run.data->candidates;
  const auto& b = yaml.run.data->candidates;
  for (size_t i = 0; i < a.size(); ++i) {
    const auto j = static_cast<size_t>(
        std::find_if(b.begin(), b.end(), [&](const Candidate& c) { return c.name == a[i].name; }) -
        b.begin());
    ASSERT_LT(j, b.size()) << a[i].name;
    EXPECT_EQ(world.sensor_coverage[i], yaml.sensor_coverage[j]) << a[i].name;
  }
}

/// optimize on cell.sdf with a population of 12 cameras added (population.sdf.part), written
/// into `dir`; n = 5, --keep-existing.
OptimizeOptions PopulatedCell(const test::TempDir& dir) {
  std::string text = test::ReadText(Gz("cell.sdf"));
  text.replace(text.find("  </world>"), 10,
               test::ReadText(Gz("population.sdf.part")) + "  </world>");
  test::WriteText(dir.File("cell.sdf"), text);
  OptimizeOptions options;
  options.scene.path = dir.File("cell.sdf");
  options.scene.load.model_paths = {Gz("models")};
  options.selection.n = 5;
  options.selection.keep_existing = true;
  return options;
}

// --keep-existing: every method's answer holds the world's cameras, and exact's is the best
// such answer, checked by enumerating every completion.
TEST(GzWorld, KeepExistingKeepsTheWorldsCamerasInEveryMethod) {
  ClearPathEnv();
  test::TempDir dir;
  OptimizeOptions options = PopulatedCell(dir);
  options.selection.keep_existing = true;
  const RunResult run = Optimize(options);
  const VisibilityFile& data = *run.data;
  std::vector<uint32_t> kept;
  for (uint32_t i = 0; i < data.candidates.size(); ++i)
    if (data.candidates[i].population.empty()) kept.push_back(i);
  ASSERT_EQ(kept.size(), 3u);
  ASSERT_GT(data.candidates.size(), 8u);
  std::set<std::string> methods;
  const CoverageEvaluator evaluator(data.observations, data.reference.size());
  for (const Selection& s : run.report.results) {
    methods.insert(s.method);
    for (const uint32_t k : kept)
      EXPECT_NE(std::find(s.chosen.begin(), s.chosen.end(), k), s.chosen.end()) << s.method;
    if (s.method != "exact" || s.n != 5) continue;
    // Every pair of the others completes the kept three: exact is the best of them.
    size_t best = 0;
    for (uint32_t a = 0; a < data.candidates.size(); ++a)
      for (uint32_t b = a + 1; b < data.candidates.size(); ++b) {
        if (!data.candidates[a].population.empty() && !data.candidates[b].population.empty()) {
          std::vector<uint32_t> chosen = kept;
          chosen.push_back(a);
          chosen.push_back(b);
          best = std::max(best, evaluator.CoveredCount(chosen));
        }
      }
    EXPECT_EQ(evaluator.CoveredCount(s.chosen), best);
    EXPECT_TRUE(s.proven_optimal);
  }
  EXPECT_EQ(methods, (std::set<std::string>{"best", "ransac", "greedy", "local", "exact"}));
  // The run says it kept them (report.json inputs), so that a rerun from it can do the same.
  ASSERT_TRUE(run.report.inputs.has_value());
  EXPECT_TRUE(run.report.inputs->selection.keep_existing);
  EXPECT_NE(run.files.at("report.json").find("\"keep_existing\": true"), std::string::npos);

  // A goal and a budget count the kept sensors too.
  options.selection.n.reset();
  options.selection.goal = 0.65;
  for (const Selection& s : Optimize(options).report.results) {
    EXPECT_GE(s.coverage, 0.65) << s.method;
    for (const uint32_t k : kept)
      EXPECT_NE(std::find(s.chosen.begin(), s.chosen.end(), k), s.chosen.end()) << s.method;
  }
  options.selection.goal.reset();
  options.selection.budget = 4;  // unit costs: the kept three and one more
  for (const Selection& s : Optimize(options).report.results) {
    EXPECT_EQ(s.chosen.size(), 4u) << s.method;
    for (const uint32_t k : kept)
      EXPECT_NE(std::find(s.chosen.begin(), s.chosen.end(), k), s.chosen.end()) << s.method;
  }
  options.selection.budget = 2;
  try {
    Optimize(options);
    ADD_FAILURE() << "no error";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("--budget:"), std::string::npos) << e.what();
  }
  options.selection.budget.reset();

  // n below the kept sensors names the option.
  options.selection.n = 2;
  try {
    Optimize(options);
    ADD_FAILURE() << "no error";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("-n:"), std::string::npos) << e.what();
  }
}

/// Runs a command, returning its standard output.
std::string Output(const std::string& command) {
  std::string out;
  FILE* pipe = ::popen(command.c_str(), "r");  // NOLINT(cert-env33-c): the test's own command
  if (!pipe) return out;
  char buffer[4096];
  while (size_t n = std::fread(buffer, 1, sizeof buffer, pipe)) out.append(buffer, n);
  EXPECT_EQ(::pclose(pipe), 0) << command;
  return out;
}

/// The model name constellation.sdf uses ("rig::mount" -> "rig__mount").
std::string Exported(std::string name) {
  for (size_t at; (at = name.find("::")) != std::string::npos;) name.replace(at, 2, "__");
  return name;
}

// constellation.sdf loads in libsdformat without errors, with each chosen camera exactly at its
// pose and with its intrinsics; cameras.urdf.xacro and static_transforms.launch.py parse (Python's
// XML parser and ast) and carry the same poses, the optical frames rotated by rpy(-pi/2, 0, -pi/2).
TEST(GzWorld, ExportsPutTheChosenCamerasBackExactly) {
  ClearPathEnv();
  test::TempDir dir;
  OptimizeOptions options = PopulatedCell(dir);
  options.selection.method = Method::kExact;
  options.selection.keep_existing = true;
  const RunResult run = Optimize(options);
  for (const char* name : {"constellation.sdf", "cameras.urdf.xacro", "static_transforms.launch.py",
                           "constellation.world", "static_transforms.yaml"})
    ASSERT_TRUE(run.files.count(name)) << name;
  std::vector<Candidate> chosen;
  for (const uint32_t i : run.report.PrimaryChosen()) chosen.push_back(run.data->candidates[i]);
  ASSERT_EQ(chosen.size(), 5u);
  std::vector<Candidate> as_models = chosen;
  for (Candidate& c : as_models) c.name = Exported(c.name);

  const std::string sdf = run.files.at("constellation.sdf");
  test::WriteText(dir.File("out/constellation.sdf"), sdf);
  ExpectSameCameras(as_models,
                    SdformatCameras(dir.File("out/constellation.sdf"), ModelDir(Gz("models"))));
  // The ROS exports name frames by docs/outputs.md's encoding ("rig::mount" -> "rig..mount").
  for (Candidate& c : chosen) c.name = ExportedFrameName(c.name);
  // Only cam_a (off-centre, fx != fy) needs <lens><intrinsics>; one Sensors system.
  size_t intrinsics = 0;
  for (size_t at = 0; (at = sdf.find("<intrinsics>", at)) != std::string::npos; ++at) ++intrinsics;
  EXPECT_EQ(intrinsics, 1u);
  EXPECT_EQ(sdf.find("gz-sim-sensors-system"), sdf.rfind("gz-sim-sensors-system"));

  test::WriteText(dir.File("out/cameras.urdf.xacro"), run.files.at("cameras.urdf.xacro"));
  test::WriteText(dir.File("out/launch.py"), run.files.at("static_transforms.launch.py"));
  const std::string lines =
      Output(fmt::format("python3 '{}' '{}' '{}'", Gz("read_ros_exports.py"),
                         dir.File("out/cameras.urdf.xacro"), dir.File("out/launch.py")));
  std::map<std::string, Pose> xacro;
  std::map<std::string, Pose> launch;
  std::map<std::string, std::string> parent;
  std::istringstream in(lines);
  for (std::string kind, child, from; in >> kind >> child >> from;) {
    std::vector<double> v(kind == "xacro" ? 6 : 7);
    for (double& x : v) in >> x;
    const Pose pose = kind == "xacro" ? Pose::FromXyzRpy(v[0], v[1], v[2], v[3], v[4], v[5])
                                      : Pose{Vec3(v[0], v[1], v[2]), Quat(v[6], v[3], v[4], v[5])};
    (kind == "xacro" ? xacro : launch)[child] = pose;
    if (kind == "xacro") parent[child] = from;
  }
  ASSERT_EQ(xacro.size(), 10u) << lines;
  ASSERT_EQ(launch.size(), 10u) << lines;
  // The optical frame by hand: z forward = body x, x right = body -y, y down = body -z.
  Mat3 body_from_optical;
  body_from_optical << 0, 0, 1, -1, 0, 0, 0, -1, 0;
  for (const Candidate& c : chosen) {
    for (const auto* frames : {&xacro, &launch}) {
      ASSERT_TRUE(frames->count(c.name)) << c.name;
      const Pose& body = frames->at(c.name);
      EXPECT_LT((body.position - c.world_from_body.position).norm(), kTol) << c.name;
      EXPECT_LT(body.rotation.angularDistance(c.world_from_body.rotation), kTol) << c.name;
      const Pose& optical = frames->at(c.name + "_optical_frame");
      EXPECT_LT(optical.position.norm(), kTol);
      EXPECT_LT(optical.rotation.angularDistance(Quat(body_from_optical)), kTol) << c.name;
    }
    EXPECT_EQ(parent.at(c.name), "${parent}");
    EXPECT_EQ(parent.at(c.name + "_optical_frame"), c.name);
  }
}

}  // namespace
}  // namespace vantage
