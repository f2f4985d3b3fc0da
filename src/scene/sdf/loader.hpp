#pragma once
/// The SDF reader's state and the records of its walk, private to the reader (scene/sdf/*.cpp).
/// One Loader reads one world: each concern is a group of member functions in its own file
/// (values, resolution, frames, model_walk, plugin, populations, roles, geometry; world.cpp runs
/// them in order), sharing the documents, the collected errors and notes, and the Problem being
/// filled. The records below are what the walk over world -> model -> link -> visual/sensor
/// collects before the scene is built.
#include <algorithm>
#include <array>
#include <map>
#include <memory>
#include <optional>
#include <set>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "scene/scaled_mesh_cache.hpp"
#include "scene/sdf/materials.hpp"
#include "scene/sdf/world.hpp"
#include "util/xml.hpp"
#include "vantage/error.hpp"
#include "vantage/problem.hpp"
#include "vantage/scene.hpp"
#include "vantage/scene_settings.hpp"
#include "vantage/types.hpp"

namespace vantage::detail::gazebo {

/// Gazebo's ground_plane model: a 100 m x 100 m plane at z = 0 (used when it is not on the path).
constexpr double kGroundPlaneSize = 100.0;
/// Default segmentation colour of the plugin (sensorDataSegmentationColorRGB).
constexpr std::array<int, 3> kDefaultSegmentationColour = {0, 255, 0};

// ---------------------------------------------------------------------------------------------
// Records of the walk.

/// A loaded SDF file.
struct Doc {
  XmlDocument xml;
  std::string dir;        ///< folder of the file
  std::string model_dir;  ///< model folder it belongs to ("" for the world file)
};

/// Where a top-level entity is declared in the world file (for messages and sensors).
struct Site {
  std::string file;
  int line = 0;
};

struct VisualRecord {
  std::string model;  ///< scoped instance name
  std::string link;
  std::string name;
  Pose world_from_visual;
  const Doc* doc = nullptr;
  const XmlElement* element = nullptr;  ///< <visual>; nullptr: synthetic ground plane
  Site site;
};

struct SensorRecord {
  std::string model;      ///< scoped instance name of the model holding the sensor
  std::string type_name;  ///< the model's name in its own file
  std::string sensor_name;
  Pose world_from_model;
  Pose model_from_camera;  ///< link · sensor
  const Doc* doc = nullptr;
  const XmlElement* element = nullptr;  ///< <sensor>
  Site site;
};

/// What a walk collects; a null member is not wanted.
struct Sink {
  std::vector<VisualRecord>* visuals = nullptr;
  std::vector<SensorRecord>* sensors = nullptr;
  std::vector<std::pair<std::string, bool>>* models = nullptr;  ///< scoped name, is hidden
};

struct ModelContext {
  std::string scoped;  ///< instance name, "outer::inner" when nested
  /// Where the model goes: the pose of its model frame, or, with a placement frame, the pose
  /// that frame of the model must have (SDF 1.8 placement_frame; VisitModel moves the model).
  Pose world_from_model;
  std::string placement_frame;        ///< "" = the model frame
  const Doc* placement_doc = nullptr;  ///< the file of the element that names it
  int placement_line = 0;              ///< and its line
  bool hidden = false;  ///< inside a sensor model: its bodies never occlude
  Sink sink;
  Site site;
};

struct IncludeResult {
  enum class Kind { kModel, kSkipped, kGroundPlane, kFailed };
  Kind kind = Kind::kFailed;
  const Doc* doc = nullptr;
  const XmlElement* model = nullptr;
  std::string name;  ///< instance name (<include><name> or the model's own)
};

/// A named frame of a model scope (link, nested model, include, <frame>) and its pose.
struct FrameEntry {
  const Doc* doc = nullptr;
  const XmlElement* pose = nullptr;  ///< may be null (identity)
  bool honours_relative_to = true;   ///< false for an included model's own pose
  std::string default_parent;        ///< "" = the model frame
  int line = 0;
  /// A nested model placed by its placement_frame: its pose is its placement frame's, so other
  /// frames cannot be placed relative to it (refused at their pose).
  bool is_placed_by_frame = false;
};

/// A Fuel model URI, https://fuel.gazebosim.org/1.0/<owner>/models/<name>[/<version>][/files/..].
struct FuelUri {
  std::string host;     ///< lower case
  std::string owner;    ///< %XX decoded; matched without case
  std::string name;     ///< %XX decoded; matched without case
  std::string version;  ///< "" or "tip": the newest in the cache
  std::string file;     ///< a file inside the model ("" for the model folder)
};
/// nullopt when `uri` is no Fuel model URI (resolution.cpp).
std::optional<FuelUri> ParseFuelUri(const std::string& uri);

// ---------------------------------------------------------------------------------------------

/// Reads one Gazebo world into a Problem; its member functions live in the files named below.
/// An SDF bool as sdformat reads it: true/false/1/0 in any case; nullopt for any other word.
std::optional<bool> BoolWord(std::string text);

class Loader {
 public:
  /// Sets the model and resource search paths (resolution.cpp).
  Loader(std::string path, const LoadOptions& options);

