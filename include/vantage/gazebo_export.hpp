#pragma once
/// constellation.world (SYSTEM.md, Outputs): the input Gazebo world with only the chosen sensors,
/// as plain static models at their poses, ready to load in Gazebo or to evaluate again.
#include <cstdint>
#include <optional>
#include <set>
#include <string>
#include <vector>

#include "vantage/candidates.hpp"
#include "vantage/scene.hpp"
#include "vantage/visibility.hpp"

namespace vantage {

/// What shaped a run's coverage besides the scene's geometry and the sensors' poses: the options
/// that the command written into a generated constellation.sdf passes to `vantage evaluate`, so
/// that it scores the layout as the run did (issue 44: without the cell size it gave 60.57 %
/// against the run's 74.58 %).
struct ScoringOptions {
  double cell_size = 0;                ///< the run's cell edge F [m] (0: not known, no command)
  QualityFilter quality;               ///< --max-incidence, --max-depth-noise
  std::optional<int64_t> min_points;   ///< --min-points
  std::optional<double> min_density;   ///< --min-density [points per cm²]
};

/// The text of `world_path` with every `<population>` and every depth-sensor model of the world
/// replaced by one static model per chosen candidate, placed so that its camera frame lands
/// exactly at the candidate's world_from_body: model pose = world_from_body ·
/// model_from_camera⁻¹, written as `<pose>x y z roll pitch yaw</pose>` [m, rad].
///
/// - A candidate of a population whose model is an `<include>` becomes `<include>` with
///   `<name>` = the candidate's name, the population's `<uri>`, `<static>1</static>` and the
///   pose; one whose model is inline becomes a copy of that `<model>`, renamed, with the pose.
///   An explicitly placed sensor is handled alike from its own element.
/// - Everything else keeps its exact text (comments, plugins, physics, GUI), except the plugin's
///   `numberOfSamplingSensors`, set to the number of sensors the new world holds so that it
///   passes its own check. The new sensors go where the first removed element was (else just
///   before `</world>`).
/// - `populations` and `sensors` are those that LoadGazeboWorld returned for this world (they
///   give each candidate's source element and model_from_camera); a candidate is found by its
///   `population` name, else by its name among `sensors`.
/// - A depth sensor nested inside an included model file cannot be cut without rewriting that
///   file: it stays where it is, and a line in `notes` (when not null) says so.
///
/// URIs are copied as written: load the result with the same model path as the input (a
/// `models/` folder beside the input world is not beside the output). Throws InputError when the
/// world cannot be read or parsed, or when a candidate belongs to no population or sensor given.
std::string ConstellationWorld(const std::string& world_path,
                               const std::vector<Candidate>& chosen,
                               const std::vector<Population>& populations,
                               const std::vector<ExplicitSensor>& sensors,
                               std::vector<std::string>* notes = nullptr);

/// constellation.sdf (docs/outputs.md): the same edit of the input world as ConstellationWorld,
/// but each chosen sensor becomes a generated gz-sim model (static, its frame the camera's body
/// frame at world_from_body) holding one `depth_camera` sensor whose pinhole reproduces the
/// candidate's exactly: `horizontal_fov` = 2·atan(W / (2·fx)), image W × H, clip near/far, and
/// `<lens><intrinsics>` (fx, fy, cx, cy) only when the principal point is off centre or fy ≠ fx.
/// The world gets gz-sim's Sensors system plugin when it has none.
std::string ConstellationSdf(const std::string& world_path,
                             const std::vector<Candidate>& chosen,
                             const std::vector<Population>& populations,
                             const std::vector<ExplicitSensor>& sensors,
                             std::vector<std::string>* notes = nullptr);

/// constellation.sdf of a scene that is not a Gazebo world (a YAML scene): a gz-sim world (SDF
/// 1.9) of one static model per object, its shapes as SDF geometry at their world poses (visual
/// and collision; meshes by absolute path, with their scale), plus the chosen cameras as
/// ConstellationSdf writes them, and gz-sim's Physics, UserCommands, SceneBroadcaster and Sensors
/// systems. Its first element, `<vantage:rescore>`, holds the command that scores it again:
/// `vantage evaluate constellation.sdf --cell-size F --target T...` and the options of `scoring`
/// that were set (run in the folder of the file). Model names are ConstellationModelName's,
/// unique. An object whose shapes are unknown (a robot link, one a state reshaped) is left out
/// with a line in `notes`.
std::string SceneConstellationSdf(const Scene& scene, const std::vector<Candidate>& chosen,
                                  const ScoringOptions& scoring = {},
                                  std::vector<std::string>* notes = nullptr);

/// An SDF model name for a sensor or object (docs/outputs.md, constellation.sdf): "::" (which
/// SDF reserves) -> "__", "/" -> "_", a name that SDF reserves ("world", "__...__") prefixed by
/// "vantage_"; then, when a sibling already has it, "_2", "_3", ... until unique in `taken`,
/// which receives it.
std::string ConstellationModelName(const std::string& name, std::set<std::string>* taken);

/// True when `path` names a Gazebo world by its extension (`.world` or `.sdf`, any case).
bool IsGazeboWorldPath(const std::string& path);

}  // namespace vantage
