// Candidate poses: the plugin's look-at orientation, its random roll, the camera mount
// (GAZEBO.md, "Sensor orientation and camera").
#include <fmt/format.h>

#include <cmath>
#include <numbers>
#include <string>
#include <vector>

#include "vantage/candidates.hpp"
#include "vantage/error.hpp"
#include "vantage/rng.hpp"

namespace vantage {
namespace {

/// Below this eye–target distance [m] there is no viewing direction.
constexpr double kMinLookDistance = 1e-9;
/// Below this |up × front| the view is vertical and left is fixed to +Y.
constexpr double kVerticalTolerance = 1e-9;
/// Roll streams of explicit sensors use indices above every population index (uint32), so an
/// explicit sensor never shares a roll with a population clone.
constexpr uint64_t kExplicitRollIndex = uint64_t{1} << 32;

std::string Where(const std::string& file, int line) {
  if (file.empty()) return "";
  return line > 0 ? fmt::format("{}:{}", file, line) : file;
}

/// The type named `key`: from `types` first, else a catalog id (so a scene may name a catalog
/// sensor without declaring it).
const SensorType& ResolveType(const std::string& key,
                              const std::vector<SensorType>& types,
                              const std::string& file,
                              int line,
                              const std::string& what) {
  for (const SensorType& type : types) {
    if (type.id == key) return type;
  }
  if (const SensorType* type = FindCatalogType(key)) return *type;
  throw InputError(AtPlace(file, line,
                           fmt::format("{}: unknown sensor type '{}' — declare it or use a catalog "
                                       "id (`vantage sensors` lists them)",
                                       what, key)));
}

void CheckMount(const Pose& model_from_camera,
                const std::string& file,
                int line,
                const std::string& what) {
  if (!model_from_camera.position.allFinite() || !model_from_camera.rotation.coeffs().allFinite() ||
      model_from_camera.rotation.norm() < 1e-9) {
    throw InputError(AtPlace(file, line,
                             fmt::format("{}: the camera's pose in the sensor model is "
                                         "not finite — fix the link/sensor <pose>",
                                         what)));
  }
}

/// Look-at orientation, then the plugin's random roll when asked: decompose, replace the roll by
/// U(0, 4π), recompose (the x axis, hence the viewing direction, is unchanged).
Quat Orient(const Vec3& position,
            const DeployOptions& options,
            uint64_t roll_index,
            uint64_t roll_sub_index,
            const std::string& file,
            int line,
            const std::string& what) {
  Quat rotation;
  try {
    rotation = LookAt(position, options.observation_point);
  } catch (const InputError& e) {
    throw InputError(AtPlace(file, line, fmt::format("{}: {}", what, e.what())));
  }
  if (!options.random_roll) return rotation;
  const Vec3 rpy = RpyFromRotation(rotation.toRotationMatrix());
  Rng rng(options.seed, Stream::kRoll, roll_index, roll_sub_index);
  const double roll = rng.Uniform(0.0, 4.0 * std::numbers::pi);
  return Quat(RotationFromRpy(roll, rpy.y(), rpy.z())).normalized();
}

Candidate MakeCandidate(std::string name,
                        const SensorType& type,
                        const Pose& world_from_model,
                        const Pose& model_from_camera,
                        std::string population) {
  Candidate candidate;
  candidate.name = std::move(name);
  const std::string catalog_id = MatchCatalogId(type);
  candidate.type_id = catalog_id.empty() ? type.id : catalog_id;
  candidate.sensor = type;
  // The mount composes after the orientation: the camera sits where the model's link puts it.
  candidate.world_from_body = world_from_model * model_from_camera;
  candidate.population = std::move(population);
  return candidate;
}

}  // namespace

Quat LookAt(const Vec3& eye, const Vec3& target) {
  const Vec3 delta = target - eye;
  if (!delta.allFinite())
    throw InputError(fmt::format("look-at from ({}, {}, {}) to ({}, {}, {}) is not finite", eye.x(),
                                 eye.y(), eye.z(), target.x(), target.y(), target.z()));
  const double distance = delta.norm();
  if (distance < kMinLookDistance) {
    throw InputError(
        fmt::format("the sensor at ({}, {}, {}) sits on the observation point — move "
                    "the sensor or the observation point",
                    eye.x(), eye.y(), eye.z()));
  }
  const Vec3 front = delta / distance;
  const Vec3 side = Vec3::UnitZ().cross(front);
  const double side_norm = side.norm();
  const Vec3 left = side_norm < kVerticalTolerance ? Vec3::UnitY() : Vec3(side / side_norm);
  const Vec3 up = front.cross(left);
  Mat3 rotation;
  rotation.col(0) = front;
  rotation.col(1) = left;
  rotation.col(2) = up;
  return Quat(rotation).normalized();
}

std::vector<Candidate> DeployCandidates(const std::vector<Population>& populations,
                                        const std::vector<ExplicitSensor>& sensors,
                                        const std::vector<SensorType>& types,
                                        const DeployOptions& options) {
  if (!options.observation_point.allFinite())
    throw InputError("observation point is not finite — give three numbers x y z");
  std::vector<Candidate> candidates;

  for (size_t pi = 0; pi < populations.size(); ++pi) {
    const Population& population = populations[pi];
    if (population.arm_views) continue;  // views from an arm's joint space: ApplyArms (arm.hpp)
    const std::string what = fmt::format("population '{}'", population.name);
    const SensorType& type =
        ResolveType(population.sensor_type, types, population.file, population.line, what);
    type.Validate(Where(population.file, population.line));
    CheckMount(population.model_from_camera, population.file, population.line, what);
    const auto population_index = static_cast<uint32_t>(pi);
    const std::vector<Vec3> positions =
        PopulationPositions(population, options.seed, population_index);
    for (size_t i = 0; i < positions.size(); ++i) {
      const Quat rotation = Orient(positions[i], options, population_index, i, population.file,
                                   population.line, fmt::format("{} clone {}", what, i));
      candidates.push_back(MakeCandidate(fmt::format("{}_{}", population.name, i), type,
                                         Pose{positions[i], rotation}, population.model_from_camera,
                                         population.name));
    }
  }

  for (size_t si = 0; si < sensors.size(); ++si) {
    const ExplicitSensor& sensor = sensors[si];
    const std::string what = fmt::format("sensor '{}'", sensor.name);
    const SensorType& type = ResolveType(sensor.sensor_type, types, sensor.file, sensor.line, what);
    type.Validate(Where(sensor.file, sensor.line));
    CheckMount(sensor.model_from_camera, sensor.file, sensor.line, what);
    if (!sensor.pose.position.allFinite() || !sensor.pose.rotation.coeffs().allFinite() ||
        sensor.pose.rotation.norm() < 1e-9) {
      throw InputError(AtPlace(sensor.file, sensor.line,
                               fmt::format("{}: <pose> is not finite — give six numbers", what)));
    }
    // look_at = false keeps the given rotation as is (no re-orientation, no random roll).
    const Quat rotation = sensor.look_at ? Orient(sensor.pose.position, options, kExplicitRollIndex,
                                                  si, sensor.file, sensor.line, what)
                                         : sensor.pose.rotation.normalized();
    candidates.push_back(MakeCandidate(sensor.name, type, Pose{sensor.pose.position, rotation},
                                       sensor.model_from_camera, ""));
  }
  return candidates;
}

void CheckCandidate(const Candidate& candidate, const std::string& where) {
  const Pose& pose = candidate.world_from_body;
  if (!pose.rotation.coeffs().allFinite())
    throw InputError(fmt::format("{}: its rotation is not finite", where));
  const std::string problem = WorldPointProblem(pose.position);
  if (!problem.empty()) {
    throw InputError(fmt::format("{}: its position {} — place sensors near the scene", where,
                                 problem));
  }
  candidate.sensor.Validate(where);
}

}  // namespace vantage
