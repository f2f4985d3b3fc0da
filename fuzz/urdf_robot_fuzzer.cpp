// libFuzzer target: URDF robots (docs/scene-format.md, `robots`). The fuzzed bytes are a URDF
// file, read twice: by LoadUrdf, whose model must be a tree that forward kinematics can walk, and
// as the robot of a YAML scene written for it — every settable joint moved in a state, a camera
// mounted on the last link — so that the links' visuals, their meshes (package:// through the
// test package folder), the mount and the state's re-posed links are built as a run builds them.
// An InputError is the expected outcome for bad input; anything else (another exception, a
// sanitizer report, a hang — session 14 found a link with two parent joints walking forever —
// an out-of-memory) is a bug.
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <set>
#include <string>

#include <nlohmann/json.hpp>

#include "fuzz_util.hpp"
#include "vantage/error.hpp"
#include "vantage/problem.hpp"
#include "vantage/robot.hpp"

namespace {

using vantage::JointPositions;
using vantage::RobotJoint;
using vantage::RobotModel;

/// Within the joint's limits when it has them (their middle, halved first so that ±1e308 limits
/// stay finite), else half a radian or metre: a position that moves every settable joint.
JointPositions MovedJoints(const RobotModel& robot) {
  JointPositions positions;
  for (const RobotJoint& joint : robot.joints) {
    if (!joint.IsSettable()) continue;
    positions[joint.name] =
        joint.limits ? joint.limits->first / 2 + joint.limits->second / 2 : 0.5;
  }
  return positions;
}

/// The tree that LoadUrdf promises: every link once, the root first, each joint between links
/// already listed (its parent before its child), a unit axis; forward kinematics poses every link.
void CheckModel(const RobotModel& robot) {
  VANTAGE_CHECK(!robot.links.empty() && robot.links.front() == robot.root_link);
  std::set<std::string> listed;
  for (const std::string& link : robot.links) VANTAGE_CHECK(listed.insert(link).second);
  std::set<std::string> children;
  for (const RobotJoint& joint : robot.joints) {
    VANTAGE_CHECK(listed.count(joint.parent_link) == 1 && listed.count(joint.child_link) == 1);
    VANTAGE_CHECK(joint.child_link != robot.root_link);
    VANTAGE_CHECK(children.insert(joint.child_link).second);  // one parent joint per link
    VANTAGE_CHECK(std::abs(joint.axis.norm() - 1) < 1e-9);
  }
  VANTAGE_CHECK(robot.joints.size() + 1 == robot.links.size());
  for (const JointPositions& positions : {JointPositions{}, MovedJoints(robot)}) {
    if (!vantage::JointPositionProblems(robot, positions).empty()) continue;
    const auto poses = vantage::LinkPoses(robot, vantage::Pose{}, positions);
    VANTAGE_CHECK(poses.size() == robot.links.size());
  }
}

/// A scene around the robot: a target plate, the robot, a camera on its last link, a state that
/// moves its settable joints. JSON is YAML, and nlohmann quotes any name the URDF holds.
std::string SceneFor(const RobotModel& robot) {
  using nlohmann::json;
  json joints = json::object();
  for (const auto& [name, position] : MovedJoints(robot)) joints[name] = position;
  json scene = {
      {"settings", {{"cell_size", 0.01}, {"n", 1}}},
      {"objects",
       json::array({{{"name", "plate"},
                     {"role", "target"},
                     {"pose", {{"xyz", {0, 0, -1}}}},
                     {"plane", {{"size", {0.2, 0.2}}}}}})},
      {"robots", json::array({{{"name", "arm"}, {"urdf", "../robot.urdf"}}})},
      {"sensors",
       json::array({{{"name", "wrist"},
                     {"type", "kinect_xbox_360"},
                     {"mount", {{"link", robot.links.back()}}}}})},
      {"states", json::array({{{"name", "rest"}},
                              {{"name", "moved"}, {"joints", {{"arm", joints}}}}})}};
  return scene.dump(-1, ' ', false, json::error_handler_t::replace);
}

}  // namespace

extern "C" int LLVMFuzzerInitialize(int* /*argc*/, char*** /*argv*/) {
  return vantage::fuzz::Initialize();
}

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  using namespace vantage;  // NOLINT(google-build-using-namespace): a fuzzer's one function
  const std::string urdf = fuzz::WriteInput("robot.urdf", data, size);
  std::string scene;
  try {
    const RobotModel robot = LoadUrdf(urdf);
    CheckModel(robot);
    scene = SceneFor(robot);
  } catch (const InputError&) {
    return 0;  // rejected with a message: the expected outcome for bad input
  }
  const std::string scene_path =
      fuzz::WriteInput("scenes/robot.yaml", reinterpret_cast<const uint8_t*>(scene.data()),
                       scene.size());
  LoadOptions options;
  options.package_paths = {fuzz::SourcePath("tests/data/urdf/packages")};
  try {
    const Problem problem = LoadProblem(scene_path, options);
    VANTAGE_CHECK(problem.states.size() == 2);
    for (const SceneObject& object : problem.scene.objects) {
      for (const Vec3& v : object.mesh.vertices) VANTAGE_CHECK(WorldPointProblem(v).empty());
    }
  } catch (const InputError&) {
    // a URDF that loads may still not make a scene: its meshes, a state's joints, its extent
  }
  return 0;
}
