// Gazebo SDF worlds, read the way the original Gazebo plugin saw them (GAZEBO.md).
//
// Parsing: vantage's own XML reader (gazebo_xml.hpp explains why not sdformat's element tree),
// then a walk over world → include/model → link → visual/sensor that reproduces Gazebo classic:
// includes resolved against the model path, the include's <pose> replacing the model's own,
// world_from_visual = model · link · visual, nested models named "outer::inner", sensor bodies
// hidden, Ogre material colours for the plugin's colour segmentation, <population> elements as
// Population structs (their positions are drawn later by PopulationPositions).
//
// Frames: `<pose relative_to="X">` is honoured when X names the parent (or "__model__"/"world")
// or a link, nested model, include or <frame> of the same model; anything else (scoped names
// "a::b", relative_to between top-level models) is an error. The SDF 1.5/1.6 `frame` attribute
// is ignored, as Gazebo classic ignored it. `placement_frame`, `<state>` and merge-includes are
// not applied (a note says so).
//
// Targets: a visual is a target when its colour rounds (round(255·v)) to the plugin's
// sensorDataSegmentationColorRGB. Its colour is the emissive one where the Ogre script or the
// inline <material> sets it (even 0 0 0), else the diffuse one; inline colours replace the
// script's channel by channel (Gazebo applies them after the script); ambient never counts; a
// visual with neither, or with a material that cannot be found (a note), is never a target.
// Objects: one SceneObject per model instance (scoped name) and role; a model with visuals of
// both roles gives "NAME" (target part) and "NAME/occluder". sceneModelPath's names are only
// cross-checked (each disagreement is a note: the plugin segmented by colour); no target at all
// is an error at <sensorDataSegmentationColorRGB>. --target NAME (LoadOptions::targets) makes
// exactly those models, with everything they nest, targets; an unknown name is an error.
// Sensor models: a model with a <sensor type="depth"> in one of its links (and what it nests)
// adds no geometry; outside populations it becomes an ExplicitSensor named after the instance.
#include "scene/gazebo_world.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <map>
#include <memory>
#include <numbers>
#include <optional>
#include <set>
#include <string>
#include <string_view>
#include <vector>

#include "scene/gazebo_material.hpp"
#include "util/xml.hpp"
#include "vantage/error.hpp"
#include "vantage/problem.hpp"
#include "vantage/scene.hpp"

namespace vantage {
namespace detail {
namespace {

namespace fs = std::filesystem;

/// Gazebo's ground_plane model: a 100 m x 100 m plane at z = 0 (used when it is not on the path).
constexpr double kGroundPlaneSize = 100.0;
/// Default segmentation colour of the plugin (sensorDataSegmentationColorRGB).
constexpr std::array<int, 3> kDefaultSegmentationColour = {0, 255, 0};

// ---------------------------------------------------------------------------------------------
// Text helpers.

bool IsSpace(char c) { return c == ' ' || c == '\t' || c == '\n' || c == '\r'; }

std::string Trim(std::string_view s) {
  size_t begin = 0;
  size_t end = s.size();
  while (begin < end && IsSpace(s[begin])) ++begin;
  while (end > begin && IsSpace(s[end - 1])) --end;
  return std::string(s.substr(begin, end - begin));
}

std::vector<std::string> SplitWords(std::string_view s) {
  std::vector<std::string> words;
  size_t i = 0;
  while (i < s.size()) {
    while (i < s.size() && IsSpace(s[i])) ++i;
    const size_t start = i;
    while (i < s.size() && !IsSpace(s[i])) ++i;
    if (i > start) words.emplace_back(s.substr(start, i - start));
  }
  return words;
}

std::vector<std::string> SplitList(std::string_view s, char separator) {
  std::vector<std::string> parts;
  size_t start = 0;
  while (start <= s.size()) {
    size_t end = s.find(separator, start);
    if (end == std::string_view::npos) end = s.size();
    std::string part = Trim(s.substr(start, end - start));
    if (!part.empty()) parts.push_back(std::move(part));
    start = end + 1;
  }
  return parts;
}

/// A number as SDF writes it (a leading '+' allowed); not checked for finiteness.
std::optional<double> ParseDouble(std::string_view s) {
  if (!s.empty() && s[0] == '+') s.remove_prefix(1);
  double value = 0;
  const auto [ptr, ec] = std::from_chars(s.data(), s.data() + s.size(), value);
  if (s.empty() || ec != std::errc() || ptr != s.data() + s.size()) return std::nullopt;
  return value;
}

std::optional<int64_t> ParseInteger(std::string_view s) {
  if (!s.empty() && s[0] == '+') s.remove_prefix(1);
  int64_t value = 0;
  const auto [ptr, ec] = std::from_chars(s.data(), s.data() + s.size(), value);
  if (s.empty() || ec != std::errc() || ptr != s.data() + s.size()) return std::nullopt;
  return value;
}

/// "1.5" -> (1, 5).
std::optional<std::pair<int, int>> ParseVersion(std::string_view s) {
  const size_t dot = s.find('.');
  if (dot == std::string_view::npos) return std::nullopt;
  const auto major = ParseInteger(s.substr(0, dot));
  const auto minor = ParseInteger(s.substr(dot + 1));
  if (!major || !minor || *major < 0 || *minor < 0 || *major > 1000 || *minor > 1000)
    return std::nullopt;
  return std::make_pair(static_cast<int>(*major), static_cast<int>(*minor));
}

std::vector<std::string> PathListFromEnv(const char* variable) {
  // Read while loading only; vantage never sets the environment.
  const char* value = std::getenv(variable);  // NOLINT(concurrency-mt-unsafe)
  return value ? SplitList(value, ':') : std::vector<std::string>{};
}

bool IsDirectory(const std::string& path) {
  std::error_code ec;
  return fs::is_directory(path, ec);
}

bool IsFile(const std::string& path) {
  std::error_code ec;
  return fs::is_regular_file(path, ec);
}

std::string ParentDir(const std::string& path) {
  return fs::path(path).parent_path().lexically_normal().string();
}

std::string Join(const std::vector<std::string>& items, std::string_view separator) {
  std::string out;
  for (size_t i = 0; i < items.size(); ++i) {
    if (i) out += separator;
    out += items[i];
  }
  return out;
}

bool IsDepthSensorType(const std::string& type) {
  // Gazebo classic calls it "depth"; newer SDF spells "depth_camera" and "rgbd_camera".
  return type == "depth" || type == "depth_camera" || type == "rgbd_camera";
}

/// Models that hold only a light when they are not on the path (Gazebo's database `sun`).
bool IsLightModelName(const std::string& name) { return name == "sun"; }

/// The model name in a URI: "model://sun" -> "sun", "file:///a/b/box/" -> "box".
std::string UriBaseName(const std::string& uri) {
  std::string rest = uri;
  const size_t scheme = rest.find("://");
  if (scheme != std::string::npos) rest = rest.substr(scheme + 3);
  while (!rest.empty() && rest.back() == '/') rest.pop_back();
  if (uri.rfind("model://", 0) == 0) return rest.substr(0, rest.find('/'));
  const size_t slash = rest.rfind('/');
  return slash == std::string::npos ? rest : rest.substr(slash + 1);
}

/// True when `name` selects `model`: the same scoped name or an ancestor of it ("a" selects
/// "a::b").
bool NameSelects(const std::string& name, const std::string& model) {
  return model == name || (model.size() > name.size() + 2 && model.rfind(name + "::", 0) == 0);
}

/// The plane of Gazebo's MeshManager::CreatePlane: z axis = normal, y axis = normal ×
/// (1, 0, 0) (or × (0, 1, 0) when parallel), x axis = y × z; size along x and y.
Quat PlaneRotation(const Vec3& normal) {
  const Vec3 z = normal.normalized();
  Vec3 y = z.cross(Vec3::UnitX());
  if (y.squaredNorm() < 1e-12) y = z.cross(Vec3::UnitY());
  y.normalize();
  const Vec3 x = y.cross(z);
  Mat3 rotation;
  rotation.col(0) = x;
  rotation.col(1) = y;
  rotation.col(2) = z;
  return Quat(rotation).normalized();
}

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
  Pose world_from_model;
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
};

// ---------------------------------------------------------------------------------------------

class Loader {
 public:
  Loader(std::string path, const LoadOptions& options) : path_(std::move(path)), options_(options) {
    for (const std::string& dir : options_.model_paths) model_dirs_.push_back(dir);
    for (const std::string& dir : PathListFromEnv("GAZEBO_MODEL_PATH")) model_dirs_.push_back(dir);
    model_dirs_.push_back((fs::path(path_).parent_path() / "models").lexically_normal().string());
    for (const std::string& dir : options_.resource_paths) resource_dirs_.push_back(dir);
    for (const std::string& dir : PathListFromEnv("GAZEBO_RESOURCE_PATH"))
      resource_dirs_.push_back(dir);
    for (const std::string& dir : model_dirs_) resource_dirs_.push_back(ParentDir(dir + "/"));
  }

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

