#pragma once
/// Where sensors may go, as a scene declares it (Gazebo `<population>`, YAML `populations:` and
/// `sensors:`): plain values that the readers fill and the candidates stage deploys.
#include <map>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "vantage/types.hpp"

namespace vantage {

enum class RegionShape { kBox, kCylinder, kNone };
enum class Distribution { kRandom, kUniform, kGrid, kLinearX, kLinearY, kLinearZ };

/// How an `arm` population draws configurations in joint space (docs/arm.md).
enum class JointSampling { kRandom, kHalton, kGrid, kList };

/// A camera carried by a robot arm (issue 45, docs/arm.md): population kind `arm` (views from
/// joint space) or a region's `reach:` (the region's poses kept where inverse kinematics puts
/// the camera there).
struct ArmMount {
  std::string robot;       ///< a `robots:` entry's name
  std::string link;        ///< the link the camera is fixed on
  Pose link_from_camera;   ///< the camera body frame (x forward) in the link frame
  JointSampling sampling = JointSampling::kHalton;
  /// The joints drawn (all movable joints between the root and `link` when empty); the others
  /// stay at the robot's `joints:` positions.
  std::vector<std::string> joints;
  /// kList: each configuration, joint name -> position (joints not named stay fixed).
  std::vector<std::map<std::string, double>> configurations;
  std::vector<int> configuration_lines;
  /// Pairs of links (or a link and a scene object) whose contact is allowed.
  std::vector<std::pair<std::string, std::string>> allowed_pairs;
  /// `reach:`: what IK matches of the region's camera pose: the whole pose, the position and
  /// the optical axis (the roll about it free; default), or the position only.
  enum class Match { kPose, kDirection, kPosition };
  Match match = Match::kDirection;
  /// `reach:`: inverse kinematics tolerances (position [m], angle [rad]) and restarts.
  double position_tolerance = 1e-3;
  double angle_tolerance = 1e-3;
  int ik_restarts = 8;
  /// Where the tour starts and ends (joint name -> position); the robot's `joints:` when empty.
  std::map<std::string, double> home;
  std::string file;  ///< where it is declared, for messages
  int line = 0;
  int link_line = 0;   ///< the `link:` key's line
  int robot_line = 0;  ///< the `robot:` key's line (the mapping's when left out)
};

/// A population of one sensor type (Gazebo `<population>`), placed by position only.
struct Population {
  std::string name;
  std::string sensor_type;  ///< key into Problem::sensor_types
  Pose pose;                ///< P: the population's pose in the world
  RegionShape region = RegionShape::kBox;
  Vec3 box_size = Vec3::Zero();  ///< kBox: sx sy sz [m]
  double radius = 0;             ///< kCylinder [m]
  double length = 0;             ///< kCylinder [m]
  int count = 0;                 ///< model_count (not used by grid)
  Distribution distribution = Distribution::kRandom;
  int rows = 0, cols = 0;        ///< grid
  Vec3 step = Vec3::Zero();      ///< grid step dx dy dz [m]
  /// Camera frame in the sensor model's frame (Gazebo: link pose · sensor pose); identity for
  /// a bare camera. Composed after the look-at orientation.
  Pose model_from_camera;
  /// Kind `arm`: views from the arm's joint space (no region; count is the number of views);
  /// with a region: its `reach:`, poses kept only where the arm can put the camera.
  std::optional<ArmMount> arm;
  bool arm_views = false;  ///< kind `arm` (joint space) rather than a region's `reach:`
  std::string file;  ///< where it was declared, for messages
  int line = 0;
};

/// A sensor placed explicitly (a Gazebo `<include>` of a depth sensor, a YAML `sensors:` entry).
struct ExplicitSensor {
  std::string name;
  std::string sensor_type;
  Pose pose;                ///< the model's pose in the world
  bool look_at = true;      ///< re-orient towards the observation point (the plugin does)
  Pose model_from_camera;   ///< as Population::model_from_camera
  std::string file;
  int line = 0;
};

}  // namespace vantage
