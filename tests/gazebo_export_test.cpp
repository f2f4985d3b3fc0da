// constellation.world (ConstellationWorld, SYSTEM.md "Outputs"): the exported world loads in
// libsdformat (the reference SDF parser, as Gazebo would) with every chosen camera exactly at its
// candidate's pose, holds no population and only the chosen sensors, keeps the rest of the text,
// and reloads in vantage to the same candidates. Then `vantage optimize` on the shared
// bin_picking world, with no option but the model path (the plugin's parameters rule).
//
// sdformat's headers pull in <regex>, whose inlined code GCC 12 flags as maybe-uninitialized
// under -fsanitize=address (a false positive in libstdc++): silenced for this file only.
#if defined(__GNUC__) && !defined(__clang__)
#pragma GCC diagnostic ignored "-Wmaybe-uninitialized"
#endif
#include "vantage/gazebo_export.hpp"

#include <fmt/format.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <map>
#include <nlohmann/json.hpp>
#include <numbers>
#include <sdf/sdf.hh>
#include <set>
#include <string>
#include <vector>

#include "scene/sdf/world.hpp"
#include "test_util.hpp"
#include "util/xml.hpp"
#include "vantage/error.hpp"
#include "vantage/problem.hpp"

namespace vantage {
namespace {

constexpr double kTol = 1e-9;

// The tests run on one thread: changing the environment is safe here.
void SetEnv(const char* name, const std::string& value) {
  ::setenv(name, value.c_str(), 1);  // NOLINT(concurrency-mt-unsafe)
}
void UnsetEnv(const char* name) {
  ::unsetenv(name);  // NOLINT(concurrency-mt-unsafe)
}

Problem Load(const std::string& path, const LoadOptions& options = {}) {
  UnsetEnv("GAZEBO_MODEL_PATH");
  UnsetEnv("GAZEBO_RESOURCE_PATH");
  return LoadGazeboWorld(path, options);
}

std::string World(const std::string& name) { return test::DataPath("worlds/" + name); }

double AngleBetween(const Quat& a, const Quat& b) { return a.angularDistance(b); }

void ExpectPose(const Pose& actual, const Pose& expected, double tol, const std::string& what) {
  EXPECT_LT((actual.position - expected.position).norm(), tol) << what;
  EXPECT_LT(AngleBetween(actual.rotation, expected.rotation), tol) << what;
}

std::vector<Candidate> Deploy(const Problem& problem, bool random_roll) {
  DeployOptions options;
  options.observation_point = problem.observation_point;
  options.random_roll = random_roll;
  options.seed = problem.seed;
  return DeployCandidates(problem.populations, problem.sensors, problem.sensor_types, options);
}

std::vector<Candidate> Pick(const std::vector<Candidate>& candidates,
                            const std::vector<std::string>& names) {
  std::vector<Candidate> chosen;
  for (const std::string& name : names) {
    const auto it = std::find_if(candidates.begin(), candidates.end(),
                                 [&](const Candidate& c) { return c.name == name; });
    EXPECT_NE(it, candidates.end()) << name;
    if (it != candidates.end()) chosen.push_back(*it);
  }
  return chosen;
}

Pose FromIgnition(const ignition::math::Pose3d& p) {
  return Pose{Vec3(p.Pos().X(), p.Pos().Y(), p.Pos().Z()),
              Quat(p.Rot().W(), p.Rot().X(), p.Rot().Y(), p.Rot().Z())};
}

/// A world loaded by libsdformat, model:// resolved against `model_dir`: the errors, the names of
/// its models and the world pose of each model's depth camera.
struct SdfWorld {
  std::vector<std::string> errors;
  std::set<std::string> models;
  std::map<std::string, Pose> cameras;  ///< model name -> world_from_camera
  std::set<std::string> populations;    ///< names of the world's <population> elements
};

SdfWorld LoadWithSdformat(const std::string& path, const std::string& model_dir) {
  sdf::Console::Instance()->SetQuiet(true);
  sdf::ParserConfig config;
  config.SetFindCallback([model_dir](const std::string& uri) -> std::string {
    if (uri.rfind("model://", 0) != 0) return "";
    const std::string candidate = model_dir + "/" + uri.substr(8);
    // sdformat wants a model.config in a model folder; the test models may have only model.sdf.
    if (std::filesystem::is_directory(candidate) &&
        !std::filesystem::exists(candidate + "/model.config"))
      return candidate + "/model.sdf";
    return std::filesystem::exists(candidate) ? candidate : "";
  });
  SdfWorld result;
  sdf::Root root;
  for (const sdf::Error& e : root.Load(path, config)) result.errors.push_back(e.Message());
  if (root.WorldCount() != 1) {
    result.errors.emplace_back("no world");
    return result;
  }
  const sdf::World* world = root.WorldByIndex(0);
  for (sdf::ElementPtr e = world->Element()->GetElementImpl("population"); e;
       e = e->GetNextElement("population")) {
    result.populations.insert(e->Get<std::string>("name"));
  }
  for (uint64_t m = 0; m < world->ModelCount(); ++m) {
    const sdf::Model* model = world->ModelByIndex(m);
    result.models.insert(model->Name());
    ignition::math::Pose3d world_from_model;
    const sdf::Errors errors = model->SemanticPose().Resolve(world_from_model, "world");
    EXPECT_TRUE(errors.empty()) << model->Name();
    for (uint64_t l = 0; l < model->LinkCount(); ++l) {
      const sdf::Link* link = model->LinkByIndex(l);
      for (uint64_t s = 0; s < link->SensorCount(); ++s) {
        const sdf::Sensor* sensor = link->SensorByIndex(s);
        if (sensor->Type() != sdf::SensorType::DEPTH_CAMERA) continue;
        ignition::math::Pose3d model_from_sensor;
        const sdf::Errors sensor_errors =
            sensor->SemanticPose().Resolve(model_from_sensor, "__model__");
        EXPECT_TRUE(sensor_errors.empty()) << model->Name() << "/" << sensor->Name();
        result.cameras[model->Name()] =
            FromIgnition(world_from_model) * FromIgnition(model_from_sensor);
      }
    }
  }
  return result;
}

std::string Between(const std::string& text, const std::string& from, const std::string& to) {
  const size_t begin = text.find(from);
  const size_t end = text.find(to, begin);
  if (begin == std::string::npos || end == std::string::npos) return "";
  return text.substr(begin, end + to.size() - begin);
}

const std::vector<std::string> kChosen = {"box_random_2", "line_1", "fixed_camera", "rig::wrist"};
const std::set<std::string> kExportedSensors = {"box_random_2", "line_1", "fixed_camera",
                                                "rig__wrist"};

TEST(GazeboExport, GazeboPutsEveryChosenCameraExactlyAtItsCandidatePose) {
  const std::string path = World("export.world");
  const Problem problem = Load(path);
  ASSERT_TRUE(problem.random_roll);
  const std::vector<Candidate> candidates = Deploy(problem, problem.random_roll);
  ASSERT_EQ(candidates.size(), 12u);
  const std::vector<Candidate> chosen = Pick(candidates, kChosen);

  std::vector<std::string> notes;
  const std::string text =
      ConstellationWorld(path, chosen, problem.populations, problem.sensors, &notes);
  EXPECT_TRUE(notes.empty()) << notes.front();
  test::TempDir dir;
  test::WriteText(dir.File("constellation.world"), text);

  // The input itself loads cleanly: every difference below comes from the export.
  const SdfWorld input = LoadWithSdformat(path, World("models"));
  ASSERT_TRUE(input.errors.empty()) << input.errors.front();
  EXPECT_EQ(input.populations, (std::set<std::string>{"box_random", "line"}));

  const SdfWorld output = LoadWithSdformat(dir.File("constellation.world"), World("models"));
  ASSERT_TRUE(output.errors.empty()) << output.errors.front();
  EXPECT_TRUE(output.populations.empty());
  std::set<std::string> models = kExportedSensors;
  models.insert({"target_box", "block", "rig"});
  EXPECT_EQ(output.models, models);
  // Exactly the chosen cameras (inline_fixed is gone, rig::wrist moved out of the rig), each
  // where its candidate is, random roll included: Gazebo needs no re-orientation.
  std::set<std::string> cameras;
  for (const auto& [name, pose] : output.cameras) cameras.insert(name);
  EXPECT_EQ(cameras, kExportedSensors);
  for (size_t i = 0; i < chosen.size(); ++i) {
    const std::string exported = kChosen[i] == "rig::wrist" ? "rig__wrist" : kChosen[i];
    ASSERT_TRUE(output.cameras.count(exported)) << exported;
    ExpectPose(output.cameras.at(exported), chosen[i].world_from_body, kTol, exported);
  }
}

TEST(GazeboExport, KeepsTheRestOfTheWorldTextAsItWas) {
  const std::string path = World("export.world");
  const Problem problem = Load(path);
  const std::vector<Candidate> chosen = Pick(Deploy(problem, true), kChosen);
  const std::string text = ConstellationWorld(path, chosen, problem.populations, problem.sensors);
  const std::string input = test::ReadText(path);

  // Everything before the first sensor is byte for byte the input's.
  const size_t first_sensor = input.find("    <include>\n      <uri>model://test_camera</uri>");
  ASSERT_NE(first_sensor, std::string::npos);
  EXPECT_EQ(text.substr(0, first_sensor), input.substr(0, first_sensor));
  // The rig without its camera, physics and plugin as written; the plugin's sensor count is that
  // of the new world.
  const std::string physics = Between(input, "    <physics", "</physics>\n");
  ASSERT_FALSE(physics.empty());
  EXPECT_NE(text.find(physics), std::string::npos);
  std::string plugin = Between(input, "    <plugin", "</plugin>\n");
  ASSERT_FALSE(plugin.empty());
  const std::string count = "<numberOfSamplingSensors>12</numberOfSamplingSensors>";
  plugin.replace(plugin.find(count), count.size(),
                 "<numberOfSamplingSensors>4</numberOfSamplingSensors>");
  EXPECT_NE(text.find(plugin), std::string::npos) << text;
  EXPECT_NE(text.find("  </world>\n</sdf>\n"), std::string::npos);
  const std::string rig = Between(text, "    <model name=\"rig\">", "    </model>\n");
  EXPECT_EQ(rig.find("wrist"), std::string::npos) << rig;
  EXPECT_NE(rig.find("<visual name=\"pole\">"), std::string::npos);
  EXPECT_EQ(text.find("<population"), std::string::npos);
  EXPECT_EQ(text.find("inline_fixed"), std::string::npos);
  // The XML reader accepts it.
  const detail::XmlDocument doc = detail::ParseXml(text, "constellation.world");
  EXPECT_EQ(doc.root.Child("world")->Children("population").size(), 0u);
  EXPECT_EQ(doc.root.Child("world")->Children("include").size(), 4u);  // block + 3 cameras
}

TEST(GazeboExport, ReloadingGivesTheChosenCandidatesBack) {
  // Without random roll, vantage's re-orientation of explicit sensors (look-at from the same
  // position) gives the exported cameras their exact poses back.
  const std::string path = World("export.world");
  const Problem problem = Load(path);
  const std::vector<Candidate> chosen = Pick(Deploy(problem, false), kChosen);
  test::TempDir dir;
  test::WriteText(dir.File("constellation.world"),
                  ConstellationWorld(path, chosen, problem.populations, problem.sensors));

  LoadOptions options;
  options.model_paths = {World("models")};
  const Problem reloaded = Load(dir.File("constellation.world"), options);
  EXPECT_TRUE(reloaded.populations.empty());
  ASSERT_TRUE(reloaded.expected_candidates.has_value());
  EXPECT_EQ(*reloaded.expected_candidates, 4);
  std::set<std::string> sensors;
  for (const ExplicitSensor& s : reloaded.sensors) sensors.insert(s.name);
  EXPECT_EQ(sensors, kExportedSensors);
  const std::vector<Candidate> again = Deploy(reloaded, false);
  ASSERT_EQ(again.size(), chosen.size());
  for (const Candidate& original : chosen) {
    const std::string name = original.name == "rig::wrist" ? "rig__wrist" : original.name;
    const auto it = std::find_if(again.begin(), again.end(),
                                 [&](const Candidate& c) { return c.name == name; });
    ASSERT_NE(it, again.end()) << name;
    ExpectPose(it->world_from_body, original.world_from_body, kTol, name);
    EXPECT_EQ(it->sensor.width, original.sensor.width) << name;
    EXPECT_EQ(it->sensor.fx, original.sensor.fx) << name;
  }
  // The same scene: every object, with its triangles, in the same place.
  ASSERT_EQ(reloaded.scene.objects.size(), problem.scene.objects.size());
  for (size_t i = 0; i < problem.scene.objects.size(); ++i) {
    const SceneObject& a = problem.scene.objects[i];
    const SceneObject& b = reloaded.scene.objects[i];
    EXPECT_EQ(a.name, b.name);
    EXPECT_EQ(a.role, b.role);
    EXPECT_EQ(a.mesh.vertices, b.mesh.vertices) << a.name;
  }

  // With random roll, only the roll differs: same model positions and viewing directions.
  const std::vector<Candidate> rolled = Pick(Deploy(problem, true), kChosen);
  test::WriteText(dir.File("rolled.world"),
                  ConstellationWorld(path, rolled, problem.populations, problem.sensors));
  const Problem rolled_back = Load(dir.File("rolled.world"), options);
  for (const ExplicitSensor& sensor : rolled_back.sensors) {
    const auto original = std::find_if(rolled.begin(), rolled.end(), [&](const Candidate& c) {
      return (c.name == "rig::wrist" ? "rig__wrist" : c.name) == sensor.name;
    });
    ASSERT_NE(original, rolled.end()) << sensor.name;
    const Pose world_from_model = original->world_from_body * sensor.model_from_camera.Inverse();
    EXPECT_LT((sensor.pose.position - world_from_model.position).norm(), kTol) << sensor.name;
    const Vec3 look = LookAt(sensor.pose.position, problem.observation_point) * Vec3::UnitX();
    EXPECT_LT((look - world_from_model.rotation * Vec3::UnitX()).norm(), kTol) << sensor.name;
  }
}

TEST(GazeboExport, ACandidateOfNoPopulationOrSensorIsAnError) {
  const std::string path = World("export.world");
  const Problem problem = Load(path);
  std::vector<Candidate> chosen = Pick(Deploy(problem, false), {"box_random_0"});
  chosen[0].population = "nowhere";
  EXPECT_THROW(ConstellationWorld(path, chosen, problem.populations, problem.sensors), InputError);
  chosen[0].population.clear();
  EXPECT_THROW(ConstellationWorld(path, chosen, problem.populations, problem.sensors), InputError);
  EXPECT_TRUE(IsGazeboWorldPath("a/b.WORLD"));
  EXPECT_TRUE(IsGazeboWorldPath("b.sdf"));
  EXPECT_FALSE(IsGazeboWorldPath("b.yaml"));
}

TEST(GazeboXml, ByteOffsetsCoverExactlyEachElement) {
  // What the export cuts and copies: the '<' of the start tag to the last '>', and the content.
  const std::string text =
      "\xEF\xBB\xBF<?xml version=\"1.0\"?>\n<!-- c -->\n<a>\n  <b x='1>'>t<!-- > --></b><c/>\n"
      "  <d><![CDATA[<e>]]></d >\n</a>\n";
  const detail::XmlDocument doc = detail::ParseXml(text, "t.xml");
  const auto slice = [&](size_t begin, size_t end) { return text.substr(begin, end - begin); };
  const detail::XmlElement& a = doc.root;
  EXPECT_EQ(slice(a.begin, a.end),
            text.substr(text.find("<a>"), text.rfind("</a>") + 4 - text.find("<a>")));
  ASSERT_EQ(a.children.size(), 3u);
  const detail::XmlElement& b = a.children[0];
  EXPECT_EQ(slice(b.begin, b.end), "<b x='1>'>t<!-- > --></b>");
  EXPECT_EQ(slice(b.content_begin, b.end), "t<!-- > --></b>");
  const detail::XmlElement& c = a.children[1];
  EXPECT_EQ(slice(c.begin, c.end), "<c/>");
  EXPECT_EQ(c.content_begin, c.end);
  const detail::XmlElement& d = a.children[2];
  EXPECT_EQ(slice(d.begin, d.end), "<d><![CDATA[<e>]]></d >");
}

// ---------------------------------------------------------------------------------------------
// The CLI on the shared worlds (ctest label `integration`).

TEST(GazeboExportCli, OptimizeAWorldWithNoOptionRunsThePluginsExperiment) {
  const std::string costa = test::Costa2017Dir();
  const std::string world = costa + "/worlds/bin_picking.world";
  // GAZEBO.md: the model path from GAZEBO_MODEL_PATH (the costa2017 layout needs it or the flag).
  SetEnv("GAZEBO_MODEL_PATH", costa + "/media/models");
  SetEnv("GAZEBO_RESOURCE_PATH", costa + "/media");
  test::TempDir dir;
  const auto run =
      test::RunVantage("-q optimize " + world + " --method greedy --out " + dir.File("out"));
  UnsetEnv("GAZEBO_MODEL_PATH");
  UnsetEnv("GAZEBO_RESOURCE_PATH");
  ASSERT_EQ(run.exit_code, 0) << run.err;
  const nlohmann::json report = nlohmann::json::parse(test::ReadText(dir.File("out/report.json")));
  // The plugin's parameters: N = 1, F = 0.005, 100 sampling sensors.
  EXPECT_EQ(report["cell_size"].get<double>(), 0.005);
  EXPECT_EQ(report["candidates"].size(), 100u);
  ASSERT_EQ(report["results"].size(), 1u);
  EXPECT_EQ(report["results"][0]["n"].get<int>(), 1);
  EXPECT_TRUE(std::filesystem::exists(dir.File("out/constellation.world")));
}

/// The model frames of export.world's `box_random` clones in a report: test_camera's camera sits
/// at (0.01, 0, 0.02), yaw 90°, in its model (tests/data/worlds/models/test_camera).
std::vector<Pose> BoxRandomModels(const nlohmann::json& report) {
  const Pose model_from_camera{Vec3(0.01, 0, 0.02),
                               Quat(Eigen::AngleAxisd(std::numbers::pi / 2, Vec3::UnitZ()))};
  std::vector<Pose> models;
  for (const auto& c : report["candidates"]) {
    if (c["name"].get<std::string>().rfind("box_random_", 0) != 0) continue;
    const auto& p = c["position"];
    const auto& q = c["quaternion"];
    const Pose world_from_camera{
        Vec3(p[0].get<double>(), p[1].get<double>(), p[2].get<double>()),
        Quat(q[0].get<double>(), q[1].get<double>(), q[2].get<double>(), q[3].get<double>())};
    models.push_back(world_from_camera * model_from_camera.Inverse());
  }
  return models;
}

TEST(GazeboExportCli, CommandLineOverridesThePluginsParameters) {
  // export.world's models are in models/ beside it: no option is needed at all.
  test::TempDir dir;
  const std::string world = World("export.world");
  UnsetEnv("GAZEBO_MODEL_PATH");
  const auto plain =
      test::RunVantage("-q optimize " + world + " --method greedy --out " + dir.File("plain"));
  ASSERT_EQ(plain.exit_code, 0) << plain.err;
  const auto same = test::RunVantage("-q optimize " + world +
                                     " --method greedy -n 3 "
                                     "--cell-size 0.005 --observation-point 0 0 0.1 "
                                     "--random-roll true --out " +
                                     dir.File("same"));
  ASSERT_EQ(same.exit_code, 0) << same.err;
  const auto other = test::RunVantage("-q optimize " + world +
                                      " --method greedy -n 2 "
                                      "--cell-size 0.01 --observation-point 0 0 0.2 "
                                      "--random-roll false --out " +
                                      dir.File("other"));
  ASSERT_EQ(other.exit_code, 0) << other.err;
  const auto read = [&](const std::string& name) {
    nlohmann::json report = nlohmann::json::parse(test::ReadText(dir.File(name + "/report.json")));
    report.erase("timings");
    for (auto& r : report["results"]) r.erase("seconds");
    return report;
  };
  const nlohmann::json a = read("plain");
  const nlohmann::json b = read("same");
  const nlohmann::json c = read("other");
  // The plugin's values: N = 3, the observation point (0, 0, 0.1), random roll on.
  EXPECT_EQ(a["results"][0]["n"].get<int>(), 3);
  EXPECT_EQ(a["cell_size"].get<double>(), 0.005);
  EXPECT_EQ(a["candidates"], b["candidates"]);
  EXPECT_EQ(a["results"], b["results"]);
  // Overridden: N = 2, F = 0.01, every model looking at (0, 0, 0.2) with roll 0.
  EXPECT_EQ(c["results"][0]["n"].get<int>(), 2);
  EXPECT_EQ(c["cell_size"].get<double>(), 0.01);
  const std::vector<Pose> rolled = BoxRandomModels(a);
  const std::vector<Pose> level = BoxRandomModels(c);
  ASSERT_EQ(rolled.size(), 6u);
  ASSERT_EQ(level.size(), 6u);
  double max_tilt = 0;
  for (const Pose& model : rolled) {
    const Vec3 look = (Vec3(0, 0, 0.1) - model.position).normalized();
    EXPECT_LT((model.rotation * Vec3::UnitX() - look).norm(), 1e-9);
    max_tilt = std::max(max_tilt, std::abs((model.rotation * Vec3::UnitY()).z()));
  }
  EXPECT_GT(max_tilt, 0.1);  // random roll tilts the left axis
  for (const Pose& model : level) {
    const Vec3 look = (Vec3(0, 0, 0.2) - model.position).normalized();
    EXPECT_LT((model.rotation * Vec3::UnitX() - look).norm(), 1e-9);
    EXPECT_LT(std::abs((model.rotation * Vec3::UnitY()).z()), 1e-9);  // roll 0: left is level
  }
}

TEST(GazeboExportCli, OptimizeWritesAConstellationWorldThatSdformatLoads) {
  const std::string costa = test::Costa2017Dir();
  const std::string world = costa + "/worlds/bin_picking.world";
  const std::string models = costa + "/media/models";
  test::TempDir dir;
  const auto run =
      test::RunVantage("-q optimize " + world + " --model-path " + models + " --resource-path " +
                       costa + "/media" + " -n 3 --method greedy --out " + dir.File("out"));
  ASSERT_EQ(run.exit_code, 0) << run.err;
  const nlohmann::json report = nlohmann::json::parse(test::ReadText(dir.File("out/report.json")));
  ASSERT_EQ(report["results"].size(), 1u);
  std::set<std::string> chosen;
  for (const auto& name : report["results"][0]["sensors"]) chosen.insert(name.get<std::string>());
  ASSERT_EQ(chosen.size(), 3u);

  const std::string exported = dir.File("out/constellation.world");
  const SdfWorld sdf = LoadWithSdformat(exported, models);
  for (const std::string& error : sdf.errors)  // model://sun is not in the shared models
    EXPECT_NE(error.find("model://sun"), std::string::npos) << error;
  EXPECT_TRUE(sdf.populations.empty());
  std::set<std::string> expected = chosen;
  expected.insert(
      {"tool_trolley", "stacking_box", "alternator", "differential_gearbox", "starter_motor"});
  EXPECT_EQ(sdf.models, expected);
  EXPECT_EQ(sdf.cameras.size(), 3u);
  // Each camera where report.json puts it (JSON numbers round-trip).
  for (const auto& c : report["candidates"]) {
    const std::string name = c["name"];
    if (!chosen.count(name)) continue;
    const auto& p = c["position"];
    const auto& q = c["quaternion"];
    const Pose expected_pose{
        Vec3(p[0].get<double>(), p[1].get<double>(), p[2].get<double>()),
        Quat(q[0].get<double>(), q[1].get<double>(), q[2].get<double>(), q[3].get<double>())};
    ASSERT_TRUE(sdf.cameras.count(name)) << name;
    ExpectPose(sdf.cameras.at(name), expected_pose, 1e-9, name);
  }

  // vantage reads it back: the same scene, the three sensors, no population.
  LoadOptions options;
  options.model_paths = {models};
  options.resource_paths = {costa + "/media"};
  const Problem original = Load(world, options);
  const Problem reloaded = Load(exported, options);
  EXPECT_TRUE(reloaded.populations.empty());
  std::set<std::string> sensors;
  for (const ExplicitSensor& s : reloaded.sensors) sensors.insert(s.name);
  EXPECT_EQ(sensors, chosen);
  ASSERT_EQ(reloaded.scene.objects.size(), original.scene.objects.size());
  for (size_t i = 0; i < original.scene.objects.size(); ++i) {
    EXPECT_EQ(reloaded.scene.objects[i].name, original.scene.objects[i].name);
    EXPECT_EQ(reloaded.scene.objects[i].mesh.triangles.size(),
              original.scene.objects[i].mesh.triangles.size());
  }
}

// Bug of issue 13: `vantage render OUT` of a Gazebo run failed unless --model-path and
// --resource-path were given again. The run's folder now carries them (report.json `inputs`): the
// picture is made from the folder alone and re-observes the
// report's own coverage.
TEST(GazeboExportCli, RenderReproducesAGazeboRunFromItsFolderAlone) {
  const std::string costa = test::Costa2017Dir();
  test::TempDir dir;
  const auto run = test::RunVantage(
      "-q optimize " + costa + "/worlds/bin_picking.world --model-path " + costa +
      "/media/models --resource-path " + costa + "/media -n 1 --method best --out " +
      dir.File("out"));
  ASSERT_EQ(run.exit_code, 0) << run.err;
  const nlohmann::json report = nlohmann::json::parse(test::ReadText(dir.File("out/report.json")));
  ASSERT_EQ(report["inputs"]["model_paths"].size(), 1u);
  const auto render = test::RunVantage("render " + dir.File("out") + " --png " +
                                       dir.File("view.png") + " --width 160 --height 120");
  ASSERT_EQ(render.exit_code, 0) << render.err;
  EXPECT_TRUE(std::filesystem::exists(dir.File("view.png")));
  EXPECT_EQ(render.err.find("coverage"), std::string::npos) << render.err;  // no "changed" warning
  const double coverage = report["results"][0]["coverage"].get<double>();
  EXPECT_NE(render.out.find(fmt::format("coverage {:.2f} %", 100.0 * coverage)), std::string::npos)
      << render.out;
}

// Issue 19: a YAML scene's run writes constellation.sdf too — its objects as SDF shapes. Checked
// against the scene file's own numbers (typed here from examples/scenes/bin_picking_cell.yaml),
// through libsdformat's pose resolution, and by vantage's Gazebo reader: evaluating the exported
// world scores the chosen cameras exactly as the run did.
TEST(GazeboExportCli, YamlSceneRunWritesAGzWorldOfItsObjectsAndCameras) {
  const std::string scene = std::string(VANTAGE_SOURCE_DIR) + "/examples/scenes/bin_picking_cell.yaml";
  test::TempDir dir;
  const auto run = test::RunVantage("-q optimize " + scene + " -n 3 --method greedy --out " +
                                    dir.File("out"));
  ASSERT_EQ(run.exit_code, 0) << run.err;
  const std::string exported = dir.File("out/constellation.sdf");
  const nlohmann::json report = nlohmann::json::parse(test::ReadText(dir.File("out/report.json")));

  sdf::Console::Instance()->SetQuiet(true);
  sdf::Root root;
  const sdf::Errors errors = root.Load(exported);
  for (const sdf::Error& e : errors) ADD_FAILURE() << e.Message();
  ASSERT_EQ(root.WorldCount(), 1u);
  const sdf::World* world = root.WorldByIndex(0);
  std::map<const sdf::Visual*, const sdf::Model*> model_of;
  const auto visual_of = [&](const std::string& name) -> const sdf::Visual* {
    const sdf::Model* model = world->ModelByName(name);
    if (!model || model->LinkCount() != 1 || model->LinkByIndex(0)->VisualCount() != 1)
      return nullptr;
    model_of[model->LinkByIndex(0)->VisualByIndex(0)] = model;
    return model->LinkByIndex(0)->VisualByIndex(0);
  };
  // world_from_model · model_from_visual, as libsdformat resolves them.
  const auto world_pose = [&](const sdf::Visual* visual) {
    ignition::math::Pose3d world_from_model, model_from_visual;
    EXPECT_TRUE(model_of.at(visual)->SemanticPose().Resolve(world_from_model, "world").empty());
    EXPECT_TRUE(visual->SemanticPose().Resolve(model_from_visual, "__model__").empty());
    return FromIgnition(world_from_model) * FromIgnition(model_from_visual);
  };
  // The table: a box of 1.2 x 0.8 x 0.04 m at z = 0.72.
  const sdf::Visual* table = visual_of("table");
  ASSERT_NE(table, nullptr);
  ASSERT_NE(table->Geom()->BoxShape(), nullptr);
  EXPECT_EQ(table->Geom()->BoxShape()->Size(), ignition::math::Vector3d(1.2, 0.8, 0.04));
  ExpectPose(world_pose(table), Pose{Vec3(0, 0, 0.72), Quat::Identity()}, 1e-12, "table");
  // The pipe: a cylinder of r 0.02, l 0.25, turned by 1.5707963 rad about y.
  const sdf::Visual* pipe = visual_of("pipe");
  ASSERT_NE(pipe, nullptr);
  ASSERT_NE(pipe->Geom()->CylinderShape(), nullptr);
  EXPECT_DOUBLE_EQ(pipe->Geom()->CylinderShape()->Radius(), 0.02);
  EXPECT_DOUBLE_EQ(pipe->Geom()->CylinderShape()->Length(), 0.25);
  // (Pitch 1.5707963 is 3e-8 from gimbal lock: the roll-pitch-yaw text holds it to ~1e-9 rad.)
  ExpectPose(world_pose(pipe),
             Pose{Vec3(0, -0.045, 0.77), Quat(Eigen::AngleAxisd(1.5707963, Vec3::UnitY()))},
             kTol, "pipe");
  // The floor: a 4 x 4 m plane; the motor: the mesh file by its absolute path.
  const sdf::Visual* floor = visual_of("floor");
  ASSERT_NE(floor, nullptr);
  ASSERT_NE(floor->Geom()->PlaneShape(), nullptr);
  EXPECT_EQ(floor->Geom()->PlaneShape()->Size(), ignition::math::Vector2d(4, 4));
  const sdf::Visual* motor = visual_of("motor");
  ASSERT_NE(motor, nullptr);
  ASSERT_NE(motor->Geom()->MeshShape(), nullptr);
  EXPECT_EQ(std::filesystem::path(motor->Geom()->MeshShape()->Uri()),
            std::filesystem::weakly_canonical(std::string(VANTAGE_SOURCE_DIR) + "/examples/meshes/small_motor.obj"));
  EXPECT_EQ(world->ModelCount(), 10u + 3u);  // 10 objects, 3 cameras

  // Read back by vantage's Gazebo reader: the cameras keep their poses and intrinsics (no
  // plugin: a real layout), so the layout scores what the run's result scored.
  const auto evaluated = test::RunVantage("-q evaluate " + exported + " --target motor --out " +
                                          dir.File("again"));
  ASSERT_EQ(evaluated.exit_code, 0) << evaluated.err;
  const nlohmann::json again =
      nlohmann::json::parse(test::ReadText(dir.File("again/report.json")));
  EXPECT_EQ(again["reference_voxels"], report["reference_voxels"]);
  EXPECT_DOUBLE_EQ(again["results"][0]["coverage"].get<double>(),
                   report["results"][0]["coverage"].get<double>());
  // evaluate writes the constellation files of what it scored, too.
  EXPECT_TRUE(std::filesystem::exists(dir.File("again/constellation.sdf")));
  EXPECT_TRUE(std::filesystem::exists(dir.File("again/constellation.world")));
}

}  // namespace
}  // namespace vantage
