#pragma once
/// Everything a scene file or a Gazebo world declares: the geometry, where sensors may go, and
/// the settings of the run. Loaded from YAML (docs/scene-format.md) or SDF (GAZEBO.md).
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "vantage/candidates.hpp"
#include "vantage/scene.hpp"
#include "vantage/scene_states.hpp"
#include "vantage/sensors.hpp"

namespace vantage {

struct Problem {
  std::string source;  ///< path of the scene/world file
  Scene scene;
  std::vector<SensorType> sensor_types;  ///< types the populations and sensors refer to (by id)
  std::vector<Population> populations;
  std::vector<ExplicitSensor> sensors;
  Vec3 observation_point = Vec3::Zero();
  bool random_roll = false;
  double cell_size = 0.005;  ///< F [m]
  int n = 1;                 ///< number of sensors wanted (numberOfIntendedSensors)
  int ransac_iterations = 1000;
  double ransac_stop_coverage = 1.0;  ///< fraction in [0, 1]: RANSAC stops once reached
  uint64_t seed = 1;
  std::string method = "all";
  /// Objectives beyond coverage (SelectOptions): at most one is set.
  std::optional<double> goal;    ///< settings.goal: fewest sensors reaching this coverage
  int k = 1;                     ///< settings.k: k-coverage when >= 2
  std::optional<double> budget;  ///< settings.budget: total sensor cost cap
  std::optional<int> expected_candidates;  ///< numberOfSamplingSensors: a check
  std::vector<std::string> notes;          ///< non-fatal remarks made while loading
  /// States of a changing scene (`states:`; docs/scene-format.md, States), in file order; empty
  /// when the scene does not change. Each applies to `scene` through ApplyState.
  std::vector<SceneState> states;

  /// Looks up a sensor type by id; nullptr when absent.
  const SensorType* FindType(const std::string& id) const;
};

/// Options given on the command line that change how a file is read.
struct LoadOptions {
  std::vector<std::string> model_paths;     ///< --model-path (Gazebo), searched first
  std::vector<std::string> resource_paths;  ///< --resource-path (Gazebo)
  std::vector<std::string> targets;         ///< --target NAME: overrides the file's targets
};

/// Loads a `.yaml`/`.yml` scene or a `.world`/`.sdf` Gazebo world, by extension.
/// Throws InputError ("file:line: what is wrong") for anything the user can fix.
Problem LoadProblem(const std::string& path, const LoadOptions& options = {});

/// vantage's YAML scene format (docs/scene-format.md).
Problem LoadYamlScene(const std::string& path, const LoadOptions& options = {});

/// A Gazebo SDF world, read the way the original plugin saw it (GAZEBO.md).
Problem LoadGazeboWorld(const std::string& path, const LoadOptions& options = {});

}  // namespace vantage