  /// Reads the world; throws InputError listing every problem (world.cpp).
  Problem Load(std::vector<GazeboVisual>* visuals_out);

 private:
  // Problems.
  /// Records an already placed message ("file:line: ..."), once.
  void AddError(const std::string& text) {
    if (errors_seen_.insert(text).second) diag_.Error(0, text);
  }
  void Error(const std::string& file, int line, const std::string& message) {
    AddError(AtPlace(file, line, message));
  }
  void Error(const Doc& doc, int line, const std::string& message) {
    Error(doc.xml.path, line, message);
  }
  void Note(const std::string& note) {
    if (notes_seen_.insert(note).second) problem_.notes.push_back(note);
  }
  /// A note logged as a warning: what the world says is not what vantage (or Gazebo) reads.
  void Warn(const std::string& note) {
    if (!notes_seen_.contains(note)) problem_.warnings.push_back(note);
    Note(note);
  }
  /// Throws the errors, when there are any, followed by the warnings so far: a load that fails
  /// prints no warning, and what vantage did not read may be the cause (a second <diffuse>,
  /// ignored, that held the target colour).
  void ThrowIfErrors() {
    if (!diag_.HasErrors()) return;
    for (const std::string& warning : problem_.warnings) diag_.Error(0, "warning: " + warning);
    diag_.ThrowIfAny();
  }

  // Values (values.cpp). Each returns nullopt after recording an error naming the element.
  std::optional<std::vector<double>> Numbers(const Doc& doc,
                                             const XmlElement& e,
                                             size_t count,
                                             std::string_view example);
  std::optional<double> Number(const Doc& doc, const XmlElement& e, std::string_view example);
  std::optional<double> PositiveNumber(const Doc& doc,
                                       const XmlElement& e,
                                       std::string_view unit_example);
  std::optional<int64_t> Integer(const Doc& doc, const XmlElement& e, int64_t min, int64_t max);
  std::optional<bool> Boolean(const Doc& doc, const XmlElement& e);
  std::optional<Vec3> Vector(const Doc& doc,
                             const XmlElement& e,
                             bool positive,
                             std::string_view example);
  /// The pose value of a <pose> (identity when null or wrong; errors recorded).
  Pose PoseValue(const Doc& doc, const XmlElement* pose);
  std::string RelativeTo(const Doc& doc, const XmlElement* pose);
  /// A pose at world level: relative_to empty, "world", or (in the world file) a world-level
  /// <frame>, <model> or named <include> (WorldFrame).
  Pose WorldPose(const Doc& doc, const XmlElement* pose);
  /// The world pose of a world-level frame, model or named include of the world file, following
  /// relative_to and attached_to; an error at `line` when there is none of that name, it is
  /// placed by a placement_frame, or the chain is a cycle.
  Pose WorldFrame(const std::string& name, int line);
  /// Sets `context`'s placement frame: an include's <placement_frame> (in `include_doc`), else
  /// the model's placement_frame attribute (in `model_doc`), else none.
  void SetPlacementFrame(const Doc& include_doc, const XmlElement* include, const Doc& model_doc,
                         const XmlElement& model, ModelContext* context);
  /// Child value of `parent` or `fallback` when the child is absent.
  double NumberOr(const Doc& doc,
                  const XmlElement* parent,
                  std::string_view child,
                  double fallback,
                  bool positive);

  // Files, URIs and includes (resolution.cpp).
  const Doc* LoadSdf(const std::string& path, const std::string& model_dir);
  std::string ModelFileInDir(const std::string& dir, const Doc& from, int line);
  std::optional<std::string> ResolveModelUri(const std::string& uri,
                                             const Doc& from,
                                             std::vector<std::string>* searched);
  /// The model folder (or file) of a Fuel URI in the local cache; the cache folders looked in
  /// go to `searched`.
  std::optional<std::string> FuelCached(const FuelUri& fuel, std::vector<std::string>* searched);
  /// A file:// or relative resource (a material script, a mesh) on the resource path; the
  /// folders looked in go to `searched` (each once) when it is given.
  std::optional<std::string> ResolveResourceUri(const std::string& uri, const Doc& from,
                                                std::vector<std::string>* searched = nullptr);
  IncludeResult ResolveInclude(const Doc& doc, const XmlElement& include);

