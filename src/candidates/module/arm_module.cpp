// The arm module's table (candidates/arm_module.hpp): each entry calls this module's own
// definition (its symbols are hidden, so nothing here binds to the process' forwarders).
#include "candidates/arm_module.hpp"

namespace vantage::detail {
namespace {

const ArmModuleApi kApi = {
    kArmModuleVersion,
    [](ArmKinematics* self, const PlacedRobot& robot, const std::string& tip_link,
       const std::vector<std::string>& moved) { *self = ArmKinematics(robot, tip_link, moved); },
    [](const ArmKinematics& self) { return self.Rest(); },
    [](const ArmKinematics& self, const std::vector<double>& configuration) {
      return self.LinkPosesAt(configuration);
    },
    [](const ArmKinematics& self, const std::vector<double>& configuration) {
      return self.TipPose(configuration);
    },
    [](const ArmKinematics& self, const Pose& world_from_camera, const Pose& tip_from_camera,
       ArmKinematics::Match match, double position_tolerance, double angle_tolerance,
       const std::vector<double>& start, int restarts, uint64_t seed, uint64_t stream) {
      return self.SolveIk(world_from_camera, tip_from_camera, match, position_tolerance,
                          angle_tolerance, start, restarts, seed, stream);
    },
    [](ArmCollisions* self, const PlacedRobot& robot, const Scene& scene,
       const std::vector<KeepOutBox>& keep_out, const std::vector<std::string>& moving_joints,
       const std::vector<std::pair<std::string, std::string>>& allowed_pairs) {
      *self = ArmCollisions(robot, scene, keep_out, moving_joints, allowed_pairs);
    },
    [](const ArmCollisions& self, const std::map<std::string, Pose>& world_from_link,
       std::string* what) { return self.Check(world_from_link, what); },
    [](const ArmKinematics& kinematics, const ArmCollisions& collisions,
       const std::vector<double>& from, const std::vector<double>& to,
       const std::vector<double>& speeds, const MotionPlanOptions& options) {
      return PlanMotion(kinematics, collisions, from, to, speeds, options);
    },
};

}  // namespace
}  // namespace vantage::detail

extern "C" __attribute__((visibility("default"))) const vantage::detail::ArmModuleApi*
vantage_arm_module() {
  return &vantage::detail::kApi;
}
