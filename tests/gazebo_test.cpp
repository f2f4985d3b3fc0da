// Gazebo world loader (GAZEBO.md): the shared costa2017 worlds, hand-made worlds whose poses are
// worked out by hand here, libsdformat's DOM as an independent reference for world poses, and
// bad worlds that must fail with "file:line:".
//
// sdformat's headers pull in <regex>, whose inlined code GCC 12 flags as maybe-uninitialized
// under -fsanitize=address (a false positive in libstdc++): silenced for this file only.
#if defined(__GNUC__) && !defined(__clang__)
#pragma GCC diagnostic ignored "-Wmaybe-uninitialized"
#endif
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <map>
#include <numbers>
#include <sdf/sdf.hh>
#include <set>
#include <string>
#include <vector>

#include "scene/sdf/materials.hpp"
#include "scene/sdf/world.hpp"
#include "test_util.hpp"
#include "util/xml.hpp"
#include "vantage/error.hpp"
#include "vantage/pipeline.hpp"
#include "vantage/problem.hpp"

namespace vantage {
namespace {

using detail::GazeboVisual;
constexpr double kPi = std::numbers::pi;
constexpr double kTol = 1e-9;

// The tests run on one thread: changing the environment is safe here.
void SetEnv(const char* name, const std::string& value) {
  ::setenv(name, value.c_str(), 1);  // NOLINT(concurrency-mt-unsafe)
}
void UnsetEnv(const char* name) {
  ::unsetenv(name);  // NOLINT(concurrency-mt-unsafe)
}

/// The loader with a clean environment (GAZEBO_MODEL_PATH / GAZEBO_RESOURCE_PATH unset), so that
/// only the options and the models/ folder beside the world count.
Problem Load(const std::string& path,
             const LoadOptions& options = {},
             std::vector<GazeboVisual>* visuals = nullptr) {
  UnsetEnv("GAZEBO_MODEL_PATH");
  UnsetEnv("GAZEBO_RESOURCE_PATH");
  return detail::LoadGazeboWorld(path, options, visuals);
}

std::string World(const std::string& name) { return test::DataPath("worlds/" + name); }

/// A copy of the test world `name` with `from` replaced by `to` (it must occur), written to `as`.
std::string EditedWorld(const std::string& name,
                        const std::string& from,
                        const std::string& to,
                        const std::string& as) {
  std::string text = test::ReadText(World(name));
  const size_t at = text.find(from);
  EXPECT_NE(at, std::string::npos) << from;
  if (at != std::string::npos) text.replace(at, from.size(), to);
  test::WriteText(as, text);
  return as;
}

/// The options that find the test worlds' included models.
LoadOptions TestModels() {
  LoadOptions options;
  options.model_paths = {World("models")};
  return options;
}

LoadOptions CostaOptions() {
  LoadOptions options;
  options.model_paths = {test::Costa2017Dir() + "/media/models"};
  options.resource_paths = {test::Costa2017Dir() + "/media"};
  return options;
}

const SceneObject* FindObject(const Problem& problem, const std::string& name) {
  for (const SceneObject& object : problem.scene.objects)
    if (object.name == name) return &object;
  return nullptr;
}

const GazeboVisual* FindVisual(const std::vector<GazeboVisual>& visuals,
                               const std::string& model,
                               const std::string& link,
                               const std::string& name) {
  for (const GazeboVisual& v : visuals)
    if (v.model == model && v.link == link && v.name == name) return &v;
  return nullptr;
}

std::set<std::string> Names(const Problem& problem, Role role) {
  std::set<std::string> names;
  for (const SceneObject& object : problem.scene.objects)
    if (object.role == role) names.insert(object.name);
  return names;
}

bool HasNote(const Problem& problem, const std::string& fragment) {
  return std::any_of(problem.notes.begin(), problem.notes.end(),
                     [&](const std::string& n) { return n.find(fragment) != std::string::npos; });
}

void ExpectBounds(const SceneObject* object, const Vec3& min, const Vec3& max, double tol = 1e-9) {
  ASSERT_NE(object, nullptr);
  const Aabb bounds = object->mesh.Bounds();
  for (int i = 0; i < 3; ++i) {
    EXPECT_NEAR(bounds.min[i], min[i], tol) << object->name << " min[" << i << "]";
    EXPECT_NEAR(bounds.max[i], max[i], tol) << object->name << " max[" << i << "]";
  }
}

void ExpectVec(const Vec3& actual, const Vec3& expected, double tol = kTol) {
  for (int i = 0; i < 3; ++i) EXPECT_NEAR(actual[i], expected[i], tol) << "component " << i;
}

/// Angle between two rotations [rad].
double AngleBetween(const Quat& a, const Quat& b) { return a.angularDistance(b); }

Quat Rz(double yaw) { return Quat(Eigen::AngleAxisd(yaw, Vec3::UnitZ())); }

/// Loads a world that must fail; returns the message.
std::string LoadError(const std::string& path, const LoadOptions& options = {}) {
  try {
    Load(path, options);
  } catch (const InputError& e) {
    return e.what();
  }
  ADD_FAILURE() << path << " loaded without an InputError";
  return "";
}

/// The message's first line starts with "path:line:" and the message names `fragment`.
void ExpectErrorAt(const std::string& message,
                   const std::string& path,
                   int line,
                   const std::string& fragment) {
  const std::string prefix = path + ":" + std::to_string(line) + ":";
  EXPECT_EQ(message.rfind(prefix, 0), 0u) << "expected prefix " << prefix << " in:\n" << message;
  EXPECT_NE(message.find(fragment), std::string::npos) << "expected '" << fragment << "' in:\n"
                                                       << message;
}

// ---------------------------------------------------------------------------------------------
// The shared worlds of the original system.

TEST(Gazebo, BinPickingWorld) {
  const std::string path = test::Costa2017Dir() + "/worlds/bin_picking.world";
  const Problem problem = Load(path, CostaOptions());
  EXPECT_EQ(problem.source, path);

  // Plugin parameters as the world writes them.
  EXPECT_EQ(problem.selection.n, 1);
  EXPECT_EQ(problem.selection.ransac_iterations, 1000);
  EXPECT_DOUBLE_EQ(problem.selection.ransac_stop_coverage, 0.9);
  EXPECT_DOUBLE_EQ(problem.cell_size, 0.005);
  EXPECT_TRUE(problem.random_roll);
  ExpectVec(problem.observation_point, Vec3::Zero());
  ASSERT_TRUE(problem.expected_candidates.has_value());
  EXPECT_EQ(*problem.expected_candidates, 100);

  // Scene: one target, the README's occluders; no sensor bodies; the sun skipped with a note.
  EXPECT_EQ(Names(problem, Role::kTarget), std::set<std::string>{"starter_motor"});
  EXPECT_EQ(Names(problem, Role::kOccluder),
            (std::set<std::string>{"tool_trolley", "stacking_box", "alternator",
                                   "differential_gearbox"}));
  EXPECT_EQ(problem.scene.TargetCount(), 1u);
  EXPECT_GT(FindObject(problem, "starter_motor")->mesh.triangles.size(), 100u);
  EXPECT_TRUE(HasNote(problem, "model://sun"));

  // The alternator: a 0.1816 x 0.118 x 0.1555 box, visual 0.07775 up, include at
  // (0.090696, 0.054119, 0), no rotation.
  ExpectBounds(FindObject(problem, "alternator"), Vec3(0.090696 - 0.0908, 0.054119 - 0.059, 0.0),
               Vec3(0.090696 + 0.0908, 0.054119 + 0.059, 0.1555), 1e-12);
  // The trolley: 0.8794 x 0.5004 trays turned by yaw 1.5707 (≈ 90°), floor at z = -0.81, top
  // tray 0.78..0.80 above it; the legs (±0.4247 ± 0.015, ±0.2352 ± 0.015) stay inside.
  ExpectBounds(FindObject(problem, "tool_trolley"), Vec3(-0.2502, -0.4397, -0.81),
               Vec3(0.2502, 0.4397, -0.01), 1e-3);

  // Populations: 60 SR300 in a box, 20 MultiSense S7 uniform in a cylinder, 20 Kinect 360.
  ASSERT_EQ(problem.populations.size(), 3u);
  const Population& p1 = problem.populations[0];
  EXPECT_EQ(p1.name, "sensors_population_1");
  EXPECT_EQ(p1.sensor_type, "intel_realsense_sr300_sensor");
  EXPECT_EQ(p1.region, RegionShape::kBox);
  ExpectVec(p1.box_size, Vec3(0.55, 0.45, 0.2));
  ExpectVec(p1.pose.position, Vec3(0, 0, 0.4));
  EXPECT_EQ(p1.count, 60);
  EXPECT_EQ(p1.distribution, Distribution::kRandom);
  EXPECT_EQ(p1.file, path);
  EXPECT_EQ(p1.line, 41);
  // SR300: no link or sensor pose, so the camera is the model frame (the model's own
  // <pose>0 0 0.0327</pose> is replaced by the clone's position).
  ExpectVec(p1.model_from_camera.position, Vec3::Zero());
  EXPECT_NEAR(AngleBetween(p1.model_from_camera.rotation, Quat::Identity()), 0, kTol);

  const Population& p2 = problem.populations[1];
  EXPECT_EQ(p2.sensor_type, "multisense_s7_sensor");
  EXPECT_EQ(p2.region, RegionShape::kCylinder);
  EXPECT_DOUBLE_EQ(p2.radius, 0.35);
  EXPECT_DOUBLE_EQ(p2.length, 0.1);
  EXPECT_EQ(p2.distribution, Distribution::kUniform);
  EXPECT_EQ(p2.count, 20);
  const Population& p3 = problem.populations[2];
  EXPECT_EQ(p3.sensor_type, "kinect_xbox_360_sensor");
  EXPECT_EQ(p3.distribution, Distribution::kRandom);
  EXPECT_EQ(p3.count, 20);
  EXPECT_EQ(p1.count + p2.count + p3.count, *problem.expected_candidates);
  EXPECT_TRUE(problem.sensors.empty());

  // Sensor types, Gazebo's pinhole model: fx = fy = W / (2 tan(hfov / 2)), centre W/2, H/2.
  ASSERT_EQ(problem.sensor_types.size(), 3u);
  const SensorType* sr300 = nullptr;
  for (const SensorType& t : problem.sensor_types)
    if (t.id == "intel_realsense_sr300_sensor") sr300 = &t;
  ASSERT_NE(sr300, nullptr);
  EXPECT_EQ(sr300->width, 640);
  EXPECT_EQ(sr300->height, 480);
  EXPECT_NEAR(sr300->fx, 320.0 / std::tan(0.623955), 1e-9);
  EXPECT_NEAR(sr300->fy, 320.0 / std::tan(0.623955), 1e-9);
  EXPECT_DOUBLE_EQ(sr300->cx, 320.0);
  EXPECT_DOUBLE_EQ(sr300->cy, 240.0);
  EXPECT_DOUBLE_EQ(sr300->near, 0.2);
  EXPECT_DOUBLE_EQ(sr300->far, 1.5);
  EXPECT_DOUBLE_EQ(sr300->fps, 60.0);
  const SensorType& s7 = problem.sensor_types[1];
  EXPECT_EQ(s7.id, "multisense_s7_sensor");
  EXPECT_EQ(s7.width, 2048);
  EXPECT_EQ(s7.height, 1088);
  EXPECT_NEAR(s7.fx, 1024.0 / std::tan(1.39626 / 2), 1e-9);
  EXPECT_DOUBLE_EQ(s7.near, 0.4);
  EXPECT_DOUBLE_EQ(s7.far, 5.0);
  const SensorType& kinect = problem.sensor_types[2];
  EXPECT_EQ(kinect.id, "kinect_xbox_360_sensor");
  EXPECT_NEAR(kinect.fx, 320.0 / std::tan(0.994838 / 2), 1e-9);
  EXPECT_DOUBLE_EQ(kinect.far, 4.0);
}

TEST(Gazebo, BinPickingWithOcclusionsWorld) {
  const std::string path = test::Costa2017Dir() + "/worlds/bin_picking_with_occlusions.world";
  const Problem problem = Load(path, CostaOptions());
  EXPECT_EQ(problem.selection.n, 3);
  EXPECT_EQ(problem.selection.ransac_iterations, 1000);
  EXPECT_DOUBLE_EQ(problem.selection.ransac_stop_coverage, 0.9);
  EXPECT_DOUBLE_EQ(problem.cell_size, 0.005);
  EXPECT_TRUE(problem.random_roll);
  EXPECT_EQ(Names(problem, Role::kTarget), std::set<std::string>{"starter_motor"});
  EXPECT_EQ(Names(problem, Role::kOccluder),
            (std::set<std::string>{"tool_trolley", "stacking_box", "alternator",
                                   "differential_gearbox_1", "differential_gearbox_2",
                                   "differential_gearbox_3", "differential_gearbox_4"}));
  ASSERT_EQ(problem.populations.size(), 3u);
  EXPECT_EQ(problem.populations[0].count, 200);
  EXPECT_EQ(problem.populations[1].count, 20);
  EXPECT_EQ(problem.populations[1].distribution, Distribution::kRandom);
  EXPECT_EQ(problem.populations[2].count, 80);
  ExpectVec(problem.populations[0].pose.position, Vec3(0, 0, 0.5));
  ExpectVec(problem.populations[1].pose.position, Vec3(0, 0, 0.65));
  ASSERT_TRUE(problem.expected_candidates.has_value());
  EXPECT_EQ(*problem.expected_candidates, 300);
  EXPECT_EQ(
      problem.populations[0].count + problem.populations[1].count + problem.populations[2].count,
      300);
  // The first gearbox: its include pose replaces the model's own <pose>0 0 0.047</pose>, so the
  // 0.094 m high box (visual at the model origin) is centred at z = 0.047.
  const Aabb gearbox = FindObject(problem, "differential_gearbox_1")->mesh.Bounds();
  EXPECT_NEAR(0.5 * (gearbox.min.z() + gearbox.max.z()), 0.047, 1e-12);
  EXPECT_NEAR(gearbox.max.z() - gearbox.min.z(), 0.094, 1e-12);
}

// ---------------------------------------------------------------------------------------------
// Pose composition, by hand.

TEST(Gazebo, PoseComposition) {
  std::vector<GazeboVisual> visuals;
  const Problem problem = Load(World("poses.world"), {}, &visuals);

  // outer = T(1,0,0)·Rz(90°); inner = outer·T(1,0,0) → origin (1, 1, 0); visual 1 m up.
  // The 0.2 x 0.4 x 0.6 box turned 90° spans 0.4 in x and 0.2 in y.
  const GazeboVisual* nested = FindVisual(visuals, "outer::inner", "link", "box");
  ASSERT_NE(nested, nullptr);
  ExpectVec(nested->world_from_visual.position, Vec3(1, 1, 1));
  EXPECT_NEAR(AngleBetween(nested->world_from_visual.rotation, Rz(kPi / 2)), 0, kTol);
  ExpectBounds(FindObject(problem, "outer::inner"), Vec3(0.8, 0.9, 0.7), Vec3(1.2, 1.1, 1.3));

  // tilted: model (0,-3,0), link (0,0,2) pitched 90°: Ry(90°) sends the visual's x offset to -z.
  const GazeboVisual* tilted = FindVisual(visuals, "tilted", "link", "box");
  ASSERT_NE(tilted, nullptr);
  ExpectVec(tilted->world_from_visual.position, Vec3(0, -3, 1));
  ExpectVec(tilted->world_from_visual.rotation * Vec3::UnitX(), Vec3(0, 0, -1));
  ExpectBounds(FindObject(problem, "tilted"), Vec3(-0.05, -3.05, 0.95), Vec3(0.05, -2.95, 1.05));

  // Includes: block's own pose (5,5,5) is replaced by the include pose (0,2,0); block_b keeps it.
  // The 1 m cube sits 0.5 m above its model origin.
  ExpectBounds(FindObject(problem, "block_a"), Vec3(-0.5, 1.5, 0), Vec3(0.5, 2.5, 1));
  ExpectBounds(FindObject(problem, "block_b"), Vec3(4.5, 4.5, 5), Vec3(5.5, 5.5, 6));

  // Includes nested in holder = T(0,0,3)·Rz(90°): "held" at holder·T(1,0,0) = (0,1,3);
  // "held_own" at holder·T(5,5,5) = (-5,5,8) (its own pose, relative to the holder).
  ExpectBounds(FindObject(problem, "holder::held"), Vec3(-0.5, 0.5, 3), Vec3(0.5, 1.5, 4));
  ExpectBounds(FindObject(problem, "holder::held_own"), Vec3(-5.5, 4.5, 8), Vec3(-4.5, 5.5, 9));
  const GazeboVisual* held = FindVisual(visuals, "holder::held", "link", "cube");
  ASSERT_NE(held, nullptr);
  ExpectVec(held->world_from_visual.position, Vec3(0, 1, 3.5));

  // The triangle (0,0,0), (1,0,0), (0,1,1) scaled by (2,3,4), lifted 1 m.
  const SceneObject* scaled = FindObject(problem, "scaled");
  ASSERT_NE(scaled, nullptr);
  EXPECT_TRUE(scaled->is_target());
  ASSERT_EQ(scaled->mesh.triangles.size(), 1u);
  std::vector<Vec3> corners;
  for (uint32_t index : scaled->mesh.triangles[0]) corners.push_back(scaled->mesh.vertices[index]);
  const std::vector<Vec3> expected = {Vec3(0, 0, 1), Vec3(2, 0, 1), Vec3(0, 3, 5)};
  for (const Vec3& e : expected) {
    EXPECT_TRUE(std::any_of(corners.begin(), corners.end(),
                            [&](const Vec3& c) { return (c - e).norm() < 1e-6; }))
        << "missing corner " << e.transpose();
  }

  // model.config's highest version (1.6: a 2 m cube) at (10, 0, 0).
  ExpectBounds(FindObject(problem, "versions"), Vec3(9, -1, -1), Vec3(11, 1, 1));

  // The light-only model is skipped with a note; only "scaled" is green.
  EXPECT_TRUE(HasNote(problem, "light"));
  EXPECT_EQ(Names(problem, Role::kTarget), std::set<std::string>{"scaled"});
  EXPECT_EQ(problem.scene.objects.size(), 8u);
}

TEST(Gazebo, ArmOf27Links) {
  std::vector<GazeboVisual> visuals;
  const Problem problem = Load(World("arm.world"), {}, &visuals);
  // Chain: link_i = link_{i-1} · T(0.1, 0, 0) · Rz(0.1).
  Vec3 position = Vec3::Zero();
  double yaw = 0;
  for (int i = 0; i < 27; ++i) {
    if (i > 0) {
      position += 0.1 * Vec3(std::cos(yaw), std::sin(yaw), 0);
      yaw += 0.1;
    }
    const GazeboVisual* v = FindVisual(visuals, "arm", "link_" + std::to_string(i), "visual");
    ASSERT_NE(v, nullptr) << i;
    ExpectVec(v->world_from_visual.position, position, 1e-9);
    EXPECT_NEAR(AngleBetween(v->world_from_visual.rotation, Rz(yaw)), 0, 1e-9) << i;
    EXPECT_TRUE(v->is_target);
  }
  // Flat: link_i at (0.1 i, 0, 0) yaw 0.1 i in the model at (0, 1, 0); visual 0.05 m along the
  // link's x.
  for (int i = 0; i < 27; ++i) {
    const GazeboVisual* v = FindVisual(visuals, "arm_flat", "link_" + std::to_string(i), "visual");
    ASSERT_NE(v, nullptr) << i;
    const double a = 0.1 * i;
    ExpectVec(v->world_from_visual.position,
              Vec3(0.1 * i + 0.05 * std::cos(a), 1 + 0.05 * std::sin(a), 0), 1e-9);
    EXPECT_FALSE(v->is_target);
  }
  EXPECT_EQ(Names(problem, Role::kTarget), std::set<std::string>{"arm"});
  EXPECT_EQ(Names(problem, Role::kOccluder), std::set<std::string>{"arm_flat"});
  EXPECT_EQ(FindObject(problem, "arm")->mesh.triangles.size(), 27u * 12u);
}

// libsdformat's DOM (frame graph, include expansion) as an independent reference: every visual's
// world pose must agree with it. The DOM resolves frames per model scope: world_from_model
// (top level), then "__model__"-relative poses of nested models and visuals.
Pose FromIgnition(const ignition::math::Pose3d& p) {
  return Pose{Vec3(p.Pos().X(), p.Pos().Y(), p.Pos().Z()),
              Quat(p.Rot().W(), p.Rot().X(), p.Rot().Y(), p.Rot().Z())};
}

void CollectDomVisuals(const sdf::Model& model,
                       const Pose& world_from_model,
                       const std::string& scoped,
                       std::map<std::string, Pose>* out) {
  for (uint64_t l = 0; l < model.LinkCount(); ++l) {
    const sdf::Link* link = model.LinkByIndex(l);
    for (uint64_t v = 0; v < link->VisualCount(); ++v) {
      const sdf::Visual* visual = link->VisualByIndex(v);
      ignition::math::Pose3d model_from_visual;
      const sdf::Errors errors = visual->SemanticPose().Resolve(model_from_visual, "__model__");
      EXPECT_TRUE(errors.empty()) << scoped << "/" << link->Name() << "/" << visual->Name() << ": "
                                  << (errors.empty() ? "" : errors[0].Message());
      (*out)[scoped + "/" + link->Name() + "/" + visual->Name()] =
          world_from_model * FromIgnition(model_from_visual);
    }
  }
  for (uint64_t m = 0; m < model.ModelCount(); ++m) {
    const sdf::Model* nested = model.ModelByIndex(m);
    ignition::math::Pose3d model_from_nested;
    const sdf::Errors errors = nested->SemanticPose().Resolve(model_from_nested, "__model__");
    EXPECT_TRUE(errors.empty()) << scoped << "::" << nested->Name();
    CollectDomVisuals(*nested, world_from_model * FromIgnition(model_from_nested),
                      scoped + "::" + nested->Name(), out);
  }
}

void ExpectSameAsSdformat(const std::string& path,
                          const LoadOptions& options,
                          const std::string& model_dir) {
  sdf::Console::Instance()->SetQuiet(true);
  sdf::ParserConfig config;
  config.SetFindCallback([&](const std::string& uri) -> std::string {
    if (uri.rfind("model://", 0) != 0) return "";
    const std::string candidate = model_dir + "/" + uri.substr(8);
    return std::filesystem::exists(candidate) ? candidate : "";
  });
  sdf::Root root;
  root.Load(path, config);  // errors for model://sun are expected; the rest loads
  ASSERT_EQ(root.WorldCount(), 1u);
  const sdf::World* world = root.WorldByIndex(0);
  std::map<std::string, Pose> reference;
  for (uint64_t m = 0; m < world->ModelCount(); ++m) {
    const sdf::Model* model = world->ModelByIndex(m);
    ignition::math::Pose3d world_from_model;
    const sdf::Errors errors = model->SemanticPose().Resolve(world_from_model, "world");
    EXPECT_TRUE(errors.empty()) << model->Name();
    CollectDomVisuals(*model, FromIgnition(world_from_model), model->Name(), &reference);
  }

  std::vector<GazeboVisual> visuals;
  Load(path, options, &visuals);
  ASSERT_FALSE(visuals.empty());
  EXPECT_EQ(visuals.size(), reference.size());
  for (const GazeboVisual& v : visuals) {
    const std::string key = v.model + "/" + v.link + "/" + v.name;
    const auto it = reference.find(key);
    ASSERT_NE(it, reference.end()) << key << " is not in sdformat's DOM";
    ExpectVec(v.world_from_visual.position, it->second.position, 1e-9);
    EXPECT_NEAR(AngleBetween(v.world_from_visual.rotation, it->second.rotation), 0, 1e-9) << key;
  }
}

TEST(Gazebo, PosesAgreeWithSdformat) {
  ExpectSameAsSdformat(World("poses.world"), {}, World("models"));
  ExpectSameAsSdformat(World("arm.world"), {}, World("models"));
  ExpectSameAsSdformat(test::Costa2017Dir() + "/worlds/bin_picking_with_occlusions.world",
                       CostaOptions(), test::Costa2017Dir() + "/media/models");
}

// ---------------------------------------------------------------------------------------------
// Targets.

TEST(Gazebo, TargetsByColour) {
  const Problem problem = Load(World("colours.world"));
  // Emissive where set, else diffuse; inline colours override the script's; ambient never counts.
  EXPECT_EQ(Names(problem, Role::kTarget),
            (std::set<std::string>{"green_script", "glow_green", "inline_diffuse", "mixed"}));
  EXPECT_EQ(Names(problem, Role::kOccluder),
            (std::set<std::string>{"glow_red", "inline_override", "ambient_only", "mixed/occluder",
                                   "unknown_material"}));
  // The mixed model: the green cube is the target, the grey one above it an occluder.
  ExpectBounds(FindObject(problem, "mixed"), Vec3(5.95, -0.05, -0.05), Vec3(6.05, 0.05, 0.05));
  ExpectBounds(FindObject(problem, "mixed/occluder"), Vec3(5.95, -0.05, 0.15),
               Vec3(6.05, 0.05, 0.25));
  // sceneModelPath disagreements are notes, naming the line of <sceneModelPath>.
  const std::string at = World("colours.world") + ":122: ";
  EXPECT_TRUE(HasNote(problem, at + "sceneModelPath lists 'ghost'"));
  EXPECT_TRUE(HasNote(problem, at + "sceneModelPath lists 'glow_red'"));
  EXPECT_TRUE(HasNote(problem, at + "model 'inline_diffuse'"));
  EXPECT_TRUE(HasNote(problem, at + "model 'mixed'"));
  EXPECT_FALSE(HasNote(problem, "'green_script'"));
  EXPECT_TRUE(HasNote(problem, World("colours.world") + ":114: material 'Test/Nope'"));
}

TEST(Gazebo, CommandLineTargetsOverride) {
  LoadOptions options;
  options.targets = {"glow_red", "mixed"};
  const Problem problem = Load(World("colours.world"), options);
  // Exactly those models, all of their visuals; colours no longer count.
  EXPECT_EQ(Names(problem, Role::kTarget), (std::set<std::string>{"glow_red", "mixed"}));
  EXPECT_EQ(FindObject(problem, "mixed")->mesh.triangles.size(), 24u);

  // A nested model by its scoped name, or by its parent.
  options.targets = {"outer::inner"};
  EXPECT_EQ(Names(Load(World("poses.world"), options), Role::kTarget),
            std::set<std::string>{"outer::inner"});
  options.targets = {"holder"};
  EXPECT_EQ(Names(Load(World("poses.world"), options), Role::kTarget),
            (std::set<std::string>{"holder::held", "holder::held_own"}));

  options.targets = {"no_such_model"};
  const std::string message = LoadError(World("colours.world"), options);
  EXPECT_EQ(message.rfind(World("colours.world") + ": --target 'no_such_model'", 0), 0u) << message;
}

/// A green (target) sphere and cylinder with the plugin's leaf size `cell`.
std::string BallAndCanWorld(const std::string& cell) {
  const auto model = [](const std::string& name, const std::string& shape) {
    return "<model name='" + name + "'><link name='link'><visual name='visual'><geometry>" + shape +
           "</geometry><material><diffuse>0 1 0 1</diffuse></material></visual></link>" +
           "</model>\n";
  };
  return "<?xml version='1.0'?>\n<sdf version='1.6'><world name='w'>\n" +
         model("ball", "<sphere><radius>0.05</radius></sphere>") +
         model("can", "<cylinder><radius>0.04</radius><length>0.1</length></cylinder>") +
         "<plugin name='p' filename='libp.so'><voxelGridFilterLeafSize>" + cell +
         "</voxelGridFilterLeafSize></plugin>\n</world></sdf>\n";
}

TEST(Gazebo, CellSizeOptionTessellatesLikeTheLeafSize) {
  // The bug: --cell-size landed after the visuals were tessellated with the plugin's F / 10.
  test::TempDir dir;
  test::WriteText(dir.File("coarse.world"), BallAndCanWorld("0.01"));
  test::WriteText(dir.File("fine.world"), BallAndCanWorld("0.0025"));
  LoadOptions options;
  options.cell_size = 0.0025;
  const Problem overridden = Load(dir.File("coarse.world"), options);
  const Problem fine = Load(dir.File("fine.world"));
  EXPECT_EQ(overridden.cell_size, 0.0025);
  ASSERT_EQ(overridden.scene.objects.size(), 2u);
  EXPECT_EQ(test::SceneDifference(overridden.scene, fine.scene), "");
  // r (1 − cos(π/n)) < F / 10 with r = 0.04, F = 0.0025: π/n < acos(0.99375) = 0.111862 →
  // n > 28.08 → 29 rim vertices on each cap (15 with the file's F = 0.01).
  EXPECT_EQ(test::RimVertices(FindObject(overridden, "can")->mesh, 0.05, 0.04), 29);
  EXPECT_EQ(test::RimVertices(FindObject(Load(dir.File("coarse.world")), "can")->mesh, 0.05, 0.04),
            15);

  // The file's own value is still checked; a bad option is refused at the option.
  test::WriteText(dir.File("negative.world"), BallAndCanWorld("-0.01"));
  ExpectErrorAt(LoadError(dir.File("negative.world"), options), dir.File("negative.world"), 5,
                "<voxelGridFilterLeafSize> -0.01 must be positive");
  options.cell_size = -0.0025;
  EXPECT_EQ(LoadError(dir.File("coarse.world"), options),
            "--cell-size: cell_size = -0.0025 must be a positive length in metres (e.g. 0.005)");
}

// ---------------------------------------------------------------------------------------------
// Sensors.

TEST(Gazebo, PopulationsAndSensors) {
  const std::string path = World("sensors.world");
  const Problem problem = Load(path);

  EXPECT_EQ(problem.selection.n, 2);
  EXPECT_EQ(problem.selection.ransac_iterations, 50);
  EXPECT_DOUBLE_EQ(problem.selection.ransac_stop_coverage, 0.755);
  EXPECT_DOUBLE_EQ(problem.cell_size, 0.01);
  EXPECT_FALSE(problem.random_roll);
  ExpectVec(problem.observation_point, Vec3(0.1, -0.2, 0.3));
  EXPECT_EQ(problem.expected_candidates, 101);

  // The camera model: fx = 100 / (2 tan 0.5), centre (50, 25), 0.1..5 m, 10 Hz; the inline one
  // 64 x 48 with hfov 1.5.
  ASSERT_EQ(problem.sensor_types.size(), 2u);
  const SensorType& camera = problem.sensor_types[0];
  EXPECT_EQ(camera.id, "test_camera");
  EXPECT_EQ(camera.width, 100);
  EXPECT_EQ(camera.height, 50);
  EXPECT_NEAR(camera.fx, 50.0 / std::tan(0.5), 1e-12);
  EXPECT_NEAR(camera.fy, 50.0 / std::tan(0.5), 1e-12);
  EXPECT_DOUBLE_EQ(camera.cx, 50);
  EXPECT_DOUBLE_EQ(camera.cy, 25);
  EXPECT_DOUBLE_EQ(camera.near, 0.1);
  EXPECT_DOUBLE_EQ(camera.far, 5);
  EXPECT_DOUBLE_EQ(camera.fps, 10);
  const SensorType& inline_camera = problem.sensor_types[1];
  EXPECT_EQ(inline_camera.id, "inline_camera");
  EXPECT_NEAR(inline_camera.fx, 32.0 / std::tan(0.75), 1e-12);
  EXPECT_DOUBLE_EQ(inline_camera.near, 0.2);
  EXPECT_DOUBLE_EQ(inline_camera.far, 2);
  EXPECT_DOUBLE_EQ(inline_camera.fps, 30);

  // Camera in the model: link (0.01, 0, 0) · sensor (0, 0, 0.02, yaw 90°); the model's own pose
  // (0, 0, 0.05) is not part of it.
  const auto expect_camera_offset = [](const Pose& model_from_camera) {
    ExpectVec(model_from_camera.position, Vec3(0.01, 0, 0.02));
    ExpectVec(model_from_camera.rotation * Vec3::UnitX(), Vec3(0, 1, 0));
    ExpectVec(model_from_camera.rotation * Vec3::UnitZ(), Vec3(0, 0, 1));
  };

  ASSERT_EQ(problem.populations.size(), 4u);
  const Population& box = problem.populations[0];
  EXPECT_EQ(box.name, "box_random");
  EXPECT_EQ(box.sensor_type, "test_camera");
  EXPECT_EQ(box.region, RegionShape::kBox);
  ExpectVec(box.box_size, Vec3(0.5, 0.4, 0.2));
  ExpectVec(box.pose.position, Vec3(0, 0, 1));
  EXPECT_EQ(box.count, 7);
  EXPECT_EQ(box.distribution, Distribution::kRandom);
  EXPECT_EQ(box.file, path);
  EXPECT_EQ(box.line, 36);
  expect_camera_offset(box.model_from_camera);

  const Population& cylinder = problem.populations[1];
  EXPECT_EQ(cylinder.name, "cylinder_uniform");
  EXPECT_EQ(cylinder.region, RegionShape::kCylinder);
  EXPECT_DOUBLE_EQ(cylinder.radius, 0.3);
  EXPECT_DOUBLE_EQ(cylinder.length, 0.1);
  EXPECT_EQ(cylinder.count, 5);
  EXPECT_EQ(cylinder.distribution, Distribution::kUniform);
  EXPECT_EQ(cylinder.line, 50);

  // GAZEBO.md's grid example: pose 3.341 0 -0.35 0 -1.5707 0, 12 rows, 7 cols, step 0.3636.
  const Population& grid = problem.populations[2];
  EXPECT_EQ(grid.distribution, Distribution::kGrid);
  EXPECT_EQ(grid.region, RegionShape::kNone);
  EXPECT_EQ(grid.rows, 12);
  EXPECT_EQ(grid.cols, 7);
  ExpectVec(grid.step, Vec3(0.3636, 0.3636, 0));
  ExpectVec(grid.pose.position, Vec3(3.341, 0, -0.35));
  EXPECT_NEAR(AngleBetween(grid.pose.rotation, Quat(Eigen::AngleAxisd(-1.5707, Vec3::UnitY()))), 0,
              kTol);

  const Population& line = problem.populations[3];
  EXPECT_EQ(line.sensor_type, "inline_camera");
  EXPECT_EQ(line.distribution, Distribution::kLinearX);
  ExpectVec(line.box_size, Vec3(1, 0.1, 0.1));
  EXPECT_EQ(line.count, 4);
  ExpectVec(line.model_from_camera.position, Vec3::Zero());

  // 7 + 5 + 12·7 + 4 clones and one explicit camera: numberOfSamplingSensors = 101.
  EXPECT_EQ(box.count + cylinder.count + grid.rows * grid.cols + line.count +
                static_cast<int>(problem.sensors.size()),
            101);

  // The explicit camera: an include with a depth sensor, placed at its include pose.
  ASSERT_EQ(problem.sensors.size(), 1u);
  const ExplicitSensor& fixed = problem.sensors[0];
  EXPECT_EQ(fixed.name, "fixed_camera");
  EXPECT_EQ(fixed.sensor_type, "test_camera");
  EXPECT_TRUE(fixed.look_at);
  ExpectVec(fixed.pose.position, Vec3(1, 0, 0.5));
  expect_camera_offset(fixed.model_from_camera);
  EXPECT_EQ(fixed.file, path);
  EXPECT_EQ(fixed.line, 30);

  // Scene: the target box and Gazebo's ground plane (not on the path) — no camera bodies.
  EXPECT_EQ(Names(problem, Role::kTarget), std::set<std::string>{"target_box"});
  EXPECT_EQ(Names(problem, Role::kOccluder), std::set<std::string>{"ground_plane"});
  ExpectBounds(FindObject(problem, "ground_plane"), Vec3(-50, -50, 0), Vec3(50, 50, 0));
  ExpectBounds(FindObject(problem, "target_box"), Vec3(-0.1, -0.1, 0), Vec3(0.1, 0.1, 0.2));
  EXPECT_TRUE(HasNote(problem, "model://sun"));
  EXPECT_TRUE(HasNote(problem, "model://ground_plane"));
}

// ---------------------------------------------------------------------------------------------
// Paths.

const char* kBlockWorld = R"(<?xml version="1.0"?>
<sdf version="1.6">
  <world name="w">
    <include>
      <uri>model://block</uri>
    </include>
  </world>
</sdf>
)";

TEST(Gazebo, ModelPathOrder) {
  test::TempDir dir;
  test::WriteText(dir.File("world/w.world"), kBlockWorld);
  LoadOptions options;
  options.targets = {"block"};
  // Not beside the world, no path given: an error naming the include's <uri> line.
  ExpectErrorAt(LoadError(dir.File("world/w.world"), options), dir.File("world/w.world"), 5,
                "model://block");

  // GAZEBO_MODEL_PATH (second of three entries).
  SetEnv("GAZEBO_MODEL_PATH", "/nonexistent:" + World("models") + ":/also/none");
  const Problem from_env = detail::LoadGazeboWorld(dir.File("world/w.world"), options, nullptr);
  UnsetEnv("GAZEBO_MODEL_PATH");
  ExpectBounds(FindObject(from_env, "block"), Vec3(4.5, 4.5, 5), Vec3(5.5, 5.5, 6));

  // --model-path comes before GAZEBO_MODEL_PATH: a 3 m "block" there wins.
  test::WriteText(dir.File("mine/block/model.sdf"), R"(<?xml version="1.0"?>
<sdf version="1.6">
  <model name="block">
    <link name="link">
      <visual name="cube">
        <geometry><box><size>3 3 3</size></box></geometry>
      </visual>
    </link>
  </model>
</sdf>
)");
  options.model_paths = {dir.File("mine")};
  SetEnv("GAZEBO_MODEL_PATH", World("models"));
  const Problem mine = detail::LoadGazeboWorld(dir.File("world/w.world"), options, nullptr);
  UnsetEnv("GAZEBO_MODEL_PATH");
  ExpectBounds(FindObject(mine, "block"), Vec3(-1.5, -1.5, -1.5), Vec3(1.5, 1.5, 1.5));

  // A models/ folder beside the world comes last but works alone.
  test::WriteText(dir.File("world/models/block/model.sdf"),
                  test::ReadText(World("models/block/model.sdf")));
  options.model_paths.clear();
  ExpectBounds(FindObject(Load(dir.File("world/w.world"), options), "block"), Vec3(4.5, 4.5, 5),
               Vec3(5.5, 5.5, 6));
}

TEST(Gazebo, ResourcePathForMaterials) {
  test::TempDir dir;
  test::WriteText(dir.File("w.world"), R"(<?xml version="1.0"?>
<sdf version="1.6">
  <world name="w">
    <model name="thing">
      <link name="link">
        <visual name="visual">
          <geometry><sphere><radius>0.5</radius></sphere></geometry>
          <material>
            <script>
              <uri>file://media/custom.material</uri>
              <name>Custom/Target</name>
            </script>
          </material>
        </visual>
      </link>
    </model>
    <plugin name="p" filename="libsensor_placement_optimization.so">
      <sensorDataSegmentationColorRGB>255 128 0</sensorDataSegmentationColorRGB>
    </plugin>
  </world>
</sdf>
)");
  test::WriteText(dir.File("res/media/custom.material"),
                  "material Custom/Target { technique { pass { diffuse 1 0.5 0 } } }\n");
  // Without the resource path the script is not found: no target, an error at the colour line.
  ExpectErrorAt(LoadError(dir.File("w.world")), dir.File("w.world"), 18,
                "<sensorDataSegmentationColorRGB> 255 128 0");
  LoadOptions options;
  options.resource_paths = {dir.File("res")};
  const Problem problem = Load(dir.File("w.world"), options);
  // round(255 · 0.5) = 128: the sphere is the target, tessellated with a chord error below
  // F / 10 = 0.0005 m (the default F = 0.005).
  const SceneObject* thing = FindObject(problem, "thing");
  ASSERT_NE(thing, nullptr);
  EXPECT_TRUE(thing->is_target());
  for (const Vec3& v : thing->mesh.vertices) EXPECT_NEAR(v.norm(), 0.5, 0.0005 + 1e-9);
}

// ---------------------------------------------------------------------------------------------
// Bad worlds: InputError "file:line: ..." naming the element.

TEST(Gazebo, MalformedXml) {
  const std::string path = World("bad/malformed.world");
  ExpectErrorAt(LoadError(path), path, 6, "</model> closes <link> opened at line 5");
}

TEST(Gazebo, MissingModel) {
  const std::string path = World("bad/missing_model.world");
  ExpectErrorAt(LoadError(path), path, 5, "<include> model 'model://no_such_model' not found");
}

TEST(Gazebo, MissingMesh) {
  std::string path = World("bad/missing_mesh.world");
  ExpectErrorAt(LoadError(path), path, 9, "<mesh><uri> 'meshes/nope.stl'");
  // In an included model: the model file's line, and where it was included.
  path = World("bad/included_missing_mesh.world");
  const std::string message = LoadError(path);
  ExpectErrorAt(message, World("bad/models/broken_mesh/model.sdf"), 8,
                "'model://broken_mesh/meshes/missing.dae'");
  EXPECT_NE(message.find("included at " + path + ":4"), std::string::npos) << message;
}

TEST(Gazebo, UnknownPopulationForms) {
  std::string path = World("bad/unknown_population.world");
  ExpectErrorAt(LoadError(path), path, 20,
                "population 'ring': unknown <distribution><type> 'spiral'");
  path = World("bad/unknown_region.world");
  ExpectErrorAt(LoadError(path), path, 14,
                "population 'ball': <sphere> is not a population region");
  path = World("bad/unsupported_region.world");
  ExpectErrorAt(LoadError(path), path, 14,
                "population 'row': distribution 'linear-x' works in a <box> region only");
}

TEST(Gazebo, TargetColourMatchingNothing) {
  const std::string path = World("bad/no_target.world");
  ExpectErrorAt(LoadError(path), path, 13, "<sensorDataSegmentationColorRGB> 255 0 255 matches no");
}

TEST(Gazebo, NanAndNegativeValues) {
  std::string path = World("bad/nan_size.world");
  ExpectErrorAt(LoadError(path), path, 9, "<size> '1 nan 1' must be 3 finite numbers");

  // Every problem of the file in one message (the plugin's first: it is read first).
  path = World("bad/negative_values.world");
  const std::string message = LoadError(path);
  ExpectErrorAt(message, path, 32, "<voxelGridFilterLeafSize> -0.005 must be positive");
  EXPECT_NE(message.find(path + ":33: <ransacNumberOfIterations> 'many'"), std::string::npos)
      << message;
  EXPECT_NE(message.find(path + ":34: <observationPoint> '0 NaN 0'"), std::string::npos) << message;
  EXPECT_NE(message.find(path + ":23: <radius> -0.3 must be positive"), std::string::npos)
      << message;

  path = World("bad/bad_sensor.world");
  ExpectErrorAt(LoadError(path), path, 15, "sensor type 'camera': near = 2 must be below far = 1");
}

// A plane's <normal> is a direction of any finite length. Session 18: the length of
// (0, 1e190, 1) overflows a double, and normalising by it gave the zero vector, so the plane was
// turned by a rotation of zeros and loaded silently wrong. Gazebo's CreatePlane frame, by hand,
// for the normal (0, 1, 0): z = (0, 1, 0), y = z × (1, 0, 0) = (0, 0, −1), x = y × z = (1, 0, 0);
// the 2 × 1 plane spans x ±1 and z ±0.5 at y = 0.
TEST(Gazebo, PlaneNormalOfAnyFiniteLength) {
  const auto world = [](const std::string& normal) {
    return "<?xml version='1.0'?>\n<sdf version='1.6'><world name='w'>\n"
           "<model name='wall'><static>true</static><link name='link'><visual name='visual'>\n"
           "<geometry><plane><normal>" +
           normal +
           "</normal><size>2 1</size></plane></geometry>\n"
           "<material><diffuse>0 1 0 1</diffuse></material></visual></link></model>\n"
           "</world></sdf>\n";
  };
  test::TempDir dir;
  for (const std::string normal : {"0 1 0", "0 1e190 1", "0 1.7e308 0", "0 3e-5 0"}) {
    SCOPED_TRACE(normal);
    test::WriteText(dir.File("plane.world"), world(normal));
    const Problem problem = Load(dir.File("plane.world"));
    ExpectBounds(FindObject(problem, "wall"), Vec3(-1, 0, -0.5), Vec3(1, 0, 0.5));
  }
  // Below 1e-12 it is no direction anyone meant: refused at its line.
  test::WriteText(dir.File("zero.world"), world("0 0 1e-13"));
  ExpectErrorAt(LoadError(dir.File("zero.world")), dir.File("zero.world"), 4,
                "<normal> is zero (shorter than 1e-12)");
}

// ---------------------------------------------------------------------------------------------
// The XML reader and the material scripts on their own.

// Mounting rules (docs/constraints.md): <vantage:keep_out> and <vantage:min_separation> beside
// the populations. box_random's 7 clones lie in x ±0.25, y ±0.2, z 0.9..1.1; the keep-out box,
// turned 90° about z, spans x ±0.3, y ±0.25, z 0.85..1.15: it holds those 7 and nothing else
// (the cylinder is at z 1.45..1.55, the line at y = -1, the grid at x > 3, the fixed camera at
// (1, 0, 0.5)).
TEST(Gazebo, MountingRulesBesideThePopulations) {
  test::TempDir dir;
  std::string text = test::ReadText(World("sensors.world"));
  const std::string world = "<world name=\"sensors\">\n";
  text.replace(text.find(world), world.size(),
               world +
                   "    <vantage:keep_out name=\"cabinet\">\n"
                   "      <pose>0 0 1 0 0 1.5707963267948966</pose>\n"
                   "      <size>0.5 0.6 0.3</size>\n"
                   "    </vantage:keep_out>\n"
                   "    <vantage:min_separation>0.25</vantage:min_separation>\n");
  const std::string sdf = "<sdf version=\"1.5\">";
  text.replace(text.find(sdf), sdf.size(),
               "<sdf version=\"1.5\" xmlns:vantage=\"https://vantage.dev/sdf\">");
  const std::string path = dir.File("mounting.world");
  test::WriteText(path, text);
  LoadOptions options;
  options.model_paths = {World("models")};
  const Problem problem = Load(path, options);
  ASSERT_EQ(problem.mounting.keep_out.size(), 1u);
  const KeepOutBox& box = problem.mounting.keep_out[0];
  EXPECT_EQ(box.name, "cabinet");
  EXPECT_EQ(box.line, 6);
  ExpectVec(box.min, Vec3(-0.25, -0.3, -0.15));
  ExpectVec(box.max, Vec3(0.25, 0.3, 0.15));
  EXPECT_TRUE(box.Contains(Vec3(0.29, 0.24, 1.14)));
  EXPECT_FALSE(box.Contains(Vec3(0.29, 0.26, 1.0)));
  EXPECT_EQ(problem.mounting.min_separation, 0.25);
  EXPECT_EQ(problem.mounting.min_separation_line, 10);

  // libsdformat keeps both as custom elements of the world, without an error about them.
  sdf::Console::Instance()->SetQuiet(true);
  sdf::ParserConfig config;
  config.SetFindCallback([&](const std::string& uri) -> std::string {
    const std::string candidate = World("models") + "/" + uri.substr(uri.find("://") + 3);
    return std::filesystem::exists(candidate) ? candidate : "";
  });
  sdf::Root root;
  for (const sdf::Error& e : root.Load(path, config)) {
    EXPECT_EQ(e.Message().find("keep_out"), std::string::npos) << e.Message();
    EXPECT_EQ(e.Message().find("min_separation"), std::string::npos) << e.Message();
  }
  ASSERT_EQ(root.WorldCount(), 1u);
  const sdf::ElementPtr element = root.WorldByIndex(0)->Element();
  EXPECT_TRUE(element->HasElement("vantage:keep_out"));
  EXPECT_TRUE(element->HasElement("vantage:min_separation"));

  // The pipeline drops exactly box_random's clones before any ray.
  SceneInput input;
  input.path = path;
  input.load = options;
  UnsetEnv("GAZEBO_MODEL_PATH");
  const PreparedScene prepared = Prepare(input);
  EXPECT_EQ(prepared.kept_out.size(), 7u);
  EXPECT_EQ(prepared.candidates.size(), 101u - 7u);
  for (const Candidate& c : prepared.kept_out) EXPECT_EQ(c.population, "box_random");
  for (const Candidate& c : prepared.candidates) EXPECT_NE(c.population, "box_random");
}

TEST(Gazebo, BadMountingRules) {
  test::TempDir dir;
  const auto world = [&](const std::string& body) {
    const std::string path = dir.File("bad.world");
    test::WriteText(path, "<?xml version=\"1.0\"?>\n<sdf version=\"1.6\">\n  <world name=\"w\">\n" +
                              body + "  </world>\n</sdf>\n");
    return path;
  };
  std::string path = world("    <keep_out><size>1 1 1</size></keep_out>\n");
  ExpectErrorAt(LoadError(path), path, 4, "<keep_out> needs the vantage: prefix");
  path = world("    <vantage:keep_out name=\"k\"><pose>0 0 0 0 0 0</pose></vantage:keep_out>\n");
  ExpectErrorAt(LoadError(path), path, 4, "<vantage:keep_out name='k'> needs <size>");
  path = world(
      "    <vantage:keep_out>\n      <min>0 0 0</min>\n      <max>1 0 1</max>\n"
      "    </vantage:keep_out>\n");
  ExpectErrorAt(LoadError(path), path, 6, "<max> must exceed <min> on every axis");
  path = world("    <vantage:min_separation>-0.1</vantage:min_separation>\n");
  ExpectErrorAt(LoadError(path), path, 4, "must be positive");
  path = world("    <vantage:min_separation>1e-300</vantage:min_separation>\n");
  ExpectErrorAt(LoadError(path), path, 4, "min_separation 1e-300 m is outside [1e-06, 1e+09] m");
}

// Session 14: an element SDF allows once, written twice, was read silently as its first (as
// libsdformat reads it): the edit that added the second did nothing. It is now a warning naming
// both lines. Two shapes in one <geometry> are ambiguous — libsdformat picks by its own order (box
// before sphere), vantage took the first written — and refused.
TEST(Gazebo, RepeatedElementsWarnedAndTwoShapesRefused) {
  test::TempDir dir;
  const LoadOptions options = TestModels();
  const auto edited = [&](const std::string& from, const std::string& to) {
    return EditedWorld("export.world", from, to, dir.File("edited.world"));
  };
  // export.world's target: a 0.2 m box 0.1 m up (lines 14-16: <box>, <size>, </box>).
  std::string path =
      edited("<size>0.2 0.2 0.2</size>", "<size>0.2 0.2 0.2</size>\n<size>1 1 1</size>");
  const Problem problem = Load(path, options);
  ExpectBounds(FindObject(problem, "target_box"), Vec3(-0.1, -0.1, 0), Vec3(0.1, 0.1, 0.2));
  const std::string warning = path +
                              ":16: a second <size> in <box> (the first at line 15) is not "
                              "read — vantage, like Gazebo, reads the first; remove one";
  EXPECT_TRUE(std::find(problem.warnings.begin(), problem.warnings.end(), warning) !=
              problem.warnings.end());
  EXPECT_TRUE(HasNote(problem, warning));
  // A second <pose> of an include, and of a camera's clip: warned the same way.
  path = edited("<pose>1 0.2 0.5 0 0 3.14159</pose>",
                "<pose>1 0.2 0.5 0 0 3.14159</pose><pose>0 0 0 0 0 0</pose>");
  EXPECT_TRUE(HasNote(Load(path, options), "a second <pose> in <include> (the first at line 32)"));
  path = edited("<far>3</far>", "<far>3</far><far>9</far>");
  EXPECT_TRUE(HasNote(Load(path, options), "a second <far> in <clip>"));
  // Plugins hold what they like: two <name> in a plugin are no repeat.
  EXPECT_FALSE(HasNote(Load(World("export.world"), options), "a second"));

  path = edited("<geometry>", "<geometry><sphere><radius>1</radius></sphere>");
  ExpectErrorAt(LoadError(path, options), path, 14,
                "<geometry> has <sphere> (line 13) and <box>: one shape per geometry");
  // A warning that explains a failed load follows its error (session 15: a load that failed
  // printed no warning): the target's colour in a second <diffuse>, not read, so no target.
  path = edited("<diffuse>0 1 0 1</diffuse>",
                "<diffuse>1 1 1 1</diffuse>\n<diffuse>0 1 0 1</diffuse>");
  const std::string error = LoadError(path, options);
  const size_t no_target = error.find("matches no visual's material colour");
  const size_t repeat = error.find("\nwarning: " + path + ":20: a second <diffuse> in <material>");
  EXPECT_NE(no_target, std::string::npos) << error;
  EXPECT_NE(repeat, std::string::npos) << error;
  EXPECT_LT(no_target, repeat) << error;
}

TEST(GazeboXml, LinesEntitiesAndStructure) {
  const detail::XmlDocument doc = detail::ParseXml(
      "\xEF\xBB\xBF<?xml version=\"1.0\"?>\n<!-- c -->\n<!DOCTYPE sdf>\n<a x='1' "
      "y=\"&lt;&amp;&#65;\">\n"
      "  <b/>\n  <c>t&gt;<![CDATA[<raw>]]></c>\n</a>\n",
      "mem.xml");
  EXPECT_EQ(doc.root.name, "a");
  EXPECT_EQ(doc.root.line, 4);
  ASSERT_NE(doc.root.Attribute("y"), nullptr);
  EXPECT_EQ(*doc.root.Attribute("y"), "<&A");
  ASSERT_EQ(doc.root.children.size(), 2u);
  EXPECT_EQ(doc.root.children[0].line, 5);
  EXPECT_EQ(doc.root.Child("c")->text, "t><raw>");
  EXPECT_EQ(doc.root.Child("c")->line, 6);

  const auto error = [](const char* text) {
    try {
      detail::ParseXml(text, "mem.xml");
    } catch (const InputError& e) {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  EXPECT_EQ(error("<a>\n<b>\n</a>"),
            "mem.xml:3: malformed XML: </a> closes <b> opened at line 2 "
            "— the tags must match");
  EXPECT_EQ(error("<a>\n  <b x=1/>\n</a>").rfind("mem.xml:2: malformed XML:", 0), 0u);
  EXPECT_EQ(error("<a>&nbsp;</a>").rfind("mem.xml:1: malformed XML: unknown entity", 0), 0u);
  EXPECT_EQ(error("<a>\n<b>\n").rfind("mem.xml:2: malformed XML: <b> is never closed", 0), 0u);
  EXPECT_EQ(error("<a/>\n<b/>").rfind("mem.xml:2: malformed XML: a second root", 0), 0u);
  EXPECT_EQ(error("").rfind("mem.xml:1: malformed XML: no root element", 0), 0u);
}

TEST(GazeboMaterial, FirstPassColoursAndInheritance) {
  detail::MaterialLibrary library;
  ASSERT_TRUE(library.LoadFile(World("materials/test.material")));
  EXPECT_TRUE(library.problems.empty());
  const detail::MaterialColours* green = library.Find("Test/Green");
  ASSERT_NE(green, nullptr);
  // The first pass of the first technique: later passes and techniques (red) do not count.
  ASSERT_TRUE(green->diffuse.has_value());
  EXPECT_EQ(detail::ToRgb255(*green->diffuse), (std::array<int, 3>{0, 255, 0}));
  EXPECT_FALSE(green->emissive.has_value());
  const detail::MaterialColours* glow = library.Find("Test/GreenRedGlow");
  ASSERT_NE(glow, nullptr);
  EXPECT_EQ(detail::ToRgb255(*glow->SegmentationColour()), (std::array<int, 3>{255, 0, 0}));
  const detail::MaterialColours* inherited = library.Find("Test/GreenGlow");
  ASSERT_NE(inherited, nullptr);
  ASSERT_TRUE(inherited->diffuse.has_value());  // from Test/Green
  EXPECT_EQ(detail::ToRgb255(*inherited->SegmentationColour()), (std::array<int, 3>{0, 255, 0}));
  const detail::MaterialColours* grey = library.Find("Test/Quoted Grey");
  ASSERT_NE(grey, nullptr);
  EXPECT_EQ(detail::ToRgb255(*grey->diffuse), (std::array<int, 3>{128, 128, 128}));
}

// Session 9: a colour that is no number (1e400 overflows) and a script cut short were skipped or
// read without a word; each is a problem naming its line (the loader turns them into notes).
TEST(GazeboMaterial, ProblemsNamedAtTheirLine) {
  const test::TempDir dir;
  const std::string path = dir.File("bad.material");
  test::WriteText(path,
                  "material Bad/Huge\n{\n  technique\n  {\n    pass\n    {\n"
                  "      diffuse 1e400 0 0 1\n    }\n  }\n}\n"
                  "material Bad/Cut\n{\n  technique\n  {\n    pass\n    {\n"
                  "      diffuse 0 1 0 1\n");
  detail::MaterialLibrary library;
  ASSERT_TRUE(library.LoadFile(path));
  ASSERT_EQ(library.problems.size(), 2u);
  EXPECT_EQ(library.problems[0],
            path +
                ":11: the '{' of this block is never closed: the material script ends inside "
                "it (cut short?)");
  EXPECT_EQ(library.problems[1],
            path +
                ":7: 'diffuse 1e400 0 0 1' of material 'Bad/Huge' is not 3 or 4 finite "
                "numbers: skipped, as Ogre skips it (the material has no diffuse colour of its "
                "own)");
  const detail::MaterialColours* huge = library.Find("Bad/Huge");
  ASSERT_NE(huge, nullptr);
  EXPECT_FALSE(huge->diffuse.has_value());
  // What the cut script holds is still read, as before.
  const detail::MaterialColours* cut = library.Find("Bad/Cut");
  ASSERT_NE(cut, nullptr);
  ASSERT_TRUE(cut->diffuse.has_value());
  EXPECT_EQ(detail::ToRgb255(*cut->diffuse), (std::array<int, 3>{0, 255, 0}));
}

// Session 14: a script problem was a note, and notes are never shown once the load fails, so a
// world whose only target takes its colour from a skipped `diffuse` said only "matches no
// visual's material colour". The script's problems now follow that error.
TEST(GazeboMaterial, ScriptProblemsFollowTheNoTargetError) {
  const test::TempDir dir;
  std::filesystem::create_directories(dir.File("materials"));
  test::WriteText(dir.File("materials/m.material"),
                  "material M/X\n{ technique { pass { diffuse nan 1 0 1 } } }\n"
                  "material M/Y : M/Nope\n{ }\n");
  const std::string path =
      EditedWorld("export.world", "<diffuse>0 1 0 1</diffuse>",
                  "<script><uri>file://materials/m.material</uri><name>M/X</name></script>",
                  dir.File("scripted.world"));
  const std::string error = LoadError(path, TestModels());
  EXPECT_NE(error.find("matches no visual's material colour"), std::string::npos) << error;
  EXPECT_NE(error.find(
                "m.material:2: 'diffuse nan 1 0 1' of material 'M/X' is not 3 or 4 finite numbers"),
            std::string::npos)
      << error;
  EXPECT_NE(error.find("m.material:3: material 'M/Y' inherits unknown material 'M/Nope'"),
            std::string::npos)
      << error;
}

}  // namespace
}  // namespace vantage