  // Values. Each returns nullopt after recording an error naming the element.
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
  /// A pose at world level: relative_to must be empty or "world".
  Pose WorldPose(const Doc& doc, const XmlElement* pose);
  /// Child value of `parent` or `fallback` when the child is absent.
  double NumberOr(const Doc& doc,
                  const XmlElement* parent,
                  std::string_view child,
                  double fallback,
                  bool positive);

  // Files.
  const Doc* LoadSdf(const std::string& path, const std::string& model_dir);
  std::string ModelFileInDir(const std::string& dir, const Doc& from, int line);
  std::optional<std::string> ResolveModelUri(const std::string& uri,
                                             const Doc& from,
                                             std::vector<std::string>* searched);
  std::optional<std::string> ResolveResourceUri(const std::string& uri, const Doc& from);
  IncludeResult ResolveInclude(const Doc& doc, const XmlElement& include);

  // Walk.
  void VisitWorldEntity(const Doc& doc, const XmlElement& e);
  void VisitModel(const Doc& doc, const XmlElement& model, const ModelContext& context);
  Pose FrameInModel(const std::string& name,
                    std::map<std::string, FrameEntry>& entries,
                    std::map<std::string, Pose>& resolved,
                    std::set<std::string>& visiting,
                    const std::string& model,
                    const Doc& doc,
                    int line);
  void ReadPlugin();
  void ReadSegmentationColour(const Doc& doc, const XmlElement& e);
  void ReadPopulation(const Doc& doc, const XmlElement& e);
  std::optional<std::string> AddSensorType(const SensorRecord& record, const std::string& id);

  // Scene.
  MaterialColours ColoursOf(const VisualRecord& visual);
  std::optional<TriangleMesh> GeometryOf(const VisualRecord& visual);
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
  std::map<std::string, std::unique_ptr<Doc>> docs_;  ///< by path; null entry: failed to load
  const Doc* world_doc_ = nullptr;
  const XmlElement* world_ = nullptr;

  std::vector<VisualRecord> visuals_;
  std::vector<SensorRecord> sensors_;
  std::vector<std::pair<std::string, bool>> models_;
  std::set<std::string> top_names_;
  std::set<std::string> population_names_;

  // Plugin parameters that later steps need.
  std::array<int, 3> segmentation_colour_ = kDefaultSegmentationColour;
  Site segmentation_site_;  ///< the colour's element, else the first plugin, else no line
  bool is_segmentation_given_ = false;
  std::optional<std::vector<std::string>> scene_model_names_;
  Site scene_model_site_;