  /// A <sensor type> that vantage reads as a camera: depth, depth_camera, rgbd, rgbd_camera,
  /// and camera in a world without the Classic plugin (model_walk.cpp).
  bool IsCameraSensorType(const std::string& type) const;

  // Walk (model_walk.cpp; frames.cpp: FrameInModel; plugin.cpp; populations.cpp).
  void VisitWorldEntity(const Doc& doc, const XmlElement& e);
  void VisitModel(const Doc& doc, const XmlElement& model, const ModelContext& context);
  /// Records an error and fails `result` when its model is one the walk is inside.
  void RefuseCycle(const Doc& doc, const XmlElement& include, IncludeResult* result);
  Pose FrameInModel(const std::string& name,
                    std::map<std::string, FrameEntry>& entries,
                    std::map<std::string, Pose>& resolved,
                    std::set<std::string>& visiting,
                    const std::string& model,
                    const Doc& doc,
                    int line);
  void ReadPlugin();
  /// A selection setting's plugin parameter (its row in scene_settings.hpp); whole numbers up
  /// to `max_count`.
  void ReadSelectionSetting(const Doc& doc, const XmlElement& e,
                            const SceneSelectionSetting& setting, int64_t max_count);
  void ReadSegmentationColour(const Doc& doc, const XmlElement& e);
  void ReadPopulation(const Doc& doc, const XmlElement& e);
  /// <vantage:keep_out> and <vantage:min_separation>, siblings of <population> (mounting.cpp).
  void ReadKeepOut(const Doc& doc, const XmlElement& e);
  void ReadMinSeparation(const Doc& doc, const XmlElement& e);
  std::optional<std::string> AddSensorType(const SensorRecord& record, const std::string& id);

  // Scene (roles.cpp: ColoursOf, BuildScene; geometry.cpp: GeometryOf, LoadMesh).
  MaterialColours ColoursOf(const VisualRecord& visual);
  /// A note now; an error too when no visual ends up with the target colour (BuildScene).
  void MissingMaterial(const std::string& message) {
    Note(message);
    if (std::find(missing_materials_.begin(), missing_materials_.end(), message) ==
        missing_materials_.end())
      missing_materials_.push_back(message);
  }
  std::optional<TriangleMesh> GeometryOf(const VisualRecord& visual, bool is_target);
  const TriangleMesh* LoadMesh(const std::string& path, const Doc& doc, int line);
  void BuildScene(std::vector<GazeboVisual>* visuals_out);

  std::string path_;
  const LoadOptions& options_;
  Problem problem_;
  Diagnostics diag_{""};
  std::set<std::string> errors_seen_;
  std::set<std::string> notes_seen_;
  std::vector<std::string> model_dirs_;
  std::vector<std::string> resource_dirs_;
  std::vector<std::string> fuel_cache_dirs_;  ///< GZ_FUEL_CACHE_PATH, else ~/.gz/fuel
  std::map<std::string, std::unique_ptr<Doc>> docs_;  ///< by path; null entry: failed to load
  const Doc* world_doc_ = nullptr;
  const XmlElement* world_ = nullptr;

  std::vector<VisualRecord> visuals_;
  std::vector<SensorRecord> sensors_;
  std::vector<std::pair<std::string, bool>> models_;
  std::set<std::string> top_names_;
  std::map<std::string, Pose> world_frames_;       ///< WorldFrame's results
  std::set<std::string> world_frames_visiting_;    ///< WorldFrame's chain, to refuse cycles
  /// The models the walk is inside, outermost first (scoped name, file), to refuse include cycles.
  std::vector<std::pair<const XmlElement*, std::string>> open_models_;
  std::set<std::string> population_names_;

  /// The world has the original (Classic) plugin: a <plugin> carrying one of its parameters or
  /// loading libsensor_placement_optimization. Then explicit sensors are re-aimed at the
  /// observation point, as the plugin did; otherwise the world's cameras are a real layout.
  bool has_classic_plugin_ = false;
  // Plugin parameters that later steps need.
  std::array<int, 3> segmentation_colour_ = kDefaultSegmentationColour;
  Site segmentation_site_;  ///< the colour's element, else the first plugin, else no line
  bool is_segmentation_given_ = false;
  std::optional<std::vector<std::string>> scene_model_names_;
  Site scene_model_site_;

  MaterialLibrary materials_;
  std::set<std::string> material_files_;
  /// Material scripts and materials that were not found ("file:line: what, where looked"):
  /// reported with the error when no visual has the target colour (the likely cause).
  std::vector<std::string> missing_materials_;
  std::map<std::string, std::unique_ptr<TriangleMesh>> meshes_;  ///< unscaled; null: failed
  ScaledMeshCache scaled_meshes_;  ///< by path and scale
};

}  // namespace vantage::detail::gazebo
