// arm.hpp's kinematics, collision checks and motion planning, called in the arm module
// (candidates/arm_module.hpp), which is loaded the first time one of them is called.
#include <dlfcn.h>
#include <fmt/format.h>

#include <cstring>
#include <filesystem>
#include <mutex>

#include "candidates/arm_module.hpp"
#include "vantage/error.hpp"

namespace vantage {
namespace {

// Where the module may be, in order (as the CAD reader's, scene/step_reader.cpp): beside the code
// running (the binary, or the Python module's shared object), in the install's library folder
// relative to it, and the build tree's own.
std::vector<std::filesystem::path> ArmModulePlaces() {
  std::vector<std::filesystem::path> folders;
  Dl_info info{};
  if (dladdr(reinterpret_cast<void*>(&PlanMotion), &info) != 0 && info.dli_fname != nullptr &&
      std::strchr(info.dli_fname, '/') != nullptr) {
    folders.push_back(std::filesystem::path(info.dli_fname).parent_path());
  }
  std::error_code error;
  const std::filesystem::path self = std::filesystem::read_symlink("/proc/self/exe", error);
  if (!error) folders.push_back(self.parent_path());
  std::vector<std::filesystem::path> places;
  for (const std::filesystem::path& folder : folders) {
    places.push_back(folder / VANTAGE_ARM_MODULE_NAME);
    places.push_back(folder / VANTAGE_ARM_MODULE_FROM_BIN / VANTAGE_ARM_MODULE_NAME);
  }
  places.emplace_back(VANTAGE_ARM_MODULE_BUILT);
  return places;
}

const detail::ArmModuleApi& LoadArmModule() {
  std::string tried;
  for (const std::filesystem::path& place : ArmModulePlaces()) {
    std::error_code error;
    if (!std::filesystem::is_regular_file(place, error)) {
      tried += (tried.empty() ? "" : ", ") + place.string();
      continue;
    }
    void* module = dlopen(place.c_str(), RTLD_NOW | RTLD_LOCAL);
    if (module == nullptr)
      throw InternalError(fmt::format("cannot load the arm module {}: {}", place.string(), dlerror()));
    using Entry = const detail::ArmModuleApi* (*)();
    const auto entry = reinterpret_cast<Entry>(dlsym(module, "vantage_arm_module"));
    const detail::ArmModuleApi* api = entry ? entry() : nullptr;
    if (api == nullptr || api->version != detail::kArmModuleVersion)
      throw InternalError(fmt::format("{} is not this vantage's arm module", place.string()));
    return *api;  // never unloaded: its objects may live until the process ends
  }
  throw InternalError(fmt::format("cannot plan for an arm: the arm module {} is not installed "
                                  "(looked at {})",
                                  VANTAGE_ARM_MODULE_NAME, tried));
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
