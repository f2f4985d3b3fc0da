#pragma once
/// A camera on an arm's outputs (issue 45, docs/arm.md): the tour in report.json, views.yaml and
/// trajectory.json (trajectory_msgs/JointTrajectory's fields).
#include <nlohmann/json.hpp>
#include <string>

#include "vantage/report.hpp"

namespace vantage::detail {

/// report.json's `tour` of a result.
nlohmann::ordered_json ArmTourJson(const ArmTour& tour, const VisibilityFile& data);

/// report.json's `track` (optimize --track): each state's view, coverage and move.
nlohmann::ordered_json ArmTrackJson(const TrackInfo& track, const VisibilityFile& data);

/// views.yaml: the joint names, then each view in tour order (its candidate, configuration,
/// arrival and acquisition times, camera pose), home first and last.
std::string ViewsYaml(const ArmTour& tour, const VisibilityFile& data);

/// trajectory.json: a JSON mirror of ROS trajectory_msgs/msg/JointTrajectory (header.frame_id,
/// joint_names, points[].positions / velocities / time_from_start {sec, nanosec}): home, each
/// view (arriving and, after its acquisition, leaving), home. Straight joint-space moves.
std::string TrajectoryJson(const ArmTour& tour);

}  // namespace vantage::detail
