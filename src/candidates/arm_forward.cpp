// arm.hpp's kinematics, collision checks and motion planning, called in the arm module
// (candidates/arm_module.hpp), which is loaded the first time one of them is called.
#include <fmt/format.h>

#include <mutex>
#include <optional>

#include "candidates/arm_module.hpp"
#include "util/module_places.hpp"
#include "vantage/error.hpp"

namespace vantage {
namespace {

const detail::ArmModuleApi& LoadArmModule() {
  const detail::ModuleEntry loaded = detail::LoadModuleEntry(
      reinterpret_cast<const void*>(&PlanMotion), VANTAGE_ARM_MODULE_NAME,
      VANTAGE_ARM_MODULE_FROM_BIN, VANTAGE_ARM_MODULE_BUILT, "plan for an arm", "arm module",
      "vantage_arm_module");
  const auto* api = static_cast<const detail::ArmModuleApi*>(loaded.api);
  if (api == nullptr || api->version != detail::kArmModuleVersion)
    throw InternalError(fmt::format("{} is not this vantage's arm module", loaded.place.string()));
  return *api;  // never unloaded: its objects may live until the process ends
}

const detail::ArmModuleApi& Arm() {
  static const detail::ArmModuleApi& api = LoadArmModule();  // once, thread-safe
  return api;
}

}  // namespace

ArmKinematics::ArmKinematics(const PlacedRobot& robot, const std::string& tip_link,
                             const std::vector<std::string>& moved) {
  Arm().kinematics_make(this, robot, tip_link, moved);
}
ArmKinematics::~ArmKinematics() = default;
ArmKinematics::ArmKinematics(ArmKinematics&&) noexcept = default;
ArmKinematics& ArmKinematics::operator=(ArmKinematics&&) noexcept = default;

std::vector<double> ArmKinematics::Rest() const { return Arm().kinematics_rest(*this); }

std::map<std::string, Pose> ArmKinematics::LinkPosesAt(
    const std::vector<double>& configuration) const {
  return Arm().kinematics_link_poses(*this, configuration);
}

Pose ArmKinematics::TipPose(const std::vector<double>& configuration) const {
  return Arm().kinematics_tip_pose(*this, configuration);
}

std::optional<std::vector<double>> ArmKinematics::SolveIk(
    const Pose& world_from_camera, const Pose& tip_from_camera, Match match,
    double position_tolerance, double angle_tolerance, const std::vector<double>& start,
    int restarts, uint64_t seed, uint64_t stream) const {
  return Arm().kinematics_solve_ik(*this, world_from_camera, tip_from_camera, match,
                                   position_tolerance, angle_tolerance, start, restarts, seed,
                                   stream);
}

ArmCollisions::ArmCollisions(const PlacedRobot& robot, const Scene& scene,
                             const std::vector<KeepOutBox>& keep_out,
                             const std::vector<std::string>& moving_joints,
                             const std::vector<std::pair<std::string, std::string>>& allowed_pairs) {
  Arm().collisions_make(this, robot, scene, keep_out, moving_joints, allowed_pairs);
}
ArmCollisions::~ArmCollisions() = default;
ArmCollisions::ArmCollisions(ArmCollisions&&) noexcept = default;
ArmCollisions& ArmCollisions::operator=(ArmCollisions&&) noexcept = default;

ArmCollision ArmCollisions::Check(const std::map<std::string, Pose>& world_from_link,
                                  std::string* what) const {
  return Arm().collisions_check(*this, world_from_link, what);
}

PlannedMotion PlanMotion(const ArmKinematics& kinematics, const ArmCollisions& collisions,
                         const std::vector<double>& from, const std::vector<double>& to,
                         const std::vector<double>& speeds, const MotionPlanOptions& options) {
  return Arm().plan_motion(kinematics, collisions, from, to, speeds, options);
}

}  // namespace vantage