  MaterialLibrary materials_;
  std::set<std::string> material_files_;
  std::map<std::string, std::unique_ptr<TriangleMesh>> meshes_;  ///< null: failed
};

// ---------------------------------------------------------------------------------------------
// Values.

std::optional<std::vector<double>> Loader::Numbers(const Doc& doc,
                                                   const XmlElement& e,
                                                   size_t count,
                                                   std::string_view example) {
  const std::vector<std::string> words = SplitWords(e.text);
  std::vector<double> values;
  bool ok = words.size() == count;
  for (size_t i = 0; ok && i < words.size(); ++i) {
    const std::optional<double> v = ParseDouble(words[i]);
    ok = v && std::isfinite(*v);
    if (ok) values.push_back(*v);
  }
  if (!ok) {
    Error(doc, e.line,
          fmt::format("<{}> '{}' must be {} finite number{} — write e.g. <{}>{}</{}>", e.name,
                      e.Trimmed(), count, count == 1 ? "" : "s", e.name, example, e.name));
    return std::nullopt;
  }
  return values;
}

std::optional<double> Loader::Number(const Doc& doc,
                                     const XmlElement& e,
                                     std::string_view example) {
  const auto values = Numbers(doc, e, 1, example);
  if (!values) return std::nullopt;
  return (*values)[0];
}

std::optional<double> Loader::PositiveNumber(const Doc& doc,
                                             const XmlElement& e,
                                             std::string_view unit_example) {
  const auto value = Number(doc, e, unit_example);
  if (!value) return std::nullopt;
  if (*value <= 0) {
    Error(doc, e.line,
          fmt::format("<{}> {} must be positive — write e.g. <{}>{}</{}>", e.name, e.Trimmed(),
                      e.name, unit_example, e.name));
    return std::nullopt;
  }
  return value;
}

std::optional<int64_t> Loader::Integer(const Doc& doc,
                                       const XmlElement& e,
                                       int64_t min,
                                       int64_t max) {
  const std::optional<int64_t> value = ParseInteger(e.Trimmed());
  if (!value || *value < min || *value > max) {
    Error(doc, e.line,
          fmt::format("<{}> '{}' must be a whole number from {} to {}", e.name, e.Trimmed(), min,
                      max));
    return std::nullopt;
  }
  return value;
}

std::optional<bool> Loader::Boolean(const Doc& doc, const XmlElement& e) {
  std::string text = e.Trimmed();
  std::transform(text.begin(), text.end(), text.begin(), [](char c) {
    return static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  });
  if (text == "true" || text == "1") return true;
  if (text == "false" || text == "0") return false;
  Error(doc, e.line, fmt::format("<{}> '{}' must be true or false", e.name, e.Trimmed()));
  return std::nullopt;
}

std::optional<Vec3> Loader::Vector(const Doc& doc,
                                   const XmlElement& e,
                                   bool positive,
                                   std::string_view example) {
  const auto values = Numbers(doc, e, 3, example);
  if (!values) return std::nullopt;
  const Vec3 v((*values)[0], (*values)[1], (*values)[2]);
  if (positive && (v.array() <= 0).any()) {
    Error(doc, e.line,
          fmt::format("<{}> '{}' must be three positive numbers — write e.g. "
                      "<{}>{}</{}>",
                      e.name, e.Trimmed(), e.name, example, e.name));
    return std::nullopt;
  }
  return v;
}

Pose Loader::PoseValue(const Doc& doc, const XmlElement* pose) {
  if (!pose || pose->Trimmed().empty()) return Pose{};
  const std::string* format = pose->Attribute("rotation_format");
  const bool is_quaternion = format && *format == "quat_xyzw";
  if (format && !is_quaternion && *format != "euler_rpy") {
    Error(doc, pose->line,
          fmt::format("<pose rotation_format='{}'> is unknown — use euler_rpy "
                      "or quat_xyzw",
                      *format));
    return Pose{};
  }
  const auto values = Numbers(doc, *pose, is_quaternion ? 7 : 6,
                              is_quaternion ? "x y z qx qy qz qw" : "x y z roll pitch yaw");
  if (!values) return Pose{};
  const auto& v = *values;
  if (is_quaternion) {
    const Quat q(v[6], v[3], v[4], v[5]);
    if (q.norm() < 1e-9) {
      Error(doc, pose->line, "<pose> quaternion is zero — give a unit quaternion qx qy qz qw");
      return Pose{};
    }
    return Pose{Vec3(v[0], v[1], v[2]), q.normalized()};
  }
  const std::string* degrees = pose->Attribute("degrees");
  const double scale =
      degrees && (*degrees == "true" || *degrees == "1") ? std::numbers::pi / 180.0 : 1.0;
  return Pose::FromXyzRpy(v[0], v[1], v[2], v[3] * scale, v[4] * scale, v[5] * scale);
}

std::string Loader::RelativeTo(const Doc& doc, const XmlElement* pose) {
  if (!pose) return "";
  const std::string* frame = pose->Attribute("frame");
  if (frame && !Trim(*frame).empty()) {
    Note(AtPlace(doc.xml.path, pose->line,
                 fmt::format("<pose frame='{}'>: the frame attribute is ignored, as Gazebo "
                             "classic ignores it",
                             *frame)));
  }
  const std::string* relative_to = pose->Attribute("relative_to");
  return relative_to ? Trim(*relative_to) : "";
}

Pose Loader::WorldPose(const Doc& doc, const XmlElement* pose) {
  const std::string relative_to = RelativeTo(doc, pose);
  if (!relative_to.empty() && relative_to != "world") {
    Error(doc, pose->line,
          fmt::format("<pose relative_to='{}'> at world level is not supported — give the pose "
                      "in world coordinates",
                      relative_to));
  }
  return PoseValue(doc, pose);
}

double Loader::NumberOr(const Doc& doc,
                        const XmlElement* parent,
                        std::string_view child,
                        double fallback,
                        bool positive) {
  const XmlElement* e = parent ? parent->Child(child) : nullptr;
  if (!e) return fallback;
  const auto value = positive ? PositiveNumber(doc, *e, fmt::format("{}", fallback))
                              : Number(doc, *e, fmt::format("{}", fallback));
  return value.value_or(fallback);
}

// ---------------------------------------------------------------------------------------------
// Files.

const Doc* Loader::LoadSdf(const std::string& path, const std::string& model_dir) {
  const std::string key = fs::path(path).lexically_normal().string();
  const auto it = docs_.find(key);
  if (it != docs_.end()) return it->second.get();
  std::unique_ptr<Doc> doc;
  try {
    doc = std::make_unique<Doc>();
    doc->xml = ReadXmlFile(path);
    doc->dir = ParentDir(path);
    doc->model_dir = model_dir;
  } catch (const InputError& e) {
    AddError(e.what());
    doc.reset();
  }
  if (doc) {
    const XmlElement& root = doc->xml.root;
    const std::string* version = root.Attribute("version");
    const auto parsed = version ? ParseVersion(Trim(*version)) : std::nullopt;
    if (root.name != "sdf") {
      Error(*doc, root.line,
            fmt::format("root element is <{}> — an SDF file starts with "
                        "<sdf version=\"1.6\">",
                        root.name));
      doc.reset();
    } else if (!parsed || parsed->first != 1) {
      Error(*doc, root.line,
            fmt::format("<sdf> needs a version attribute 1.4 to 1.7 (got '{}') — "
                        "write <sdf version=\"1.6\">",
                        version ? *version : ""));
      doc.reset();
    } else if (parsed->second < 4 || parsed->second > 7) {
      Note(AtPlace(path, root.line,
                   fmt::format("SDF version {} is read as 1.4–1.7 (vantage "
                               "implements those)",
                               *version)));
    }
  }
  const Doc* result = doc.get();
  docs_[key] = std::move(doc);
  return result;
}

std::string Loader::ModelFileInDir(const std::string& dir, const Doc& from, int line) {
  const std::string config_path = (fs::path(dir) / "model.config").string();
  std::string chosen;
  if (IsFile(config_path)) {
    try {
      const XmlDocument config = ReadXmlFile(config_path);
      std::pair<int, int> best{-1, -1};
      for (const XmlElement* sdf : config.root.Children("sdf")) {
        const std::string* version = sdf->Attribute("version");
        const auto parsed = version ? ParseVersion(Trim(*version)) : std::nullopt;
        const std::pair<int, int> v = parsed.value_or(std::make_pair(0, 0));
        if (!sdf->Trimmed().empty() && v > best) {
          best = v;
          chosen = (fs::path(dir) / sdf->Trimmed()).string();
        }
      }
      if (!chosen.empty() && !IsFile(chosen)) {
        Error(config_path, config.root.line,
              fmt::format("model.config names '{}', which does not exist — fix its <sdf> element",
                          chosen));
        return "";
      }
    } catch (const InputError& e) {
      AddError(e.what());
      return "";
    }
  }
  if (chosen.empty()) chosen = (fs::path(dir) / "model.sdf").string();
  if (!IsFile(chosen)) {
    Error(from, line,
          fmt::format("model folder '{}' has no model.sdf and no model.config naming "
                      "its SDF file",
                      dir));
    return "";
  }
  return chosen;
}

std::optional<std::string> Loader::ResolveModelUri(const std::string& uri,
                                                   const Doc& from,
                                                   std::vector<std::string>* searched) {
  std::string rest;
  if (uri.rfind("model://", 0) == 0) {
    rest = uri.substr(8);
    const size_t slash = rest.find('/');
    const std::string name = rest.substr(0, slash);
    const std::string sub = slash == std::string::npos ? "" : rest.substr(slash + 1);
    if (name.empty()) return std::nullopt;
    for (const std::string& dir : model_dirs_) {
      if (searched) searched->push_back(dir);
      const fs::path model_dir = fs::path(dir) / name;
      if (!IsDirectory(model_dir.string())) continue;
      const fs::path candidate = sub.empty() ? model_dir : model_dir / sub;
      std::error_code ec;
      if (fs::exists(candidate, ec)) return candidate.lexically_normal().string();
    }
    return std::nullopt;
  }
  if (uri.find("://") != std::string::npos && uri.rfind("file://", 0) != 0) return std::nullopt;
  rest = uri.rfind("file://", 0) == 0 ? uri.substr(7) : uri;
  if (rest.empty()) return std::nullopt;
  std::vector<std::string> bases;
  if (fs::path(rest).is_absolute()) {
    bases.emplace_back();
  } else {
    bases.push_back(from.dir);
    if (!from.model_dir.empty()) bases.push_back(from.model_dir);
    bases.push_back(ParentDir(path_));
  }
  for (const std::string& base : bases) {
    const fs::path candidate = base.empty() ? fs::path(rest) : fs::path(base) / rest;
    if (searched) searched->push_back(candidate.parent_path().string());
    std::error_code ec;
    if (fs::exists(candidate, ec)) return candidate.lexically_normal().string();
  }
  return std::nullopt;
}

std::optional<std::string> Loader::ResolveResourceUri(const std::string& uri, const Doc& from) {
  if (uri.rfind("model://", 0) == 0) return ResolveModelUri(uri, from, nullptr);
  if (uri.find("://") != std::string::npos && uri.rfind("file://", 0) != 0) return std::nullopt;
  const std::string rest = uri.rfind("file://", 0) == 0 ? uri.substr(7) : uri;
  if (rest.empty()) return std::nullopt;
  std::error_code ec;
  if (fs::path(rest).is_absolute())
    return fs::exists(rest, ec) ? std::optional<std::string>(rest) : std::nullopt;
  // GAZEBO.md: --resource-path, GAZEBO_RESOURCE_PATH, the parent of each model directory; then
  // the file's own model folder and folder.
  std::vector<std::string> bases = resource_dirs_;
  if (!from.model_dir.empty()) bases.push_back(from.model_dir);
  bases.push_back(from.dir);
  for (const std::string& base : bases) {
    const fs::path candidate = fs::path(base) / rest;
    if (fs::exists(candidate, ec)) return candidate.lexically_normal().string();
  }
  return std::nullopt;
}

IncludeResult Loader::ResolveInclude(const Doc& doc, const XmlElement& include) {
  IncludeResult result;
  const XmlElement* uri_element = include.Child("uri");
  std::string uri = uri_element ? uri_element->Trimmed() : "";
  if (uri.empty()) {
    Error(doc, include.line, "<include> has no <uri> — add <uri>model://NAME</uri>");
    return result;
  }
  while (uri.size() > 1 && uri.back() == '/') uri.pop_back();
  const int line = uri_element->line;
  const XmlElement* name_element = include.Child("name");
  const std::string base = UriBaseName(uri);
  if (include.Attribute("merge") && *include.Attribute("merge") == "true") {
    Note(AtPlace(doc.xml.path, include.line,
                 fmt::format("<include merge='true'> of {}: read as a nested model", uri)));
  }
  std::vector<std::string> searched;
  const std::optional<std::string> location = ResolveModelUri(uri, doc, &searched);
  if (!location) {
    if (IsLightModelName(base)) {
      Note(
          AtPlace(doc.xml.path, line,
                  fmt::format("{} is not on the model path: skipped (a light, no geometry)", uri)));
      result.kind = IncludeResult::Kind::kSkipped;
      return result;
    }
    if (base == "ground_plane") {
      Note(AtPlace(doc.xml.path, line,
                   fmt::format("{} is not on the model path: read as Gazebo's ground plane, a "
                               "{} m x {} m plane at z = 0",
                               uri, kGroundPlaneSize, kGroundPlaneSize)));
      result.kind = IncludeResult::Kind::kGroundPlane;
      result.name = name_element ? name_element->Trimmed() : "ground_plane";
      return result;
    }
    std::string where;
    if (uri.rfind("model://", 0) == 0) {
      where = searched.empty() ? "no model path is set" : "looked in " + Join(searched, ", ");
    } else if (uri.find("://") != std::string::npos && uri.rfind("file://", 0) != 0) {
      where = "vantage reads models from disk only";
    } else {
      where = "looked in " + Join(searched, ", ");
    }
    Error(doc, line,
          fmt::format("<include> model '{}' not found ({}) — add its folder's parent with "
                      "--model-path or GAZEBO_MODEL_PATH",
                      uri, where));
    return result;
  }
  std::string file = *location;
  std::string model_dir = ParentDir(file);
  if (IsDirectory(file)) {
    model_dir = file;
    file = ModelFileInDir(file, doc, line);
    if (file.empty()) return result;
  }
  const Doc* model_doc = LoadSdf(file, model_dir);
  if (!model_doc) return result;
  const std::vector<const XmlElement*> models = model_doc->xml.root.Children("model");
  if (models.empty()) {
    if (!model_doc->xml.root.Children("light").empty()) {
      Note(AtPlace(doc.xml.path, line, fmt::format("{} holds only a light: skipped", uri)));
      result.kind = IncludeResult::Kind::kSkipped;
      return result;
    }
    if (!model_doc->xml.root.Children("actor").empty()) {
      Note(AtPlace(doc.xml.path, line,
                   fmt::format("{} is an actor: skipped (vantage reads static scenes)", uri)));
      result.kind = IncludeResult::Kind::kSkipped;
      return result;
    }
    Error(*model_doc, model_doc->xml.root.line,
          fmt::format("no <model> element (included from {}:{}) — an included file holds one "
                      "<model>",
                      doc.xml.path, line));
    return result;
  }
  if (models.size() > 1) {
    Error(*model_doc, models[1]->line,
          fmt::format("{} <model> elements (included from {}:{}) — an included file holds one",
                      models.size(), doc.xml.path, line));
  }
  const std::string* own_name = models[0]->Attribute("name");
  result.name = name_element ? name_element->Trimmed() : own_name ? Trim(*own_name) : base;
  if (result.name.empty()) {
    Error(*model_doc, models[0]->line, "<model> has no name attribute — add name=\"...\"");
    return result;
  }
  result.kind = IncludeResult::Kind::kModel;
  result.doc = model_doc;
  result.model = models[0];
  return result;
}

// ---------------------------------------------------------------------------------------------
// Walk.

Pose Loader::FrameInModel(const std::string& name,
                          std::map<std::string, FrameEntry>& entries,
                          std::map<std::string, Pose>& resolved,
                          std::set<std::string>& visiting,
                          const std::string& model,
                          const Doc& doc,
                          int line) {
  if (name.empty() || name == "__model__" || name == model) return Pose{};
  if (const auto it = resolved.find(name); it != resolved.end()) return it->second;
  const auto entry_it = entries.find(name);
  if (entry_it == entries.end()) {
    Error(doc, line,
          fmt::format("relative_to '{}' names no link, model or frame of model '{}' — name one of "
                      "its own frames (scoped names a::b are not supported)",
                      name, model));
    return Pose{};
  }
  const FrameEntry& entry = entry_it->second;
  if (!visiting.insert(name).second) {
    Error(*entry.doc, entry.line,
          fmt::format("frame '{}' of model '{}' is placed relative to itself (a relative_to "
                      "cycle) — break the cycle",
                      name, model));
    return Pose{};
  }
  std::string parent = entry.default_parent;
  if (entry.honours_relative_to) {
    const std::string relative_to = RelativeTo(*entry.doc, entry.pose);
    if (!relative_to.empty()) parent = relative_to;
  }
  const Pose parent_pose = FrameInModel(parent, entries, resolved, visiting, model, *entry.doc,
                                        entry.pose ? entry.pose->line : entry.line);
  Pose pose = parent_pose * PoseValue(*entry.doc, entry.pose);
  visiting.erase(name);
  resolved[name] = pose;
  return pose;
}

void Loader::VisitModel(const Doc& doc, const XmlElement& model, const ModelContext& context) {
  if (context.sink.models) context.sink.models->emplace_back(context.scoped, context.hidden);
  const std::string* own_name = model.Attribute("name");
  const std::string type_name = own_name ? Trim(*own_name) : context.scoped;
  if (model.Attribute("placement_frame")) {
    Note(AtPlace(doc.xml.path, model.line,
                 fmt::format("model '{}': placement_frame is not applied", context.scoped)));
  }

  // The model's named frames, for relative_to. Includes are resolved here, once.
  std::map<std::string, FrameEntry> entries;
  std::map<const XmlElement*, IncludeResult> includes;
  const auto add_entry = [&](const std::string& name, const XmlElement& element, FrameEntry entry) {
    if (name.empty()) {
      Error(doc, element.line,
            fmt::format("<{}> in model '{}' has no name — add name=\"...\"", element.name,
                        context.scoped));
      return;
    }
    if (!entries.emplace(name, entry).second) {
      Error(doc, element.line,
            fmt::format("model '{}' has two children named '{}' — names must be unique",
                        context.scoped, name));
    }
  };
  bool has_depth_sensor = false;
  for (const XmlElement& child : model.children) {
    const std::string* name_attribute = child.Attribute("name");
    const std::string name = name_attribute ? Trim(*name_attribute) : "";
    if (child.name == "link" || child.name == "model") {
      add_entry(name, child, FrameEntry{&doc, child.Child("pose"), true, "", child.line});
      if (child.name == "link") {
        for (const XmlElement* sensor : child.Children("sensor")) {
          const std::string* type = sensor->Attribute("type");
          if (type && IsDepthSensorType(*type)) has_depth_sensor = true;
        }
      }
    } else if (child.name == "frame") {
      const std::string* attached_to = child.Attribute("attached_to");
      add_entry(name, child,
                FrameEntry{&doc, child.Child("pose"), true, attached_to ? Trim(*attached_to) : "",
                           child.line});
    } else if (child.name == "include") {
      IncludeResult result = ResolveInclude(doc, child);
      if (result.kind == IncludeResult::Kind::kModel && child.Child("pose") == nullptr) {
        // No include pose: the model's own <pose>, relative to the parent model.
        add_entry(result.name, child,
                  FrameEntry{result.doc, result.model->Child("pose"), false, "", child.line});
      } else if (result.kind != IncludeResult::Kind::kSkipped &&
                 result.kind != IncludeResult::Kind::kFailed) {
        add_entry(result.name, child, FrameEntry{&doc, child.Child("pose"), true, "", child.line});
      }
      includes[&child] = std::move(result);
    }
  }
  // GAZEBO.md: sensor models' bodies never occlude; the model holding a depth sensor (and what
  // it nests) contributes no geometry.
  const bool hidden = context.hidden || has_depth_sensor;

  std::map<std::string, Pose> resolved;
  std::set<std::string> visiting;
  const auto in_model = [&](const std::string& name, int line) {
    return FrameInModel(name, entries, resolved, visiting, context.scoped, doc, line);
  };
  // Pose of a link's child (visual, sensor) in the link: relative_to defaults to the link.
  const auto link_from_child = [&](const std::string& link, const XmlElement* pose) {
    const std::string relative_to = RelativeTo(doc, pose);
    Pose value = PoseValue(doc, pose);
    if (relative_to.empty() || relative_to == link) return value;
    return in_model(link, pose->line).Inverse() * in_model(relative_to, pose->line) * value;
  };

  for (const XmlElement& child : model.children) {
    const std::string* name_attribute = child.Attribute("name");
    const std::string name = name_attribute ? Trim(*name_attribute) : "";
    if (child.name == "link" && !name.empty()) {
      const Pose model_from_link = in_model(name, child.line);
      if (!hidden && context.sink.visuals) {
        for (const XmlElement* visual : child.Children("visual")) {
          const std::string* visual_name = visual->Attribute("name");
          VisualRecord record;
          record.model = context.scoped;
          record.link = name;
          record.name = visual_name ? *visual_name : "";
          record.world_from_visual = context.world_from_model * model_from_link *
                                     link_from_child(name, visual->Child("pose"));
          record.doc = &doc;
          record.element = visual;
          record.site = context.site;
          context.sink.visuals->push_back(std::move(record));
        }
      }
      if (context.sink.sensors) {
        for (const XmlElement* sensor : child.Children("sensor")) {
          const std::string* type = sensor->Attribute("type");
          if (!type || !IsDepthSensorType(*type)) continue;
          const std::string* sensor_name = sensor->Attribute("name");
          SensorRecord record;
          record.model = context.scoped;
          record.type_name = type_name;
          record.sensor_name = sensor_name ? *sensor_name : "";
          record.world_from_model = context.world_from_model;
          record.model_from_camera = model_from_link * link_from_child(name, sensor->Child("pose"));
          record.doc = &doc;
          record.element = sensor;
          record.site = context.site;
          context.sink.sensors->push_back(std::move(record));
        }
      }
    } else if (child.name == "model" && !name.empty()) {
      ModelContext nested = context;
      nested.scoped = context.scoped + "::" + name;
      nested.world_from_model = context.world_from_model * in_model(name, child.line);
      nested.hidden = hidden;
      VisitModel(doc, child, nested);
    } else if (child.name == "include") {
      const IncludeResult& result = includes[&child];
      if (result.kind == IncludeResult::Kind::kSkipped ||
          result.kind == IncludeResult::Kind::kFailed || result.name.empty()) {
        continue;
      }
      ModelContext nested = context;
      nested.scoped = context.scoped + "::" + result.name;
      nested.world_from_model = context.world_from_model * in_model(result.name, child.line);
      nested.hidden = hidden;
      if (result.kind == IncludeResult::Kind::kGroundPlane) {
        if (nested.sink.models) nested.sink.models->emplace_back(nested.scoped, hidden);
        if (!hidden && nested.sink.visuals) {
          nested.sink.visuals->push_back(VisualRecord{nested.scoped, "", "ground_plane",
                                                      nested.world_from_model, &doc, nullptr,
                                                      context.site});
        }
      } else {
        VisitModel(*result.doc, *result.model, nested);
      }
    }
  }
}

void Loader::VisitWorldEntity(const Doc& doc, const XmlElement& e) {
  ModelContext context;
  context.sink = Sink{&visuals_, &sensors_, &models_};
  context.site = Site{doc.xml.path, e.line};
  const XmlElement* model = &e;
  const Doc* model_doc = &doc;
  if (e.name == "include") {
    const IncludeResult result = ResolveInclude(doc, e);
    if (result.kind == IncludeResult::Kind::kSkipped || result.kind == IncludeResult::Kind::kFailed)
      return;
    context.scoped = result.name;
    if (result.kind == IncludeResult::Kind::kModel) {
      model = result.model;
      model_doc = result.doc;
      // GAZEBO.md: the include's <pose> replaces the model file's own.
      const XmlElement* include_pose = e.Child("pose");
      context.world_from_model = include_pose ? WorldPose(doc, include_pose)
                                              : WorldPose(*result.doc, result.model->Child("pose"));
    } else {
      context.world_from_model = WorldPose(doc, e.Child("pose"));
    }
  } else {
    const std::string* name = e.Attribute("name");
    context.scoped = name ? Trim(*name) : "";
    if (context.scoped.empty()) {
      Error(doc, e.line, "<model> has no name attribute — add name=\"...\"");
      return;
    }
    context.world_from_model = WorldPose(doc, e.Child("pose"));
  }
  if (!top_names_.insert(context.scoped).second) {
    Error(doc, e.line,
          fmt::format("a second model named '{}' — give each model a unique name (<include> "
                      "takes <name>)",
                      context.scoped));
    return;
  }
  if (model == &e && e.name == "include") {  // ground plane stand-in
    models_.emplace_back(context.scoped, false);
    visuals_.push_back(VisualRecord{context.scoped, "", "ground_plane", context.world_from_model,
                                    &doc, nullptr, context.site});
    return;
  }
  VisitModel(*model_doc, *model, context);
}

// ---------------------------------------------------------------------------------------------
// Plugin parameters (GAZEBO.md, "The plugin's parameters").

void Loader::ReadPlugin() {
  static const std::set<std::string> kKnown = {"numberOfIntendedSensors",
                                               "ransacNumberOfIterations",
                                               "ransacSurfacePercentageStopThreshold",
                                               "voxelGridFilterLeafSize",
                                               "sensorOrientationRandomRoll",
                                               "sensorDataSegmentationColorRGB",
                                               "sceneModelPath",
                                               "observationPoint",
                                               "numberOfSamplingSensors"};
  const Doc& doc = *world_doc_;
  // Any <plugin> of the world file, at any depth, with these children.
  std::vector<const XmlElement*> stack = {world_};
  std::vector<const XmlElement*> plugins;
  while (!stack.empty()) {
    const XmlElement* e = stack.back();
    stack.pop_back();
    for (const XmlElement& child : e->children) {
      if (child.name == "plugin") {
        plugins.push_back(&child);
      } else {
        stack.push_back(&child);
      }
    }
  }
  std::sort(plugins.begin(), plugins.end(),
            [](const XmlElement* a, const XmlElement* b) { return a->line < b->line; });
  std::map<std::string, const XmlElement*> params;
  constexpr int64_t kMaxCount = 1'000'000'000;
  // In document order, so that errors come in the file's order.
  for (const XmlElement* plugin : plugins) {
    for (const XmlElement& child : plugin->children) {
      if (!kKnown.contains(child.name)) continue;
      const auto [it, inserted] = params.emplace(child.name, &child);
      if (!inserted) {
        Error(doc, child.line,
              fmt::format("<{}> is given twice (first at line {}) — keep one", child.name,
                          it->second->line));
        continue;
      }
      const XmlElement* e = &child;
      const std::string& name = child.name;
      if (name == "numberOfIntendedSensors") {
        if (const auto v = Integer(doc, *e, 1, kMaxCount)) problem_.n = static_cast<int>(*v);
      } else if (name == "ransacNumberOfIterations") {
        if (const auto v = Integer(doc, *e, 1, kMaxCount))
          problem_.ransac_iterations = static_cast<int>(*v);
      } else if (name == "numberOfSamplingSensors") {
        if (const auto v = Integer(doc, *e, 1, kMaxCount))
          problem_.expected_candidates = static_cast<int>(*v);
      } else if (name == "ransacSurfacePercentageStopThreshold") {
        if (const auto v = Number(doc, *e, "90")) {
          if (*v < 0 || *v > 100) {
            Error(doc, e->line,
                  fmt::format("<{}> {} must be a percentage from 0 to 100", name, e->Trimmed()));
          } else {
            problem_.ransac_stop_coverage = *v / 100.0;
          }
        }
      } else if (name == "voxelGridFilterLeafSize") {
        if (const auto v = PositiveNumber(doc, *e, "0.005")) problem_.cell_size = *v;
      } else if (name == "sensorOrientationRandomRoll") {
        if (const auto v = Boolean(doc, *e)) problem_.random_roll = *v;
      } else if (name == "observationPoint") {
        if (const auto v = Vector(doc, *e, false, "0 0 0")) problem_.observation_point = *v;
      } else if (name == "sensorDataSegmentationColorRGB") {
        ReadSegmentationColour(doc, *e);
      } else if (name == "sceneModelPath") {
        // "PATH|A+B": the names after '|' are the target models.
        const std::string text = e->Trimmed();
        const size_t bar = text.find('|');
        scene_model_names_ = bar == std::string::npos ? std::vector<std::string>{}
                                                      : SplitList(text.substr(bar + 1), '+');
        scene_model_site_ = Site{doc.xml.path, e->line};
      }
    }
  }
  if (!params.contains("sensorDataSegmentationColorRGB") && !plugins.empty())
    segmentation_site_ = Site{doc.xml.path, plugins.front()->line};
}

void Loader::ReadSegmentationColour(const Doc& doc, const XmlElement& e) {
  segmentation_site_ = Site{doc.xml.path, e.line};
  is_segmentation_given_ = true;
  const auto v = Numbers(doc, e, 3, "0 255 0");
  if (!v) return;
  bool ok = true;
  for (size_t i = 0; i < 3; ++i) {
    const double c = (*v)[i];
    ok = ok && c >= 0 && c <= 255 && c == std::round(c);
    if (ok) segmentation_colour_[i] = static_cast<int>(c);
  }
  if (!ok) {
    Error(doc, e.line,
          fmt::format("<{}> '{}' must be three whole numbers from 0 to 255 — write e.g. "
                      "<{}>0 255 0</{}>",
                      e.name, e.Trimmed(), e.name, e.name));
    segmentation_colour_ = kDefaultSegmentationColour;
  }
}

// ---------------------------------------------------------------------------------------------
// Sensors and populations.

std::optional<std::string> Loader::AddSensorType(const SensorRecord& record,
                                                 const std::string& id) {
  const Doc& doc = *record.doc;
  const XmlElement& sensor = *record.element;
  const XmlElement* camera = sensor.Child("camera");
  if (!camera) {
    Error(doc, sensor.line,
          fmt::format("depth <sensor name='{}'> has no <camera> — add <camera> with "
                      "<horizontal_fov>, <image> and <clip>",
                      record.sensor_name));
    return std::nullopt;
  }
  // SDF's defaults where an element is absent (Gazebo uses them too).
  const double hfov = NumberOr(doc, camera, "horizontal_fov", 1.047, true);
  const XmlElement* image = camera->Child("image");
  int width = 320;
  int height = 240;
  if (const XmlElement* e = image ? image->Child("width") : nullptr) {
    width = static_cast<int>(Integer(doc, *e, 1, 1'000'000).value_or(width));
  }
  if (const XmlElement* e = image ? image->Child("height") : nullptr) {
    height = static_cast<int>(Integer(doc, *e, 1, 1'000'000).value_or(height));
  }
  const XmlElement* clip = camera->Child("clip");
  const double near = NumberOr(doc, clip, "near", 0.1, true);
  const double far = NumberOr(doc, clip, "far", 100.0, true);
  double fps = 0;
  if (const XmlElement* e = sensor.Child("update_rate")) {
    if (const auto v = Number(doc, *e, "30")) {
      if (*v < 0) {
        Error(doc, e->line, fmt::format("<update_rate> {} must be >= 0 [Hz]", e->Trimmed()));
      } else {
        fps = *v;
      }
    }
  }
  SensorType type = SensorType::FromFov(id, width, height, hfov, std::nullopt, near, far);
  type.fps = fps;
  try {
    type.Validate(fmt::format("{}:{}", doc.xml.path, sensor.line));
  } catch (const InputError& e) {
    AddError(e.what());
    return std::nullopt;
  }
  // One type per distinct sensor model; a different model of the same name gets a suffix.
  const auto same = [&](const SensorType& t) {
    return t.width == type.width && t.height == type.height && t.fx == type.fx && t.fy == type.fy &&
           t.cx == type.cx && t.cy == type.cy && t.near == type.near && t.far == type.far &&
           t.fps == type.fps;
  };
  for (int suffix = 1;; ++suffix) {
    const std::string candidate = suffix == 1 ? id : fmt::format("{}_{}", id, suffix);
    const auto found = std::find_if(problem_.sensor_types.begin(), problem_.sensor_types.end(),
                                    [&](const SensorType& t) { return t.id == candidate; });
    const SensorType* existing = found == problem_.sensor_types.end() ? nullptr : &*found;
    if (!existing) {
      type.id = candidate;
      type.name = candidate;
      if (suffix > 1) {
        Note(AtPlace(doc.xml.path, sensor.line,
                     fmt::format("sensor model '{}' differs from another of the same name: its "
                                 "type is called '{}'",
                                 id, candidate)));
      }
      problem_.sensor_types.push_back(type);
      return candidate;
    }
    if (same(*existing)) return candidate;
  }
}

void Loader::ReadPopulation(const Doc& doc, const XmlElement& e) {
  Population population;
  population.file = doc.xml.path;
  population.line = e.line;
  const std::string* name = e.Attribute("name");
  population.name = name ? Trim(*name) : "";
  if (population.name.empty()) {
    Error(doc, e.line, "<population> has no name attribute — add name=\"...\"");
    return;
  }
  const std::string what = fmt::format("population '{}'", population.name);
  if (!population_names_.insert(population.name).second) {
    Error(doc, e.line, fmt::format("a second {} — give each population a unique name", what));
    return;
  }
  bool ok = true;
  const auto fail = [&](int line, const std::string& message) {
    Error(doc, line, fmt::format("{}: {}", what, message));
    ok = false;
  };

  population.pose = WorldPose(doc, e.Child("pose"));
  // Gazebo's regions are <box> and <cylinder>; another shape is a mistake, not "no region".
  for (const XmlElement& child : e.children) {
    static const std::set<std::string> kOtherShapes = {
        "sphere", "plane", "mesh", "capsule", "ellipsoid", "polyline", "heightmap"};
    if (kOtherShapes.contains(child.name)) {
      fail(child.line,
           fmt::format("<{}> is not a population region — use <box> or <cylinder>", child.name));
    }
  }
  const XmlElement* box = e.Child("box");
  const XmlElement* cylinder = e.Child("cylinder");
  if (box && cylinder) fail(cylinder->line, "has both <box> and <cylinder> — keep one region");
  if (box) {
    population.region = RegionShape::kBox;
    const XmlElement* size = box->Child("size");
    if (!size) {
      fail(box->line, "<box> has no <size> — add <size>sx sy sz</size>");
    } else if (const auto v = Vector(doc, *size, true, "0.5 0.5 0.2")) {
      population.box_size = *v;
    } else {
      ok = false;
    }
  } else if (cylinder) {
    population.region = RegionShape::kCylinder;
    const XmlElement* radius = cylinder->Child("radius");
    const XmlElement* length = cylinder->Child("length");
    if (!radius || !length) {
      fail(cylinder->line, "<cylinder> needs <radius> and <length>");
    } else {
      const auto r = PositiveNumber(doc, *radius, "0.35");
      const auto l = PositiveNumber(doc, *length, "0.1");
      if (r && l) {
        population.radius = *r;
        population.length = *l;
      } else {
        ok = false;
      }
    }
  } else {
    population.region = RegionShape::kNone;
  }

  const XmlElement* distribution = e.Child("distribution");
  const XmlElement* type = distribution ? distribution->Child("type") : nullptr;
  if (!type) {
    fail(distribution ? distribution->line : e.line,
         "has no <distribution><type> — add random, uniform, grid, linear-x, linear-y or "
         "linear-z");
  } else {
    static const std::map<std::string, Distribution> kTypes = {
        {"random", Distribution::kRandom},    {"uniform", Distribution::kUniform},
        {"grid", Distribution::kGrid},        {"linear-x", Distribution::kLinearX},
        {"linear-y", Distribution::kLinearY}, {"linear-z", Distribution::kLinearZ}};
    const auto it = kTypes.find(type->Trimmed());
    if (it == kTypes.end()) {
      fail(type->line, fmt::format("unknown <distribution><type> '{}' — use random, uniform, "
                                   "grid, linear-x, linear-y or linear-z",
                                   type->Trimmed()));
    } else {
      population.distribution = it->second;
    }
  }
  const bool is_grid = population.distribution == Distribution::kGrid;
  const bool is_linear = population.distribution == Distribution::kLinearX ||
                         population.distribution == Distribution::kLinearY ||
                         population.distribution == Distribution::kLinearZ;
  if (ok && is_grid) {
    // Gazebo reads rows/cols/step for grid only; SDF defaults 1, 1, (0.5 0.5 0).
    population.rows = 1;
    population.cols = 1;
    population.step = Vec3(0.5, 0.5, 0);
    if (const XmlElement* rows = distribution->Child("rows")) {
      if (const auto v = Integer(doc, *rows, 1, 1'000'000))
        population.rows = static_cast<int>(*v);
      else
        ok = false;
    }
    if (const XmlElement* cols = distribution->Child("cols")) {
      if (const auto v = Integer(doc, *cols, 1, 1'000'000))
        population.cols = static_cast<int>(*v);
      else
        ok = false;
    }
    if (const XmlElement* step = distribution->Child("step")) {
      if (const auto v = Vector(doc, *step, false, "0.5 0.5 0"))
        population.step = *v;
      else
        ok = false;
    }
    if (cylinder) {
      fail(cylinder->line,
           "distribution 'grid' takes no region — remove the <cylinder> "
           "(rows, cols and step place the grid)");
    }
  } else if (ok) {
    // Supported combinations: Gazebo's Population.cc (and PopulationPositions).
    if (!box && !cylinder) {
      fail(e.line, fmt::format("distribution '{}' needs a region — add <box><size>…</size></box> "
                               "or <cylinder>…</cylinder>",
                               type->Trimmed()));
    } else if (is_linear && cylinder) {
      fail(cylinder->line,
           fmt::format("distribution '{}' works in a <box> region only", type->Trimmed()));
    }
    const XmlElement* count = e.Child("model_count");
    if (!count) {
      fail(e.line, "has no <model_count> — add <model_count>N</model_count>");
    } else if (const auto v = Integer(doc, *count, 1, 1'000'000)) {
      population.count = static_cast<int>(*v);
    } else {
      ok = false;
    }
  }

  // The sensor model: one <include> or <model>. Its body is hidden; its depth sensor gives the
  // population's type and camera offset (link · sensor, without the model's own pose: Gazebo
  // sets the clone's pose, GAZEBO.md).
  std::vector<const XmlElement*> models = e.Children("include");
  for (const XmlElement* m : e.Children("model")) models.push_back(m);
  if (models.size() != 1) {
    fail(e.line, fmt::format("holds {} models — a population holds one <include> or <model>",
                             models.size()));
    return;
  }
  std::vector<SensorRecord> sensors;
  ModelContext context;
  context.sink = Sink{nullptr, &sensors, nullptr};
  context.hidden = true;
  context.site = Site{doc.xml.path, e.line};
  if (models[0]->name == "include") {
    const IncludeResult result = ResolveInclude(doc, *models[0]);
    if (result.kind != IncludeResult::Kind::kModel) {
      if (result.kind != IncludeResult::Kind::kFailed)
        fail(models[0]->line, "its model has no depth sensor");
      return;
    }
    context.scoped = result.name;
    VisitModel(*result.doc, *result.model, context);
  } else {
    const std::string* model_name = models[0]->Attribute("name");
    context.scoped = model_name ? Trim(*model_name) : "";
    if (context.scoped.empty()) {
      fail(models[0]->line, "<model> has no name attribute — add name=\"...\"");
      return;
    }
    VisitModel(doc, *models[0], context);
  }
  if (sensors.size() != 1) {
    fail(models[0]->line,
         fmt::format("model '{}' has {} depth sensors — a population's model holds exactly one "
                     "<sensor type=\"depth\">",
                     context.scoped, sensors.size()));
    return;
  }
  const SensorRecord& sensor = sensors[0];
  const std::optional<std::string> id = AddSensorType(sensor, sensor.type_name);
  if (!id || !ok) return;
  population.sensor_type = *id;
  population.model_from_camera = sensor.world_from_model * sensor.model_from_camera;
  problem_.populations.push_back(std::move(population));
}

// ---------------------------------------------------------------------------------------------
// Scene.

MaterialColours Loader::ColoursOf(const VisualRecord& visual) {
  MaterialColours colours;
  const XmlElement* material = visual.element ? visual.element->Child("material") : nullptr;
  if (!material) return colours;
  const Doc& doc = *visual.doc;
  if (const XmlElement* script = material->Child("script")) {
    const XmlElement* name_element = script->Child("name");
    const std::string name = name_element ? name_element->Trimmed() : "";
    std::vector<std::string> uris;
    for (const XmlElement* uri : script->Children("uri")) {
      const std::string text = uri->Trimmed();
      if (text.empty() || text == "__default__") continue;
      uris.push_back(text);
      const std::optional<std::string> location = ResolveResourceUri(text, doc);
      if (!location) {
        Note(AtPlace(doc.xml.path, uri->line,
                     fmt::format("material script {} not found on the resource path (--resource-"
                                 "path, GAZEBO_RESOURCE_PATH)",
                                 text)));
        continue;
      }
      std::vector<std::string> files;
      if (IsDirectory(*location)) {
        std::error_code ec;
        for (const auto& entry : fs::directory_iterator(*location, ec)) {
          if (entry.path().extension() == ".material") files.push_back(entry.path().string());
        }
        std::sort(files.begin(), files.end());
      } else {
        files.push_back(*location);
      }
      for (const std::string& file : files) {
        if (!material_files_.insert(file).second) continue;
        const size_t known = materials_.problems.size();
        if (!materials_.LoadFile(file)) {
          Note(fmt::format("{}: cannot read the material script", file));
        }
        for (size_t i = known; i < materials_.problems.size(); ++i) Note(materials_.problems[i]);
      }
    }
    if (!name.empty()) {
      if (const MaterialColours* found = materials_.Find(name)) {
        colours = *found;
      } else {
        Note(AtPlace(doc.xml.path, name_element->line,
                     fmt::format("material '{}' is not defined in {}: its visuals have no colour "
                                 "(never targets)",
                                 name, uris.empty() ? "any loaded script" : Join(uris, ", "))));
      }
    }
  }
  // Gazebo applies inline colours after the script.
  MaterialColours inline_colours;
  const auto read = [&](const char* key, std::optional<Rgb>* slot) {
    const XmlElement* e = material->Child(key);
    if (!e) return;
    const size_t count = SplitWords(e->text).size();
    const auto values = Numbers(doc, *e, count == 3 ? 3 : 4, "0 1 0 1");
    if (values) *slot = Rgb{(*values)[0], (*values)[1], (*values)[2]};
  };
  read("ambient", &inline_colours.ambient);
  read("diffuse", &inline_colours.diffuse);
  read("emissive", &inline_colours.emissive);
  colours.Override(inline_colours);
  return colours;
}

const TriangleMesh* Loader::LoadMesh(const std::string& path, const Doc& doc, int line) {
  const auto it = meshes_.find(path);
  if (it != meshes_.end()) return it->second.get();
  std::unique_ptr<TriangleMesh> mesh;
  try {
    mesh = std::make_unique<TriangleMesh>(LoadMeshFile(path));
  } catch (const InputError& e) {
    Error(doc, line, fmt::format("<mesh> cannot be loaded: {}", e.what()));
  }
  const TriangleMesh* result = mesh.get();
  meshes_[path] = std::move(mesh);
  return result;
}

std::optional<TriangleMesh> Loader::GeometryOf(const VisualRecord& visual) {
  if (!visual.element) return MakePlane(kGroundPlaneSize, kGroundPlaneSize);
  const Doc& doc = *visual.doc;
  const XmlElement* geometry = visual.element->Child("geometry");
  std::string what = fmt::format("visual '{}' of model '{}'", visual.name, visual.model);
  if (doc.xml.path != visual.site.file)
    what += fmt::format(" (included at {}:{})", visual.site.file, visual.site.line);
  if (!geometry || geometry->children.empty()) {
    Error(doc, visual.element->line,
          fmt::format("{} has no <geometry> — add <box>, <cylinder>, <sphere>, <plane> or <mesh>",
                      what));
    return std::nullopt;
  }
  const XmlElement& shape = geometry->children.front();
  // SDF's chord error rule for primitives (SYSTEM.md): below F / 10.
  const double chord = problem_.cell_size / 10.0;
  if (shape.name == "box") {
    const XmlElement* size = shape.Child("size");
    if (!size) {
      Error(doc, shape.line, "<box> has no <size> — add <size>sx sy sz</size>");
      return std::nullopt;
    }
    const auto v = Vector(doc, *size, true, "1 1 1");
    if (!v) return std::nullopt;
    return MakeBox(*v);
  }
  if (shape.name == "cylinder" || shape.name == "sphere") {
    const XmlElement* radius = shape.Child("radius");
    const XmlElement* length = shape.Child("length");
    if (!radius || (shape.name == "cylinder" && !length)) {
      Error(doc, shape.line,
            fmt::format("<{}> needs <radius>{}", shape.name,
                        shape.name == "cylinder" ? " and <length>" : ""));
      return std::nullopt;
    }
    const auto r = PositiveNumber(doc, *radius, "0.5");
    if (shape.name == "sphere") {
      if (!r) return std::nullopt;
      return MakeSphere(*r, chord);
    }
    const auto l = PositiveNumber(doc, *length, "1");
    if (!r || !l) return std::nullopt;
    return MakeCylinder(*r, *l, chord);
  }
  if (shape.name == "plane") {
    Vec3 normal = Vec3::UnitZ();
    double sx = 1;
    double sy = 1;
    if (const XmlElement* e = shape.Child("normal")) {
      const auto v = Vector(doc, *e, false, "0 0 1");
      if (!v) return std::nullopt;
      if (v->norm() < 1e-12) {
        Error(doc, e->line, "<normal> is zero — give a direction, e.g. <normal>0 0 1</normal>");
        return std::nullopt;
      }
      normal = *v;
    }
    if (const XmlElement* e = shape.Child("size")) {
      const auto v = Numbers(doc, *e, 2, "100 100");
      if (!v) return std::nullopt;
      if ((*v)[0] <= 0 || (*v)[1] <= 0) {
        Error(doc, e->line,
              fmt::format("<size> '{}' of <plane> must be two positive lengths [m]", e->Trimmed()));
        return std::nullopt;
      }
      sx = (*v)[0];
      sy = (*v)[1];
    }
    TriangleMesh mesh = MakePlane(sx, sy);
    mesh.Transform(Pose{Vec3::Zero(), PlaneRotation(normal)});
    return mesh;
  }
  if (shape.name == "mesh") {
    const XmlElement* uri = shape.Child("uri");
    if (!uri || uri->Trimmed().empty()) {
      Error(doc, shape.line, "<mesh> has no <uri> — add <uri>model://NAME/meshes/FILE</uri>");
      return std::nullopt;
    }
    Vec3 scale = Vec3::Ones();
    if (const XmlElement* e = shape.Child("scale")) {
      const auto v = Vector(doc, *e, true, "1 1 1");
      if (!v) return std::nullopt;
      scale = *v;
    }
    if (shape.Child("submesh")) {
      Note(AtPlace(doc.xml.path, shape.line,
                   fmt::format("{}: <submesh> is not applied, the whole mesh is used", what)));
    }
    std::string text = uri->Trimmed();
    std::optional<std::string> path = ResolveResourceUri(text, doc);
    if (!path || !IsFile(*path)) {
      Error(doc, uri->line,
            fmt::format("<mesh><uri> '{}' of {} not found (model path: {}) — check the file "
                        "name, or add its model folder's parent with --model-path",
                        text, what, model_dirs_.empty() ? "empty" : Join(model_dirs_, ", ")));
      return std::nullopt;
    }
    const TriangleMesh* mesh = LoadMesh(*path, doc, uri->line);
    if (!mesh) return std::nullopt;
    TriangleMesh scaled = *mesh;
    scaled.Scale(scale);
    return scaled;
  }
  if (shape.name == "empty") return TriangleMesh{};
  Note(AtPlace(doc.xml.path, shape.line,
               fmt::format("{}: <{}> geometry is not supported: skipped", what, shape.name)));
  return TriangleMesh{};
}

void Loader::BuildScene(std::vector<GazeboVisual>* visuals_out) {
  // Roles. --target overrides everything; else the plugin's colour segmentation decides and
  // sceneModelPath's names are cross-checked (a note for each disagreement).
  std::vector<bool> is_target(visuals_.size(), false);
  const std::string colour_text = fmt::format("{} {} {}", segmentation_colour_[0],
                                              segmentation_colour_[1], segmentation_colour_[2]);
  if (!options_.targets.empty()) {
    for (const std::string& name : options_.targets) {
      const bool exists = std::any_of(models_.begin(), models_.end(),
                                      [&](const auto& m) { return NameSelects(name, m.first); });
      const bool visible = std::any_of(visuals_.begin(), visuals_.end(),
                                       [&](const auto& v) { return NameSelects(name, v.model); });
      std::vector<std::string> names;
      for (const auto& m : models_) names.push_back(m.first);
      if (!exists) {
        Error(path_, 0,
              fmt::format("--target '{}' names no model of the world — models: {}", name,
                          Join(names, ", ")));
      } else if (!visible) {
        Error(path_, 0,
              fmt::format("--target '{}' has no visible geometry (a sensor model, or a model "
                          "without <visual>) — name a model with visuals",
                          name));
      }
    }
    for (size_t i = 0; i < visuals_.size(); ++i) {
      for (const std::string& name : options_.targets)
        if (NameSelects(name, visuals_[i].model)) is_target[i] = true;
    }
  } else {
    for (size_t i = 0; i < visuals_.size(); ++i) {
      const std::optional<Rgb> colour = ColoursOf(visuals_[i]).SegmentationColour();
      is_target[i] = colour && ToRgb255(*colour) == segmentation_colour_;
    }
  }

  // Geometry, grouped into one object per (model, role), in declaration order.
  struct Group {
    std::string model;
    Role role;
    TriangleMesh mesh;
  };
  std::vector<Group> groups;
  std::map<std::pair<std::string, Role>, size_t> group_index;
  for (size_t i = 0; i < visuals_.size(); ++i) {
    const VisualRecord& visual = visuals_[i];
    std::optional<TriangleMesh> mesh = GeometryOf(visual);
    if (visuals_out) {
      visuals_out->push_back(GazeboVisual{
          visual.model, visual.link, visual.name, visual.world_from_visual, is_target[i],
          visual.doc->xml.path, visual.element ? visual.element->line : visual.site.line});
    }
    if (!mesh || mesh->IsEmpty()) continue;
    mesh->Transform(visual.world_from_visual);
    const Role role = is_target[i] ? Role::kTarget : Role::kOccluder;
    const auto key = std::make_pair(visual.model, role);
    auto it = group_index.find(key);
    if (it == group_index.end()) {
      it = group_index.emplace(key, groups.size()).first;
      groups.push_back(Group{visual.model, role, TriangleMesh{}});
    }
    groups[it->second].mesh.Append(*mesh);
  }
  for (Group& group : groups) {
    // A model with both roles: the target part keeps the model's name.
    const bool is_split = group_index.contains(std::make_pair(group.model, Role::kTarget)) &&
                          group_index.contains(std::make_pair(group.model, Role::kOccluder));
    SceneObject object;
    object.name =
        is_split && group.role == Role::kOccluder ? group.model + "/occluder" : group.model;
    object.role = group.role;
    object.mesh = std::move(group.mesh);
    problem_.scene.objects.push_back(std::move(object));
  }

  if (!options_.targets.empty()) return;
  std::set<std::string> target_models;
  for (size_t i = 0; i < visuals_.size(); ++i)
    if (is_target[i]) target_models.insert(visuals_[i].model);
  if (target_models.empty() && !diag_.HasErrors()) {
    std::string listed;
    if (scene_model_names_ && !scene_model_names_->empty())
      listed = fmt::format(" (sceneModelPath lists {})", Join(*scene_model_names_, ", "));
    Error(segmentation_site_.file.empty() ? path_ : segmentation_site_.file,
          segmentation_site_.line,
          fmt::format("{} {} matches no visual's material colour (emissive where set, else "
                      "diffuse){} — colour the targets so, or pass --target NAME",
                      is_segmentation_given_ ? "<sensorDataSegmentationColorRGB>"
                                             : "the plugin's default segmentation colour",
                      colour_text, listed));
    return;
  }
  if (!scene_model_names_) return;
  const std::string place = AtPlace(scene_model_site_.file, scene_model_site_.line, "");
  for (const std::string& name : *scene_model_names_) {
    const bool exists = std::any_of(models_.begin(), models_.end(),
                                    [&](const auto& m) { return NameSelects(name, m.first); });
    const bool coloured = std::any_of(target_models.begin(), target_models.end(),
                                      [&](const std::string& m) { return NameSelects(name, m); });
    if (!exists) {
      Note(fmt::format("{}sceneModelPath lists '{}', which is no model of the world", place, name));
    } else if (!coloured) {
      Note(
          fmt::format("{}sceneModelPath lists '{}', which has no visual of colour {}: it is "
                      "not a target (the plugin segments by colour)",
                      place, name, colour_text));
    }
  }
  for (const std::string& model : target_models) {
    const bool listed = std::any_of(scene_model_names_->begin(), scene_model_names_->end(),
                                    [&](const std::string& n) { return NameSelects(n, model); });
    if (!listed) {
      Note(
          fmt::format("{}model '{}' has colour {} but sceneModelPath does not list it: it is a "
                      "target (the plugin segments by colour)",
                      place, model, colour_text));
    }
  }
}

Problem Loader::Load(std::vector<GazeboVisual>* visuals_out) {
  problem_.source = path_;
  world_doc_ = LoadSdf(path_, "");
  diag_.ThrowIfAny();  // nothing else can be read without the world file
  VANTAGE_CHECK(world_doc_ != nullptr);
  const std::vector<const XmlElement*> worlds = world_doc_->xml.root.Children("world");
  if (worlds.size() != 1) {
    Error(*world_doc_, world_doc_->xml.root.line,
          worlds.empty() ? "no <world> element — vantage reads world files (a model file goes in "
                           "a world with <include>)"
                         : "more than one <world> — keep one per file");
    diag_.ThrowIfAny();
  }
  world_ = worlds[0];
  ReadPlugin();
  for (const XmlElement& child : world_->children) {
    if (child.name == "include" || child.name == "model") {
      VisitWorldEntity(*world_doc_, child);
    } else if (child.name == "population") {
      ReadPopulation(*world_doc_, child);
    } else if (child.name == "state") {
      Note(AtPlace(path_, child.line, "<state> is not applied: poses come from the models"));
    } else if (child.name == "actor") {
      Note(AtPlace(path_, child.line, "<actor> skipped: vantage reads static scenes"));
    }
  }

  // Explicit sensors: plain models holding a depth sensor (the plugin re-orients them too).
  std::map<std::string, int> sensors_per_model;
  for (const SensorRecord& r : sensors_) ++sensors_per_model[r.model];
  for (const SensorRecord& r : sensors_) {
    const bool is_many = sensors_per_model[r.model] > 1;
    const std::string type_id = is_many ? r.type_name + "/" + r.sensor_name : r.type_name;
    const std::optional<std::string> id = AddSensorType(r, type_id);
    if (!id) continue;
    ExplicitSensor sensor;
    sensor.name = is_many ? r.model + "/" + r.sensor_name : r.model;
    sensor.sensor_type = *id;
    sensor.pose = r.world_from_model;
    sensor.look_at = true;
    sensor.model_from_camera = r.model_from_camera;
    sensor.file = r.site.file;
    sensor.line = r.site.line;
    problem_.sensors.push_back(std::move(sensor));
  }

  BuildScene(visuals_out);
  diag_.ThrowIfAny();
  return std::move(problem_);
}

}  // namespace
}  // namespace detail

Problem detail::LoadGazeboWorld(const std::string& path,
                                const LoadOptions& options,
                                std::vector<GazeboVisual>* visuals) {
  return Loader(path, options).Load(visuals);
}

Problem LoadGazeboWorld(const std::string& path, const LoadOptions& options) {
  return detail::LoadGazeboWorld(path, options, nullptr);
}

}  // namespace vantage
