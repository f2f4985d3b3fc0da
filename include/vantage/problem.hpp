#pragma once
/// Everything a scene file or a Gazebo world declares: the geometry, where sensors may go, and
/// the settings of the run. Loaded from YAML (docs/scene-format.md) or SDF (GAZEBO.md).
#include <cstdint>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "vantage/population.hpp"
#include "vantage/robot.hpp"
#include "vantage/scene.hpp"
#include "vantage/sensors.hpp"
#include "vantage/scene_states.hpp"
#include "vantage/settings.hpp"

namespace vantage {

/// A region where no sensor may be mounted (a YAML scene's `keep_out:`, a world's
/// `<vantage:keep_out>`; docs/constraints.md, Mounting rules): the box [min, max] in the frame
/// `world_from_box` (the identity: axis-aligned in the world).
struct KeepOutBox {
  std::string name;  ///< as given, or "keep_out[i]"
  Pose world_from_box;
  Vec3 min = Vec3::Zero();
  Vec3 max = Vec3::Zero();
  std::string file;  ///< where it is declared, for messages
  int line = 0;
  /// Whether the world point lies inside the box or on its boundary.
  bool Contains(const Vec3& world) const;
};

/// Whether the world point lies in any of `boxes` (boundaries included): where no sensor may go.
bool InKeepOut(std::span<const KeepOutBox> boxes, const Vec3& world);

/// Where sensors may be mounted (docs/constraints.md, Mounting rules).
struct MountingRules {
  /// No candidate is deployed inside any of these (excluded before any ray).
  std::vector<KeepOutBox> keep_out;
  /// [m] Two chosen sensors must be at least this far apart (their optical centres).
  std::optional<double> min_separation;
  std::string min_separation_file;  ///< where min_separation is declared, for messages
  int min_separation_line = 0;
  bool empty() const { return keep_out.empty() && !min_separation; }
};

/// The separations a scene may ask for [m]: from a micrometre (below it no mount is that exact,
/// and the neighbour hashing of the pairs would overflow) to kMaxWorldCoordinate.
constexpr double kMinSeparationFloor = 1e-6;

/// "" when `metres` is a separation a scene may ask for; else what is wrong with it, for the
/// readers' `file:line` messages (one check for YAML and SDF).
std::string MinSeparationProblem(double metres);

struct Problem {
  std::string source;  ///< path of the scene/world file
  Scene scene;
  std::vector<SensorType> sensor_types;  ///< types the populations and sensors refer to (by id)
  std::vector<Population> populations;
  std::vector<ExplicitSensor> sensors;
  Vec3 observation_point = Vec3::Zero();
  bool random_roll = false;
  double cell_size = 0.005;  ///< F [m]
  uint64_t seed = 1;
  /// n, method, RANSAC and the objective (at most one of goal, k >= 2, budget is set).
  SelectionSettings selection;
  std::optional<int> expected_candidates;  ///< numberOfSamplingSensors: a check
  std::vector<std::string> notes;          ///< non-fatal remarks made while loading
  /// Those of `notes` that change the result (an occluder left out): logged as warnings.
  std::vector<std::string> warnings;
  /// States of a changing scene (`states:`; docs/scene-format.md, States), in file order; empty
  /// when the scene does not change. Each applies to `scene` through ApplyState.
  std::vector<SceneState> states;
  MountingRules mounting;  ///< keep-out boxes and the minimum separation
  /// The scene's URDF robots (`robots:`), as placed: what `arm` populations move (issue 45).
  std::vector<PlacedRobot> robots;

  /// Looks up a sensor type by id; nullptr when absent.
  const SensorType* FindType(const std::string& id) const;
};

/// Options given on the command line that change how a file is read.
struct LoadOptions {
  std::vector<std::string> model_paths;     ///< --model-path (Gazebo), searched first
  std::vector<std::string> resource_paths;  ///< --resource-path (Gazebo)
  std::vector<std::string> targets;         ///< --target NAME: overrides the file's targets
  /// Where `targets` came from, for messages: the option, or e.g. "run/report.json: inputs.targets"
  /// when `evaluate` or `render` inherit them from a run (issue 15: blamed on --target).
  std::string targets_origin = "--target";
  /// --package-path: folders where a URDF's `package://PKG/...` paths are found (FOLDER/share/PKG,
  /// FOLDER/PKG, or FOLDER named PKG), searched before ROS_PACKAGE_PATH and AMENT_PREFIX_PATH.
  std::vector<std::string> package_paths;
  /// --cell-size F [m]: replaces the file's cell size (still validated) before any primitive is
  /// tessellated, so that cylinders and spheres get the chord error F / 10 of the F used.
  std::optional<double> cell_size;

  /// Where the three lists of folders came from, for messages: the options, or e.g.
  /// "run/report.json: inputs.model_paths" when `evaluate` or `render` inherit them from a run.
  std::string model_paths_origin = "--model-path";
  std::string resource_paths_origin = "--resource-path";
  std::string package_paths_origin = "--package-path";

  /// Throws InputError naming --cell-size when it is not a positive finite length, or the origin
  /// of a model, resource or package path that is not a folder (a mistyped folder was accepted,
  /// and what it should have held was then "not found" in the others). Every reader calls it
  /// before reading the file.
  void Validate() const;
};

/// Loads a `.yaml`/`.yml` scene or a `.world`/`.sdf` Gazebo world, by extension.
/// Throws InputError ("file:line: what is wrong") for anything the user can fix.
Problem LoadProblem(const std::string& path, const LoadOptions& options = {});

/// vantage's YAML scene format (docs/scene-format.md).
Problem LoadYamlScene(const std::string& path, const LoadOptions& options = {});

/// A Gazebo SDF world, read the way the original plugin saw it (GAZEBO.md).
Problem LoadGazeboWorld(const std::string& path, const LoadOptions& options = {});

}  // namespace vantage
