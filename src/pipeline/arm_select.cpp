// `vantage select FILE` of a camera on an arm (issue 45): the arm views a visibility file keeps
// (format 11: robot, joint names, each view's joints) given their arm again from the reloaded
// scene, so that each result gets its tour as `optimize` gives it.
#include <fmt/format.h>
#include <fmt/ranges.h>

#include <algorithm>
#include <cmath>

#include "pipeline/common.hpp"
#include "vantage/arm.hpp"
#include "vantage/error.hpp"

namespace vantage::detail {
namespace {

// How far the camera may lie from where the stored joints put it in the reloaded scene. The
// same forward kinematics of the same numbers gives the same bits; this only absorbs a
// different build's rounding, far below anything a scene edit moves.
constexpr double kCameraToleranceM = 1e-6;
constexpr double kCameraToleranceRad = 1e-6;

}  // namespace

std::vector<ArmSetup> RebuildArmViews(Problem* problem,
                                      const std::string& visibility_file,
                                      VisibilityFile* data) {
  std::vector<ArmSetup> arms = ArmSetupsOf(*problem);
  const auto refuse = [&](const Candidate& c, const std::string& why) {
    return InputError(AtPlace(
        visibility_file, 0,
        fmt::format("candidate '{}' is a camera on an arm, but {} — the scene was changed since "
                    "`vantage observe` wrote this file; observe it again",
                    c.name, why)));
  };
  std::vector<bool> used(arms.size(), false);
  for (size_t i = 0; i < data->candidates.size(); ++i) {
    if (i >= data->arm_views.size() || !data->arm_views[i]) continue;
    const StoredArmView& stored = *data->arm_views[i];
    Candidate& c = data->candidates[i];
    const auto setup = std::find_if(arms.begin(), arms.end(), [&](const ArmSetup& arm) {
      return arm.population == c.population;
    });
    if (setup == arms.end())
      throw refuse(c, fmt::format("the scene {} has no population '{}' with an arm",
                                  problem->source, c.population));
    if (setup->robot != stored.robot)
      throw refuse(c, fmt::format("its robot was '{}' and population '{}' is now on robot '{}'",
                                  stored.robot, c.population, setup->robot));
    const std::vector<std::string>& joints = setup->kinematics->joint_names();
    if (joints != stored.joint_names)
      throw refuse(
          c, fmt::format("robot '{}' had {} joints ({}) and has {} ({}) in the scene", stored.robot,
                         stored.joint_names.size(), fmt::join(stored.joint_names, ", "),
                         joints.size(), fmt::join(joints, ", ")));
    // Where the stored joints put the camera must be where observe saw it from: a moved base, a
    // changed URDF, link or mount would otherwise time a tour of other views.
    const Population& population =
        *std::find_if(problem->populations.begin(), problem->populations.end(),
                      [&](const Population& p) { return p.name == c.population && p.arm; });
    const std::map<std::string, Pose> links = setup->kinematics->LinkPosesAt(stored.joints);
    const Pose camera = links.at(population.arm->link) * population.arm->link_from_camera;
    const double moved = (camera.position - c.world_from_body.position).norm();
    const double turned = camera.rotation.angularDistance(c.world_from_body.rotation);
    if (!(moved <= kCameraToleranceM && turned <= kCameraToleranceRad))
      throw refuse(c, fmt::format("its joints put the camera {:.3g} m and {:.3g} rad from where "
                                  "it was observed",
                                  moved, turned));
    auto pose = std::make_shared<ArmPose>();
    pose->body = setup->body;
    pose->joints = stored.joints;
    for (const std::string& link : setup->body->links)
      pose->world_from_link.push_back(links.at(link));
    c.arm = std::move(pose);
    used[static_cast<size_t>(setup - arms.begin())] = true;
  }
  // The tour's arms: those some stored view is on.
  std::vector<ArmSetup> kept;
  for (size_t a = 0; a < arms.size(); ++a)
    if (used[a]) kept.push_back(std::move(arms[a]));
  // As Prepare does: the robots that carry cameras leave the scene (report.html ghosts them at
  // each view instead of a static copy at the `robots:` joints).
  std::vector<SceneObject> objects;
  for (SceneObject& object : problem->scene.objects) {
    const bool carried = std::any_of(kept.begin(), kept.end(), [&](const ArmSetup& a) {
      return object.name.rfind(a.robot + "::", 0) == 0;
    });
    if (!carried) objects.push_back(std::move(object));
  }
  problem->scene.objects = std::move(objects);
  return kept;
}

}  // namespace vantage::detail
