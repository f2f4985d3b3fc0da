#pragma once
/// The arm module (issue 47): KDL, FCL and OMPL with the code that calls them
/// (module/arm_kinematics.cpp, module/arm_collision.cpp, module/arm_motion.cpp) are a shared
/// module of their own, libvantage_arm.so, loaded the first time an arm is built: their 20-odd
/// libraries cost every process start about 20 ms, and most runs have no arm. arm_forward.cpp
/// defines arm.hpp's functions in the stage library by calling the module's through this table;
/// the module holds its own copy of the stage libraries below it, hidden.
#include <map>
#include <string>
#include <vector>

#include "vantage/arm.hpp"

namespace vantage::detail {

/// Bumped whenever the table changes: a module from another build is refused.
inline constexpr int kArmModuleVersion = 1;

struct ArmModuleApi {
  int version = kArmModuleVersion;
  // ArmKinematics: made into *self (default-constructed), then its members.
  void (*kinematics_make)(ArmKinematics* self, const PlacedRobot& robot,
                          const std::string& tip_link, const std::vector<std::string>& moved);
  std::vector<double> (*kinematics_rest)(const ArmKinematics& self);
  std::map<std::string, Pose> (*kinematics_link_poses)(const ArmKinematics& self,
                                                        const std::vector<double>& configuration);
  Pose (*kinematics_tip_pose)(const ArmKinematics& self, const std::vector<double>& configuration);
  std::optional<std::vector<double>> (*kinematics_solve_ik)(
      const ArmKinematics& self, const Pose& world_from_camera, const Pose& tip_from_camera,
      ArmKinematics::Match match, double position_tolerance, double angle_tolerance,
      const std::vector<double>& start, int restarts, uint64_t seed, uint64_t stream);
  // ArmCollisions, alike.
  void (*collisions_make)(ArmCollisions* self, const PlacedRobot& robot, const Scene& scene,
                          const std::vector<KeepOutBox>& keep_out,
                          const std::vector<std::string>& moving_joints,
                          const std::vector<std::pair<std::string, std::string>>& allowed_pairs);
  ArmCollision (*collisions_check)(const ArmCollisions& self,
                                   const std::map<std::string, Pose>& world_from_link,
                                   std::string* what);
  PlannedMotion (*plan_motion)(const ArmKinematics& kinematics, const ArmCollisions& collisions,
                               const std::vector<double>& from, const std::vector<double>& to,
                               const std::vector<double>& speeds,
                               const MotionPlanOptions& options);
};

}  // namespace vantage::detail

/// The module's one exported symbol.
extern "C" const vantage::detail::ArmModuleApi* vantage_arm_module();
