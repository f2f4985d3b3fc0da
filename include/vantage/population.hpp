#pragma once
/// Where sensors may go, as a scene declares it (Gazebo `<population>`, YAML `populations:` and
/// `sensors:`): plain values that the readers fill and the candidates stage deploys.
#include <string>

#include "vantage/types.hpp"

namespace vantage {

enum class RegionShape { kBox, kCylinder, kNone };
enum class Distribution { kRandom, kUniform, kGrid, kLinearX, kLinearY, kLinearZ };

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
