#pragma once
/// Candidate sensors: populations deployed in regions (GAZEBO.md semantics), explicit poses,
/// the look-at orientation and random roll of the paper's 4-DoF reduction.
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "vantage/sensors.hpp"
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

/// One candidate: a sensor type at a world pose of its camera body frame (x forward).
struct Candidate {
  std::string name;
  std::string type_id;  ///< catalog id when the intrinsics match one, else the type's own name
  SensorType sensor;
  Pose world_from_body;
  std::string population;  ///< population name, or "" for explicit sensors
};

/// Rotation whose columns are (front, left, up') looking from `eye` to `target` with up = +Z;
/// when front is parallel to Z, left = +Y (GAZEBO.md). Throws InputError when eye == target.
Quat LookAt(const Vec3& eye, const Vec3& target);

/// Positions of a population's clones in the world, in clone order (GAZEBO.md, exactly: the
/// box shift before rotation, the uniform lattice + k-means, cylinder radius uniform in ρ,
/// grid centring, linear offsets). Random draws come from streams keyed by (seed, population
/// index, clone index). Throws InputError for unsupported combinations.
std::vector<Vec3> PopulationPositions(const Population& population, uint64_t seed,
                                      uint32_t population_index);

struct DeployOptions {
  Vec3 observation_point = Vec3::Zero();
  bool random_roll = false;  ///< roll = U(0, 4π) after the look-at (the plugin's quirk)
  uint64_t seed = 1;
};

/// Every candidate of the populations (in order, clone names "<population>_<i>") followed by the
/// explicit sensors. `types` resolves sensor_type keys; the candidate's type_id is the catalog
/// id when the intrinsics match one.
std::vector<Candidate> DeployCandidates(const std::vector<Population>& populations,
                                        const std::vector<ExplicitSensor>& sensors,
                                        const std::vector<SensorType>& types,
                                        const DeployOptions& options);

}  // namespace vantage
