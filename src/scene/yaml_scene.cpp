// vantage's YAML scene format (docs/scene-format.md).
// Every problem is collected with its line (STYLE.md, Errors) and reported in one InputError.
#include <fmt/format.h>
#include <yaml-cpp/yaml.h>

#include <algorithm>
#include <charconv>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <initializer_list>
#include <limits>
#include <map>
#include <numbers>
#include <optional>
#include <set>
#include <tuple>
#include <type_traits>
#include <sstream>
#include <string>
#include <string_view>
#include <utility>
#include <variant>
#include <vector>

#include "scene/scaled_mesh_cache.hpp"
#include "scene/step_reader.hpp"
#include "util/cell_size.hpp"
#include "util/words.hpp"
#include "vantage/error.hpp"
#include "vantage/problem.hpp"
#include "vantage/robot.hpp"
#include "vantage/scene_settings.hpp"
#include "vantage/scene_states.hpp"
#include "vantage/settings.hpp"

namespace vantage {
namespace {

namespace fs = std::filesystem;

constexpr double kPi = std::numbers::pi;
constexpr double kDegree = kPi / 180.0;

/// The names of `items` (objects, sensors, populations) as a set, for the duplicate checks: a
/// scan of every earlier name per entry took 30 s for 10⁵ sensors.
template <typename Items>
std::set<std::string> NamesOf(const Items& items) {
  std::set<std::string> names;
  for (const auto& item : items) names.insert(item.name);
  return names;
}

// ---------------------------------------------------------------------------------------------
// Words: suggestions for misspelt keys and values.

/// "did you mean 'x'?" for the closest word within a third of its length (at least 2 edits),
/// else the list of valid words.
std::string Suggest(std::string_view word, const std::vector<std::string>& valid) {
  if (const std::string* best = detail::ClosestWord(word, valid)) return fmt::format("did you mean '{}'?", *best);
  return "valid: " + detail::JoinQuoted(valid);
}

/// The id nearest to a mistyped one: the shortest id that contains it (`d435` ->
/// `intel_realsense_d435`), else the one the fewest edits away when at most half the word's
/// length (ids are long: ClosestWord's third would miss `realsense_d435`); nullptr when none is
/// near (`lidar`: the caller lists them all).
const std::string* NearestId(const std::string& word, const std::vector<std::string>& ids) {
  const std::string* containing = nullptr;
  const std::string* closest = nullptr;
  size_t closest_distance = std::numeric_limits<size_t>::max();
  for (const std::string& id : ids) {
    if (id.find(word) != std::string::npos && (!containing || id.size() < containing->size()))
      containing = &id;
    const size_t distance = EditDistance(word, id);  // once per id
    if (distance < closest_distance) {
      closest_distance = distance;
      closest = &id;
    }
  }
  if (containing) return containing;
  return closest_distance <= std::max<size_t>(2, word.size() / 2) ? closest : nullptr;
}

int LineOf(const YAML::Node& node) {
  const YAML::Mark mark = node.Mark();
  return mark.is_null() ? 0 : mark.line + 1;
}

std::string TextOf(const YAML::Node& node) {
  if (node.IsScalar()) return node.Scalar();
  // "must be a list ..., got a list" said nothing of what was wrong with `joints: []`.
  if (node.IsSequence()) return node.size() == 0 ? "an empty list" : "a list";
  if (node.IsMap()) return node.size() == 0 ? "an empty mapping" : "a mapping";
  return "nothing";
}

/// A YAML value and the line to report it at: its key's line for a mapping entry (yaml-cpp marks
/// an empty value at the next token, often a later line), else its own.
struct Value {
  YAML::Node node;
  int line = 0;
};

Value ValueOf(const YAML::Node& node) { return Value{node, LineOf(node)}; }

std::vector<std::string> CatalogIds() {
  std::vector<std::string> ids;
  for (const SensorType& type : Catalog()) ids.push_back(type.id);
  return ids;
}

/// Diagnostics that also count, so that a reader can tell whether one item was clean.
class Reporter {
 public:
  explicit Reporter(Diagnostics* diag) : diag_(diag) {}
  void Error(int line, const std::string& message) {
    ++count_;
    diag_->Error(line, message);
  }
  size_t count() const { return count_; }

 private:
  Diagnostics* diag_;
  size_t count_ = 0;
};

// ---------------------------------------------------------------------------------------------
// Fields: one YAML mapping, its keys checked against those it may hold.

class Fields {
 public:
  /// Records an error when `input` is not a mapping (null counts as empty), or holds unknown or
  /// repeated keys.
  Fields(const Value& input,
         std::string context,
         std::initializer_list<std::string_view> allowed,
         Reporter* reporter)
      : Fields(input, std::move(context), std::vector<std::string_view>(allowed), reporter) {}
  Fields(const Value& input,
         std::string context,
         const std::vector<std::string_view>& allowed,
         Reporter* reporter)
      : context_(std::move(context)), line_(input.line) {
    const YAML::Node& node = input.node;
    if (node.IsNull()) return;  // an empty section: every key absent
    if (!node.IsMap()) {
      reporter->Error(line_, fmt::format("{} must be a mapping of `key: value` lines, got {} — see "
                                         "docs/scene-format.md",
                                         context_, TextOf(node)));
      return;
    }
    const std::vector<std::string> valid(allowed.begin(), allowed.end());
    for (const auto& entry : node) {
      const YAML::Node& key = entry.first;
      const std::string name = key.IsScalar() ? key.Scalar() : "";
      if (std::find(valid.begin(), valid.end(), name) == valid.end()) {
        reporter->Error(LineOf(key), fmt::format("unknown key '{}' in {} — {}", name, context_,
                                                 Suggest(name, valid)));
      } else if (Get(name)) {
        reporter->Error(LineOf(key),
                        fmt::format("key '{}' appears twice in {} — keep one", name, context_));
      } else {
        const YAML::Node& item = entry.second;
        entries_.emplace_back(name, Value{item, LineOf(key)});
      }
    }
  }

  std::optional<Value> Get(std::string_view key) const {
    for (const auto& [name, value] : entries_) {
      if (name == key) return value;
    }
    return std::nullopt;
  }
  bool Has(std::string_view key) const { return Get(key).has_value(); }
  const std::string& context() const { return context_; }
  int line() const { return line_; }

 private:
  std::string context_;
  int line_ = 0;
  std::vector<std::pair<std::string, Value>> entries_;
};

// ---------------------------------------------------------------------------------------------
// Robots (issue 19): a URDF robot placed in the scene, its links' visuals as objects.

/// One `robots:` entry, read: its model, base pose, joint positions and, per link with visuals,
/// the link's mesh in the link frame (the object "NAME::LINK" is it at the link's pose).
struct SceneRobot {
  std::string name;
  RobotModel model;
  Pose world_from_base;
  JointPositions joints;
  std::vector<std::pair<std::string, TriangleMesh>> link_meshes;  ///< link frame, tree order
  int line = 0;

  std::string ObjectName(const std::string& link) const { return name + "::" + link; }
  /// The link objects' world meshes at the given joint positions.
  std::vector<std::pair<std::string, TriangleMesh>> WorldMeshes(
      const JointPositions& positions) const {
    const std::map<std::string, Pose> world_from_link =
        LinkPoses(model, world_from_base, positions);
    std::vector<std::pair<std::string, TriangleMesh>> meshes;
    for (const auto& [link, mesh] : link_meshes) {
      TriangleMesh world = mesh;
      world.Transform(world_from_link.at(link));
      meshes.emplace_back(ObjectName(link), std::move(world));
    }
    return meshes;
  }
};

/// A sensor on a robot link (`mount: {robot, link, pose}`): its model pose is
/// world_from_link · link_from_model, in the base scene and in every state.
struct LinkMount {
  std::string sensor;
  size_t robot = 0;  ///< index into the reader's robots
  std::string link;
  Pose link_from_model;
};

/// A whole number as written: its sign and magnitude.
struct WholeNumber {
  bool negative = false;
  uint64_t magnitude = 0;
};

// ---------------------------------------------------------------------------------------------
// The reader of one scene file.

class SceneReader {
 public:
  SceneReader(const std::string& path,
              const LoadOptions& options,
              Diagnostics* diag,
              Problem* problem)
      : folder_(fs::path(path).parent_path()),
        options_(options),
        reporter_(diag),
        problem_(problem) {}

  void Read(const YAML::Node& root);

 private:
  // Values. Each records an error naming `what` and returns nullopt when the value is wrong.
  std::optional<double> Number(const Value& input, const std::string& what);
  std::optional<double> Positive(const Value& input, const std::string& what);
  /// A whole number written in decimal (sign, digits, no leading zero), any size up to 2^64 - 1.
  // `range` names the values the caller takes ("a value from 1 to 100"), for a number too long to
  // read at all.
  std::optional<WholeNumber> Whole(const Value& input, const std::string& what,
                                   const std::string& range);
  /// A whole number from 0 to 2^64 - 1 (a seed).
  std::optional<uint64_t> Unsigned(const Value& input, const std::string& what);
  std::optional<int64_t> Integer(const Value& input,
                                 const std::string& what,
                                 int64_t min,
                                 int64_t max);
  std::optional<bool> Boolean(const Value& input, const std::string& what);
  std::optional<std::string> Text(const Value& input, const std::string& what);
  std::optional<std::vector<double>> Numbers(const Value& input,
                                             size_t count,
                                             const std::string& what);
  std::optional<Vec3> Vector(const Value& input, const std::string& what);
  std::optional<Quat> Rotation(const Fields& fields, const std::string& what);
  std::optional<Pose> PoseOf(const Value& input, const std::string& what);
  std::optional<std::string> Name(const Fields& fields, const std::string& kind);
  std::vector<Value> Items(const Value& input, const std::string& section);
  void Missing(const Fields& fields, const std::string& key, const std::string& example);

  // Sections.
  void ReadSettings(const Value& input);
  /// One selection setting (its row) from its key's value; whether it counts as an objective
  /// where the row is one (given, or a whole number of 2 or more).
  bool ReadSelectionSetting(const SceneSelectionSetting& setting, const Value& v);
  void ReadSensorTypes(const Value& input);
  std::optional<SensorType> ReadSensorType(const Value& input);
  const SensorType* ReadBase(const Fields& fields, const std::string& what);
  void ReadIntrinsics(const Fields& fields,
                      const std::string& what,
                      const SensorType* base,
                      bool resolution_changed,
                      SensorType* type);
  void ReadRangeAndCost(const Fields& fields, const std::string& what, SensorType* type);
  void ReadSecondAperture(const Value& input, const std::string& what, SensorType* type);
  void ReadResolution(const Fields& fields,
                      const std::string& what,
                      SensorType* type,
                      bool* changed);
  std::optional<double> ReadFov(const Fields& fields,
                                const std::string& key,
                                const std::string& what);
  void ReadObjects(const Value& input);
  /// `standing`: the objects an `on:` may name (a state's, as they stand in it); the scene's
  /// objects read so far when null.
  std::optional<SceneObject> ReadObject(const Value& input,
                                        const std::vector<SceneObject>* standing = nullptr);
  bool PlaceOn(const Value& input, const std::string& what, double gap,
               const std::vector<SceneObject>& standing, TriangleMesh* mesh);
  std::optional<TriangleMesh> ReadShape(const Fields& fields, const std::string& what,
                                        ShapeSource* source);
  std::optional<TriangleMesh> ReadPrimitive(const std::string& shape,
                                            const Value& input,
                                            const std::string& what,
                                            ShapeSource* source);
  std::optional<TriangleMesh> ReadMesh(const Value& input, const std::string& what,
                                       ShapeSource* source);
  /// The mesh file at `resolved`, read once, scaled by `scale` (ScaledMesh); an error at `line`
  /// when it is missing (`not_found`), unreadable or reaches too far.
  std::optional<TriangleMesh> CachedMesh(const fs::path& resolved,
                                         int line,
                                         const std::string& not_found,
                                         const Vec3& scale);
  std::optional<Vec3> ReadScale(const Value& input, const std::string& what);
  void ReadRobots(const Value& input);
  void ReadRobot(const Value& input);
  std::optional<JointPositions> ReadJoints(const Value& input,
                                           const RobotModel& robot,
                                           const std::string& what);
  std::optional<TriangleMesh> ReadRobotVisual(const RobotVisual& visual,
                                              const std::string& urdf_folder,
                                              int line,
                                              const std::string& what);
  void ReadStateJoints(const Value& input, const std::string& what, SceneState* state);
  bool ReadLinkMount(const Value& input, const std::string& what, ExplicitSensor* sensor);
  /// `arm:` (joint space, `joint_space`) or a region's `reach:` (issue 45, docs/arm.md).
  std::optional<ArmMount> ReadArmMount(const Value& input, const std::string& what,
                                       bool joint_space);
  void ReadPopulations(const Value& input);
  std::optional<Population> ReadPopulation(const Value& input);
  bool ReadRegion(const Fields& fields, const std::string& what, Population* population);
  bool ReadGrid(const Fields& fields, const std::string& what, Population* population);
  void ReadSensors(const Value& input);
  std::optional<ExplicitSensor> ReadSensor(const Value& input);
  std::optional<std::string> TypeReference(const Fields& fields, const std::string& what);
  void ReadStates(const Value& input);
  std::optional<SceneState> ReadState(const Value& input);
  void ReadKeepOut(const Value& input);
  std::optional<KeepOutBox> ReadKeepOutBox(const Value& input, size_t index);
  void CheckStates();
  void ApplyTargetOverride();
  void AddReferencedCatalogTypes();
  bool IsCustomType(const std::string& id) const { return problem_->FindType(id) != nullptr; }
  bool IsRejectedRobot(const std::string& name) const {
    return std::find(rejected_robots_.begin(), rejected_robots_.end(), name) !=
           rejected_robots_.end();
  }

  void Error(int line, const std::string& message) { reporter_.Error(line, message); }
  size_t ErrorCount() const { return reporter_.count(); }

  fs::path folder_;
  bool observation_point_given_ = false;  // settings.observation_point, else the targets' centre
  const LoadOptions& options_;
  Reporter reporter_;
  Problem* problem_;
  int objects_line_ = 0;
  std::map<std::string, TriangleMesh> mesh_cache_;  ///< by resolved path, unscaled (ReadMeshFile)
  detail::ScaledMeshCache scaled_meshes_;  ///< by resolved path and scale
  /// A CAD file's parts (issue 46), by absolute path, unscaled: an assembly's objects.
  std::map<std::string, std::vector<detail::CadPart>> cad_parts_;
  std::set<int> by_colour_lines_;  ///< objects given `role: by_colour`, by line
  /// `object`, or one object per solid when its mesh is a CAD assembly (CadParts).
  std::vector<SceneObject> CadParts(SceneObject object, int line);
  std::vector<SceneRobot> robots_;                  ///< `robots:` read without errors, in order
  std::vector<std::string> rejected_robots_;        ///< names of robots that had errors
  std::vector<LinkMount> link_mounts_;              ///< sensors mounted on a robot link
  std::vector<std::string> rejected_type_ids_;      ///< declared sensor types that had errors
};

// ----- values --------------------------------------------------------------------------------

std::string Shown(const YAML::Node& node) {
  return node.IsScalar() ? "'" + node.Scalar() + "'" : TextOf(node);
}

std::optional<double> SceneReader::Number(const Value& input, const std::string& what) {
  std::optional<double> number;
  if (input.node.IsScalar()) {
    try {
      number = input.node.as<double>();
    } catch (const YAML::Exception&) {
      number.reset();
    }
  }
  if (!number) {
    Error(input.line, fmt::format("{}: expected a number, got {} — write a plain number, e.g. 0.5",
                                  what, Shown(input.node)));
    return std::nullopt;
  }
  if (!std::isfinite(*number)) {
    Error(input.line, fmt::format("{} is {} — give a finite number", what, input.node.Scalar()));
    return std::nullopt;
  }
  return number;
}

std::optional<double> SceneReader::Positive(const Value& input, const std::string& what) {
  const std::optional<double> number = Number(input, what);
  if (number && *number <= 0) {
    Error(input.line, fmt::format("{} = {} must be positive — give a value > 0", what, *number));
    return std::nullopt;
  }
  return number;
}

std::optional<WholeNumber> SceneReader::Whole(const Value& input, const std::string& what,
                                              const std::string& range) {
  // Decimal only: yaml-cpp reads 010 as octal 8 and 0x10 as 16 (issue 15), which no scene's
  // author means by a count or a seed.
  const std::string text = input.node.IsScalar() ? input.node.Scalar() : std::string();
  std::string_view digits(text);
  WholeNumber number;
  if (!digits.empty() && (digits.front() == '-' || digits.front() == '+')) {
    number.negative = digits.front() == '-';
    digits.remove_prefix(1);
  }
  const auto [end, error] =
      std::from_chars(digits.data(), digits.data() + digits.size(), number.magnitude);
  const bool all_digits = !digits.empty() && end == digits.data() + digits.size();
  if (all_digits && digits.size() > 1 && digits.front() == '0') {
    Error(input.line, fmt::format("{}: {} has a leading zero (YAML 1.1 reads it as octal) — write "
                                  "the number without it",
                                  what, Shown(input.node)));
    return std::nullopt;
  }
  if (all_digits && error == std::errc::result_out_of_range) {
    Error(input.line, fmt::format("{} = {} is too {} — give {}", what, text,
                                  number.negative ? "small" : "large", range));
    return std::nullopt;
  }
  if (!all_digits || error != std::errc()) {
    Error(input.line, fmt::format("{}: expected a whole number, got {} — write e.g. 3", what,
                                  Shown(input.node)));
    return std::nullopt;
  }
  return number;
}

std::optional<uint64_t> SceneReader::Unsigned(const Value& input, const std::string& what) {
  const std::optional<WholeNumber> whole =
      Whole(input, what, fmt::format("a value from 0 to {}", std::numeric_limits<uint64_t>::max()));
  if (!whole) return std::nullopt;
  if (whole->negative && whole->magnitude > 0) {
    Error(input.line, fmt::format("{} = -{} is too small — give at least 0", what, whole->magnitude));
    return std::nullopt;
  }
  return whole->magnitude;
}

std::optional<int64_t> SceneReader::Integer(const Value& input,
                                            const std::string& what,
                                            int64_t min,
                                            int64_t max) {
  const std::optional<WholeNumber> whole =
      Whole(input, what, fmt::format("a value from {} to {}", min, max));
  if (!whole) return std::nullopt;
  constexpr uint64_t kLargest = static_cast<uint64_t>(std::numeric_limits<int64_t>::max());
  if (whole->magnitude > kLargest + (whole->negative ? 1 : 0)) {
    Error(input.line, fmt::format("{} = {}{} is too {} — give a value from {} to {}", what,
                                  whole->negative ? "-" : "", whole->magnitude,
                                  whole->negative ? "small" : "large", min, max));
    return std::nullopt;
  }
  const std::optional<int64_t> number =
      whole->negative ? static_cast<int64_t>(0 - whole->magnitude)
                      : static_cast<int64_t>(whole->magnitude);
  if (*number < min) {
    Error(input.line, fmt::format("{} = {} is too small — give at least {}", what, *number, min));
    return std::nullopt;
  }
  if (*number > max) {
    Error(input.line, fmt::format("{} = {} is too large — give at most {}", what, *number, max));
    return std::nullopt;
  }
  return number;
}

std::optional<bool> SceneReader::Boolean(const Value& input, const std::string& what) {
  if (input.node.IsScalar()) {
    try {
      return input.node.as<bool>();
    } catch (const YAML::Exception&) {
      // reported below
    }
  }
  Error(input.line, fmt::format("{}: expected true or false, got {} — write true or false", what,
                                Shown(input.node)));
  return std::nullopt;
}

std::optional<std::string> SceneReader::Text(const Value& input, const std::string& what) {
  if (input.node.IsScalar() && !input.node.Scalar().empty()) {
    // Every name, id and path of a scene enters here: "a\nb" or "a\0b" would break the CSV,
    // SDF and xacro outputs (issue 15).
    const std::string& text = input.node.Scalar();
    if (const std::string problem = detail::NameProblem(text); !problem.empty()) {
      Error(input.line, fmt::format("{} '{}' {}", what, detail::Escaped(text), problem));
      return std::nullopt;
    }
    return text;
  }
  Error(input.line, fmt::format("{}: expected a word, got {} — write a plain word, e.g. part_1",
                                what, TextOf(input.node)));
  return std::nullopt;
}

/// The line of a list's element: its own, unless yaml-cpp has none for it.
Value ElementOf(const Value& list, size_t i) {
  const YAML::Node element = list.node[i];
  const int line = LineOf(element);
  return Value{element, line > 0 ? line : list.line};
}

std::optional<std::vector<double>> SceneReader::Numbers(const Value& input,
                                                        size_t count,
                                                        const std::string& what) {
  const YAML::Node& node = input.node;
  if (!node.IsSequence() || node.size() != count) {
    const char* example = count == 2 ? "0.5, 2.0" : count == 3 ? "0, 0, 1" : "1, 0, 0, 0";
    Error(input.line,
          fmt::format("{}: expected a list of {} numbers, got {} — write e.g. [{}]", what, count,
                      node.IsSequence() ? fmt::format("{} items", node.size()) : Shown(node),
                      example));
    return std::nullopt;
  }
  std::vector<double> numbers;
  for (size_t i = 0; i < count; ++i) {
    const std::optional<double> number =
        Number(ElementOf(input, i), fmt::format("{}[{}]", what, i));
    if (!number) return std::nullopt;
    numbers.push_back(*number);
  }
  return numbers;
}

std::optional<Vec3> SceneReader::Vector(const Value& input, const std::string& what) {
  const auto numbers = Numbers(input, 3, what);
  if (!numbers) return std::nullopt;
  return Vec3((*numbers)[0], (*numbers)[1], (*numbers)[2]);
}

/// `rpy: [roll, pitch, yaw]` in radians (R = Rz·Ry·Rx, as SDF), `rpy_deg:` the same in degrees,
/// or `quaternion: [w, x, y, z]`; identity when none is given.
std::optional<Quat> SceneReader::Rotation(const Fields& fields, const std::string& what) {
  const auto radians = fields.Get("rpy");
  const auto degrees = fields.Get("rpy_deg");
  const auto quaternion = fields.Get("quaternion");
  std::vector<std::pair<const char*, int>> given;  // the rotation keys present, with their lines
  if (radians) given.emplace_back("rpy", radians->line);
  if (degrees) given.emplace_back("rpy_deg", degrees->line);
  if (quaternion) given.emplace_back("quaternion", quaternion->line);
  if (given.size() > 1) {
    Error(std::max(given[0].second, given[1].second),
          fmt::format("{}: both {} and {} are given — keep one of them (each sets the rotation)",
                      what, given[0].first, given[1].first));
    return std::nullopt;
  }
  if (radians || degrees) {
    const auto v = Vector(radians ? *radians : *degrees, what + (radians ? ".rpy" : ".rpy_deg"));
    if (!v) return std::nullopt;
    // rpy: [0, 90, -10] is degrees where radians belong (a turn of 90 rad): no angle of a pose
    // needs more than a full turn.
    if (radians && (v->array().abs() > 2.0 * std::numbers::pi + 1e-9).any()) {
      Error(radians->line,
            fmt::format("{}.rpy [{:g}, {:g}, {:g}] has an angle above 2π (6.283) radians — these "
                        "look like degrees: write rpy_deg: [{:g}, {:g}, {:g}]",
                        what, v->x(), v->y(), v->z(), v->x(), v->y(), v->z()));
      return std::nullopt;
    }
    const Vec3 rpy = radians ? *v : Vec3(*v * kDegree);
    return Quat(RotationFromRpy(rpy.x(), rpy.y(), rpy.z())).normalized();
  }
  if (quaternion) {
    const auto q = Numbers(*quaternion, 4, what + ".quaternion");
    if (!q) return std::nullopt;
    const std::optional<Quat> rotation = QuatFromWxyz(*q);
    if (!rotation) {
      Error(quaternion->line,
            fmt::format("{}.quaternion is zero, or shorter than 1e-09 (no direction to "
                        "normalise) — give [w, x, y, z], e.g. [1, 0, 0, 0]",
                        what));
      return std::nullopt;
    }
    return rotation;
  }
  return Quat::Identity();
}

std::optional<Pose> SceneReader::PoseOf(const Value& input, const std::string& what) {
  const Fields fields(input, what, {"xyz", "rpy", "rpy_deg", "quaternion"}, &reporter_);
  Pose pose;
  bool ok = true;
  if (const auto xyz = fields.Get("xyz")) {
    const auto position = Vector(*xyz, what + ".xyz");
    ok = position.has_value();
    if (position) pose.position = *position;
  }
  const auto rotation = Rotation(fields, what);
  if (!rotation || !ok) return std::nullopt;
  pose.rotation = *rotation;
  return pose;
}

std::optional<std::string> SceneReader::Name(const Fields& fields, const std::string& kind) {
  const auto name = fields.Get("name");
  if (!name) {
    Missing(fields, "name", "name: part_1");
    return std::nullopt;
  }
  return Text(*name, kind + " name");
}

std::vector<Value> SceneReader::Items(const Value& input, const std::string& section) {
  std::vector<Value> items;
  if (input.node.IsNull()) return items;
  if (!input.node.IsSequence()) {
    Error(input.line,
          fmt::format("{} must be a list, got {} — write one `- name: ...` entry per item", section,
                      Shown(input.node)));
    return items;
  }
  for (size_t i = 0; i < input.node.size(); ++i) items.push_back(ElementOf(input, i));
  return items;
}

void SceneReader::Missing(const Fields& fields,
                          const std::string& key,
                          const std::string& example) {
  Error(fields.line(),
        fmt::format("{} has no '{}' — add e.g. `{}`", fields.context(), key, example));
}

// ----- settings ------------------------------------------------------------------------------

void SceneReader::ReadSettings(const Value& input) {
  const Fields fields(input, "settings",
                      {"cell_size", "n", "method", "observation_point", "random_roll", "seed",
                       "ransac", "expected_candidates", "goal", "k", "budget"},
                      &reporter_);
  Problem& p = *problem_;
  if (const auto v = fields.Get("cell_size")) {
    if (const auto f = Positive(*v, "settings.cell_size")) {
      if (const std::string problem = detail::CellSizeProblem(*f); !problem.empty()) {
        Error(v->line, "settings." + problem);
      } else {
        p.cell_size = *f;
      }
    }
  }
  if (const auto v = fields.Get("observation_point")) {
    if (const auto point = Vector(*v, "settings.observation_point")) {
      // Every candidate's look-at direction starts here: the same range as --observation-point.
      if (const std::string beyond = WorldPointProblem(*point); !beyond.empty())
        Error(v->line, fmt::format("settings.observation_point {} — give a point near the targets",
                                   beyond));
      p.observation_point = *point;
    }
    observation_point_given_ = true;
  }
  if (const auto v = fields.Get("random_roll")) {
    if (const auto roll = Boolean(*v, "settings.random_roll")) p.random_roll = *roll;
  }
  if (const auto v = fields.Get("seed")) {
    if (const auto seed = Unsigned(*v, "settings.seed")) p.seed = *seed;
  }
  // The selection settings, by their rows (scene_settings.hpp); those under `ransac:` in that
  // map. Objectives beyond coverage (SYSTEM.md, Select): at most one of them.
  std::optional<Fields> ransac;
  std::vector<std::string_view> ransac_keys;  // the keys of `settings.ransac`, from the rows
  for (const SceneSelectionSetting& setting : kSceneSelectionSettings)
    if (setting.yaml_key.starts_with("ransac."))
      ransac_keys.push_back(setting.yaml_key.substr(std::string_view("ransac.").size()));
  int objectives = 0;
  int objective_line = 0;
  std::string objective_names;
  for (const SceneSelectionSetting& setting : kSceneSelectionSettings) {
    std::string_view key = setting.yaml_key;
    const Fields* section = &fields;
    if (key.starts_with("ransac.")) {
      const auto v = fields.Get("ransac");
      if (!v) continue;
      if (!ransac) ransac.emplace(*v, "settings.ransac", ransac_keys, &reporter_);
      section = &*ransac;
      key.remove_prefix(std::string_view("ransac.").size());
    }
    if (setting.objective) {
      const bool count = std::holds_alternative<int SelectionSettings::*>(setting.member);
      objective_names += fmt::format("{}settings.{}{}", objective_names.empty() ? "" : ", ",
                                     setting.yaml_key, count ? " >= 2" : "");
    }
    if (const auto v = section->Get(key)) {
      if (ReadSelectionSetting(setting, *v) && setting.objective) {
        ++objectives;
        objective_line = v->line;
      }
    }
  }
  if (objectives > 1) {
    // "a, b, c" -> "a, b and c"
    if (const size_t comma = objective_names.rfind(", "); comma != std::string::npos)
      objective_names.replace(comma, 2, " and ");
    Error(objective_line, objective_names + " are separate objectives — give only one of them");
  }
  if (const auto v = fields.Get("expected_candidates")) {
    if (const auto count =
            Integer(*v, "settings.expected_candidates", 1, std::numeric_limits<int>::max()))
      p.expected_candidates = static_cast<int>(*count);
  }
}

bool SceneReader::ReadSelectionSetting(const SceneSelectionSetting& setting, const Value& v) {
  const std::string name = "settings." + std::string(setting.yaml_key);
  SelectionSettings& selection = problem_->selection;
  // Its line, for errors found after the scene is read (n above the candidates).
  selection.lines[std::string(setting.field)] = v.line;
  return std::visit(
      [&](auto member) -> bool {
        using Held = std::decay_t<decltype(selection.*member)>;
        if constexpr (std::is_same_v<Held, int>) {
          const auto n = Integer(v, name, static_cast<int64_t>(setting.low),
                                 std::numeric_limits<int>::max());
          if (n) selection.*member = static_cast<int>(*n);
          return n && *n >= 2;  // a whole number counts as an objective from 2 on (k)
        } else if constexpr (std::is_same_v<Held, std::optional<Method>>) {
          if (const auto text = Text(v, name)) {
            try {
              selection.*member = ParseMethod(*text);
            } catch (const InputError&) {
              Error(v.line, fmt::format(
                                "{} '{}' is unknown — {}", name, *text,
                                Suggest(*text, {"best", "ransac", "greedy", "local", "exact", "all"})));
            }
          }
          return true;
        } else {  // a number in its range
          const auto number = Number(v, name);
          if (number && setting.OutOfRange(*number)) {
            Error(v.line, fmt::format("{} = {} {}", name, *number, setting.out_of_range));
          } else if (number) {
            selection.*member = *number;
          }
          return true;
        }
      },
      setting.member);
}

// ----- sensor types --------------------------------------------------------------------------

void SceneReader::ReadSensorTypes(const Value& input) {
  for (const Value& item : Items(input, "sensor_types")) {
    std::optional<SensorType> type = ReadSensorType(item);
    if (!type) continue;
    if (FindCatalogType(type->id)) {
      Error(item.line, fmt::format("sensor type id '{}' is a catalog id — choose another id "
                                   "(derive with `base: {}` to change its fields)",
                                   type->id, type->id));
    } else if (IsCustomType(type->id)) {
      Error(item.line, fmt::format("sensor type '{}' is declared twice — rename one", type->id));
    } else {
      problem_->sensor_types.push_back(std::move(*type));
    }
  }
}

/// `hfov`/`vfov` in radians or `hfov_deg`/`vfov_deg` in degrees; the angle must lie in (0, π).
std::optional<double> SceneReader::ReadFov(const Fields& fields,
                                           const std::string& key,
                                           const std::string& what) {
  const auto radians = fields.Get(key);
  const auto degrees = fields.Get(key + "_deg");
  if (radians && degrees) {
    Error(degrees->line,
          fmt::format("{}: both {} and {}_deg are given — keep one", what, key, key));
    return std::nullopt;
  }
  if (!radians && !degrees) return std::nullopt;
  const Value& input = radians ? *radians : *degrees;
  const std::string name = fmt::format("{}.{}{}", what, key, radians ? "" : "_deg");
  const auto value = Number(input, name);
  if (!value) return std::nullopt;
  const double angle = radians ? *value : *value * kDegree;
  if (angle <= 0 || angle >= kPi) {
    Error(
        input.line,
        fmt::format("{} = {} must lie in (0, {}) — {}", name, *value, radians ? "π" : "180",
                    radians ? "give radians, or use " + key + "_deg for degrees" : "give degrees"));
    return std::nullopt;
  }
  return angle;
}

void SceneReader::ReadResolution(const Fields& fields,
                                 const std::string& what,
                                 SensorType* type,
                                 bool* changed) {
  const auto resolution = fields.Get("resolution");
  if (!resolution) return;
  if (!resolution->node.IsSequence() || resolution->node.size() != 2) {
    Error(resolution->line,
          fmt::format("{}.resolution: expected [width, height] in pixels — write e.g. "
                      "[640, 480]",
                      what));
    return;
  }
  constexpr int64_t kMaxSide = 100'000;
  const auto w = Integer(ElementOf(*resolution, 0), what + ".resolution width", 1, kMaxSide);
  const auto h = Integer(ElementOf(*resolution, 1), what + ".resolution height", 1, kMaxSide);
  if (!w || !h) return;
  type->width = static_cast<int>(*w);
  type->height = static_cast<int>(*h);
  *changed = true;
}

/// The catalog type named by `base`, or nullptr (no base, or an unknown one: reported).
const SensorType* SceneReader::ReadBase(const Fields& fields, const std::string& what) {
  const auto base_node = fields.Get("base");
  if (!base_node) return nullptr;
  const auto base_id = Text(*base_node, what + ".base");
  if (!base_id) return nullptr;
  const SensorType* base = FindCatalogType(*base_id);
  if (!base) {
    Error(base_node->line, fmt::format("{}: base '{}' is not a catalog id — {}", what, *base_id,
                                       Suggest(*base_id, CatalogIds())));
  }
  return base;
}

/// fx, fy, cx, cy from `intrinsics`, or from the fields of view (Gazebo's model, SENSORS.md); a
/// field of view not given keeps the base's, and vfov follows from the aspect ratio when the
/// base has square pixels.
void SceneReader::ReadIntrinsics(const Fields& fields,
                                 const std::string& what,
                                 const SensorType* base,
                                 bool resolution_changed,
                                 SensorType* type) {
  const auto hfov = ReadFov(fields, "hfov", what);
  const auto vfov = ReadFov(fields, "vfov", what);
  const auto intrinsics = fields.Get("intrinsics");
  const bool has_fov =
      fields.Has("hfov") || fields.Has("hfov_deg") || fields.Has("vfov") || fields.Has("vfov_deg");
  if (intrinsics && has_fov) {
    Error(intrinsics->line,
          fmt::format("{}: both intrinsics and a field of view are given — keep one", what));
    return;
  }
  if (intrinsics) {
    const auto k = Numbers(*intrinsics, 4, what + ".intrinsics");
    if (k && ((*k)[0] <= 0 || (*k)[1] <= 0)) {
      Error(intrinsics->line,
            fmt::format("{}.intrinsics: fx and fy must be positive [px] — write [fx, fy, cx, cy]",
                        what));
    } else if (k) {
      type->fx = (*k)[0];
      type->fy = (*k)[1];
      type->cx = (*k)[2];
      type->cy = (*k)[3];
    }
    return;
  }
  if (!hfov && !vfov && !(base && resolution_changed)) return;
  if (!hfov && !base) {
    Error(fields.line(), fmt::format("{}: vfov needs hfov — add hfov or hfov_deg", what));
    return;
  }
  const double h = hfov ? *hfov : base->HorizontalFov();
  std::optional<double> v = vfov;
  if (!v && !hfov && base->fx != base->fy) v = base->VerticalFov();
  const SensorType fov = SensorType::FromFov(type->id, type->width, type->height, h, v, 0, 1);
  type->fx = fov.fx;
  type->fy = fov.fy;
  type->cx = fov.cx;
  type->cy = fov.cy;
}

void SceneReader::ReadRangeAndCost(const Fields& fields,
                                   const std::string& what,
                                   SensorType* type) {
  if (const auto v = fields.Get("range")) {
    if (const auto range = Numbers(*v, 2, what + ".range")) {
      const double near = (*range)[0], far = (*range)[1];
      if (near <= 0 || near >= far) {
        Error(v->line, fmt::format("{}.range [{}, {}] must be [near, far] with 0 < near < far "
                                   "[m] — fix or swap the values",
                                   what, near, far));
      }
      type->near = near;
      type->far = far;
    }
  }
  if (const auto v = fields.Get("fps")) {
    if (const auto fps = Positive(*v, what + ".fps")) type->fps = *fps;
  }
  if (const auto v = fields.Get("cost")) {
    const auto cost = Number(*v, what + ".cost");
    if (cost && !(*cost >= 0 && *cost <= kMaxUnitCost)) {
      Error(v->line, fmt::format("{}.cost = {} must be from 0 to {:g} — give the unit's price",
                                 what, *cost, kMaxUnitCost));
    } else if (cost) {
      type->cost = *cost;
      type->cost_given = true;  // a price given here, also over a catalog entry that has none
    }
  }
  // sigma(z) = a + b z + c z^2 [m], optionally + k / sqrt(z) theta^2 / (pi/2 - theta)^2 with a
  // fourth number k (docs/sensor-models.md); Validate checks it stays >= 0.
  if (const auto v = fields.Get("depth_noise")) {
    const size_t count = v->node.IsSequence() && v->node.size() == 4 ? 4 : 3;
    if (const auto abc = Numbers(*v, count, what + ".depth_noise")) {
      type->depth_noise = DepthNoise{(*abc)[0], (*abc)[1], (*abc)[2], "scene file"};
      if (count == 4) type->depth_noise->incidence = (*abc)[3];
    }
  }
  // Time of flight's flying-pixel filter [m] (issue 43); Validate bounds it.
  if (const auto v = fields.Get("flying_pixel_threshold")) {
    if (const auto threshold = Positive(*v, what + ".flying_pixel_threshold"))
      type->flying_pixel_threshold = *threshold;
  }
}

/// `second_aperture:` of a custom type (issue 43; docs/sensor-models.md): its kind, pose and
/// field, each number checked at its own line; what a base type has is kept where not given.
void SceneReader::ReadSecondAperture(const Value& input, const std::string& type_what,
                                     SensorType* type) {
  const std::string what = type_what + ".second_aperture";
  const Fields fields(input, what,
                      {"kind", "baseline", "toe_in", "toe_in_deg", "hfov", "hfov_deg", "vfov",
                       "vfov_deg", "cone", "cone_deg", "resolution", "intrinsics",
                       "disparity_range"},
                      &reporter_);
  const size_t errors_before = ErrorCount();
  SecondAperture aperture = type->second_aperture.value_or(SecondAperture{});
  aperture.source = "scene file";
  if (const auto v = fields.Get("kind")) {
    const auto kind = Text(*v, what + ".kind");
    if (!kind) return;
    const std::vector<std::string> kinds = {"projector", "imager", "illuminator", "none"};
    SecondAperture::Kind parsed = SecondAperture::Kind::kNone;
    if (*kind == "projector") {
      parsed = SecondAperture::Kind::kProjector;
    } else if (*kind == "imager") {
      parsed = SecondAperture::Kind::kImager;
    } else if (*kind != "illuminator" && *kind != "none") {
      Error(v->line, fmt::format("{}.kind '{}' is not projector, imager, illuminator or none — {}",
                                 what, *kind, Suggest(*kind, kinds)));
      return;
    }
    // Another kind: nothing of the base's aperture applies.
    if (parsed != aperture.kind) aperture = SecondAperture{parsed, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0,
                                                           std::nullopt, "scene file"};
  } else if (!type->second_aperture) {
    Missing(fields, "kind", "kind: projector (or imager, illuminator)");
    return;
  }
  if (!aperture.active()) {
    for (const char* key : {"baseline", "toe_in", "toe_in_deg", "hfov", "hfov_deg", "vfov",
                            "vfov_deg", "cone", "cone_deg", "resolution", "intrinsics",
                            "disparity_range"}) {
      if (const auto v = fields.Get(key))
        Error(v->line, fmt::format("{}.{}: an illuminator (kind {}) has no field or pose — "
                                   "remove it", what, key, KindName(aperture.kind)));
    }
    type->second_aperture = aperture;
    return;
  }
  if (const auto v = fields.Get("baseline")) {
    const auto b = Number(*v, what + ".baseline");
    if (b && (*b < 0 || *b > kMaxBaseline)) {
      Error(v->line, fmt::format("{}.baseline = {} m must lie in [0, {:g}] m (no sensor body is "
                                 "wider) — give the distance between the optical centres",
                                 what, *b, kMaxBaseline));
    } else if (b) {
      aperture.baseline = *b;
    }
  }
  // Angles: radians under the plain key, degrees under KEY_deg, one of the two.
  const auto angle = [&](const std::string& key, double max, bool zero_ok) -> std::optional<double> {
    const auto radians = fields.Get(key);
    const auto degrees = fields.Get(key + "_deg");
    if (radians && degrees) {
      Error(degrees->line, fmt::format("{}: both {} and {}_deg are given — keep one", what, key, key));
      return std::nullopt;
    }
    if (!radians && !degrees) return std::nullopt;
    const Value& v = radians ? *radians : *degrees;
    const std::string name = fmt::format("{}.{}{}", what, key, radians ? "" : "_deg");
    const auto value = Number(v, name);
    if (!value) return std::nullopt;
    const double a = radians ? *value : *value * kDegree;
    if (a < 0 || (a == 0 && !zero_ok) || a > max || (a == max && max == kPi)) {
      Error(v.line, fmt::format("{} = {} must lie in {}0, {:g}{} {}", name, *value,
                                zero_ok ? "[" : "(", radians ? max : max / kDegree,
                                max == kPi ? ")" : "]", radians ? "rad" : "deg"));
      return std::nullopt;
    }
    return a;
  };
  if (const auto a = angle("toe_in", kMaxToeIn, true)) aperture.toe_in = *a;
  const auto hfov = angle("hfov", kPi, false);
  const auto vfov = angle("vfov", kPi, false);
  const auto cone = angle("cone", kPi, false);
  if (hfov || vfov || cone) aperture.hfov = aperture.vfov = aperture.cone = 0;
  if (hfov) aperture.hfov = *hfov;
  if (vfov) aperture.vfov = *vfov;
  if (cone) aperture.cone = *cone;
  if (const auto v = fields.Get("resolution")) {
    const auto w = Numbers(*v, 2, what + ".resolution");
    if (w && ((*w)[0] < 1 || (*w)[1] < 1 || (*w)[0] > 100'000 || (*w)[1] > 100'000 ||
              (*w)[0] != std::floor((*w)[0]) || (*w)[1] != std::floor((*w)[1]))) {
      Error(v->line, fmt::format("{}.resolution: expected [width, height], whole pixels in "
                                 "[1, 100000]", what));
    } else if (w) {
      aperture.width = static_cast<int>((*w)[0]);
      aperture.height = static_cast<int>((*w)[1]);
    }
  }
  if (const auto v = fields.Get("intrinsics")) {
    const auto k = Numbers(*v, 4, what + ".intrinsics");
    if (k && ((*k)[0] <= 0 || (*k)[1] <= 0)) {
      Error(v->line, fmt::format("{}.intrinsics: fx and fy must be positive [px] — write [fx, fy, "
                                 "cx, cy]", what));
    } else if (k) {
      aperture.fx = (*k)[0];
      aperture.fy = (*k)[1];
      aperture.cx = (*k)[2];
      aperture.cy = (*k)[3];
    }
  }
  if (fields.Has("resolution") != fields.Has("intrinsics"))
    Error(fields.line(), fmt::format("{}: an imager's own field needs both resolution and "
                                     "intrinsics (leave both out for the camera's own)", what));
  if (const auto v = fields.Get("disparity_range")) {
    const auto d = Number(*v, what + ".disparity_range");
    if (d && (*d <= 0 || *d > type->width)) {
      Error(v->line, fmt::format("{}.disparity_range = {} px must lie in (0, {}] px (the image's "
                                 "width) — give the stereo matcher's disparity search range",
                                 what, *d, type->width));
    } else if (d) {
      aperture.disparity_range = *d;
    }
  }
  if (ErrorCount() != errors_before) return;
  // What depends on the kind or on the camera (a field the kind cannot have, intrinsics whose
  // rays vantage cannot cast): the aperture's own line.
  const std::string problem = SecondApertureProblem(*type, aperture);
  if (!problem.empty()) {
    Error(fields.line(), fmt::format("{}: {}", what, problem));
    return;
  }
  type->second_aperture = aperture;
}

/// A custom type: every field given, or `base: CATALOG_ID` and the fields that differ.
std::optional<SensorType> SceneReader::ReadSensorType(const Value& input) {
  const size_t errors_before = ErrorCount();
  const Fields fields(input, "sensor type",
                      {"id", "base", "name", "technology", "resolution", "hfov", "hfov_deg", "vfov",
                       "vfov_deg", "intrinsics", "range", "fps", "cost", "depth_noise", "interferes",
                       "second_aperture", "flying_pixel_threshold"},
                      &reporter_);
  const auto id_node = fields.Get("id");
  if (!id_node) {
    Missing(fields, "id", "id: my_camera");
    return std::nullopt;
  }
  const auto id = Text(*id_node, "sensor type id");
  if (!id) return std::nullopt;
  const std::string what = fmt::format("sensor type '{}'", *id);
  // A type with errors is reported here once: populations and sensors that name it add none.
  const auto rejected = [&] {
    rejected_type_ids_.push_back(*id);
    return std::nullopt;
  };

  SensorType type;
  type.name = *id;
  const SensorType* base = ReadBase(fields, what);
  if (base) {
    type = *base;
  } else if (fields.Has("base")) {
    return rejected();  // reported by ReadBase
  } else {
    if (!fields.Has("resolution")) Missing(fields, "resolution", "resolution: [640, 480]");
    if (!fields.Has("range")) Missing(fields, "range", "range: [0.3, 3.0]");
    if (!fields.Has("intrinsics") && !fields.Has("hfov") && !fields.Has("hfov_deg"))
      Missing(fields, "hfov", "hfov_deg: 70 (or intrinsics: [fx, fy, cx, cy])");
  }
  type.id = *id;
  if (const auto v = fields.Get("name")) type.name = Text(*v, what + ".name").value_or(type.name);
  if (const auto v = fields.Get("technology"))
    type.technology = Text(*v, what + ".technology").value_or(type.technology);
  if (const auto v = fields.Get("interferes")) {
    if (const auto interferes = Boolean(*v, what + ".interferes")) type.interferes = *interferes;
  }
  bool resolution_changed = false;
  ReadResolution(fields, what, &type, &resolution_changed);
  ReadIntrinsics(fields, what, base, resolution_changed, &type);
  ReadRangeAndCost(fields, what, &type);
  if (const auto v = fields.Get("second_aperture")) ReadSecondAperture(*v, what, &type);
  if (ErrorCount() != errors_before) return rejected();
  try {
    type.Validate();
  } catch (const InputError& e) {
    std::string message = e.what();
    if (message.find(" — ") == std::string::npos) message += " — fix the type's fields";
    Error(fields.line(), message);
    return rejected();
  }
  return type;
}

// ----- objects -------------------------------------------------------------------------------

void SceneReader::ReadObjects(const Value& input) {
  objects_line_ = input.line;
  const std::vector<Value> items = Items(input, "objects");
  if (items.empty() && input.node.IsSequence()) {
    Error(objects_line_, "objects is empty — add at least one object with `role: target`");
  }
  std::set<std::string> names = NamesOf(problem_->scene.objects);
  for (const Value& item : items) {
    std::optional<SceneObject> object = ReadObject(item);
    if (!object) continue;
    for (SceneObject& piece : CadParts(std::move(*object), item.line)) {
      if (!names.insert(piece.name).second) {
        Error(item.line,
              fmt::format("object name '{}' is used twice — names must be unique", piece.name));
        continue;
      }
      problem_->scene.objects.push_back(std::move(piece));
    }
  }
}

// A CAD assembly (issue 46): one object per solid, named "OBJECT/PART" from the file's product
// names, so that --target OBJECT/PART picks a part; `role: by_colour` makes the parts whose colour
// in the file is the paper's green (0, 255, 0 in 8 bits) targets and the others occluders.
std::vector<SceneObject> SceneReader::CadParts(SceneObject object, int line) {
  const bool by_colour = by_colour_lines_.count(line) > 0;
  const auto parts = object.shapes.size() == 1 && object.shapes[0].kind == ShapeSource::Kind::kMesh
                         ? cad_parts_.find(object.shapes[0].mesh_path)
                         : cad_parts_.end();
  if (parts == cad_parts_.end()) {
    if (by_colour)
      Error(line, fmt::format("object '{}': role by_colour takes the roles from a CAD file's "
                              "colours — give a mesh file .step/.stp/.iges/.igs, or role target "
                              "or occluder",
                              object.name));
    std::vector<SceneObject> one;
    one.push_back(std::move(object));
    return one;
  }
  const auto is_green = [](const std::optional<std::array<double, 3>>& c) {
    const auto byte = [](double v) { return static_cast<int>(std::lround(255.0 * v)); };
    return c && byte((*c)[0]) == 0 && byte((*c)[1]) == 255 && byte((*c)[2]) == 0;
  };
  const ShapeSource& source = object.shapes[0];
  if (parts->second.size() == 1 && !by_colour) {
    std::vector<SceneObject> one;
    one.push_back(std::move(object));
    return one;
  }
  std::vector<SceneObject> pieces;
  size_t targets = 0;
  for (const detail::CadPart& part : parts->second) {
    SceneObject piece;
    piece.name = parts->second.size() == 1 ? object.name : object.name + "/" + part.name;
    piece.role = by_colour ? (is_green(part.colour) ? Role::kTarget : Role::kOccluder) : object.role;
    targets += piece.is_target() ? 1 : 0;
    piece.file = object.file;
    piece.line = object.line;
    try {
      piece.mesh = ScaledMesh(part.mesh, source.scale, source.mesh_path);
    } catch (const InputError&) {
      continue;  // a part of degenerate triangles only: the others are the object
    }
    piece.mesh.Transform(source.world_from_shape);
    // No shapes: exports write the triangles, not the whole CAD file once per part.
    pieces.push_back(std::move(piece));
  }
  if (by_colour && targets == 0)
    Error(line, fmt::format("object '{}': role by_colour, but no part of {} is green (0, 255, 0) "
                            "— colour the targets green in CAD, or give role target",
                            object.name, source.mesh_path));
  return pieces;
}

std::optional<SceneObject> SceneReader::ReadObject(const Value& input,
                                                  const std::vector<SceneObject>* standing) {
  const Fields fields(input, "object",
                      {"name", "role", "pose", "on", "mesh", "box", "cylinder", "sphere", "plane"},
                      &reporter_);
  const size_t errors_before = ErrorCount();
  const auto name = Name(fields, "object");
  const std::string what = fmt::format("object '{}'", name.value_or("?"));
  SceneObject object;
  object.name = name.value_or("");
  object.file = problem_->source;
  object.line = input.line;
  if (const auto v = fields.Get("role")) {
    if (const auto role = Text(*v, what + ".role")) {
      if (*role == "target") {
        object.role = Role::kTarget;
      } else if (*role == "by_colour") {  // a CAD file's colours decide (CadParts)
        by_colour_lines_.insert(input.line);
      } else if (*role != "occluder") {
        Error(v->line, fmt::format("{}: role '{}' is unknown — {}", what, *role,
                                   Suggest(*role, {"target", "occluder", "by_colour"})));
      }
    }
  }
  Pose pose;
  if (const auto v = fields.Get("pose")) pose = PoseOf(*v, what + ".pose").value_or(Pose{});
  ShapeSource source;
  std::optional<TriangleMesh> mesh = ReadShape(fields, what, &source);
  if (!mesh || ErrorCount() != errors_before) return std::nullopt;
  mesh->Transform(pose);
  source.world_from_shape = pose;
  if (const auto v = fields.Get("on")) {
    const double z_before = mesh->Bounds().min.z();
    if (!PlaceOn(*v, what, pose.position.z(), standing ? *standing : problem_->scene.objects,
                 &*mesh))
      return std::nullopt;
    source.world_from_shape.position.z() += mesh->Bounds().min.z() - z_before;
  }
  object.mesh = std::move(*mesh);
  object.shapes.push_back(std::move(source));
  return object;
}

/// `on: other`: the mesh, posed, moves up or down so that its lowest point rests on the highest
/// point of `other` (an object listed before it); the pose's z is then the gap between them.
bool SceneReader::PlaceOn(const Value& input, const std::string& what, double gap,
                          const std::vector<SceneObject>& standing, TriangleMesh* mesh) {
  const auto other = Text(input, what + ".on");
  if (!other) return false;
  std::vector<std::string> names;
  for (const SceneObject& object : standing) {
    if (object.name == *other) {
      const double dz = object.mesh.Bounds().max.z() + gap - mesh->Bounds().min.z();
      Pose lift;
      lift.position = Vec3(0, 0, dz);
      mesh->Transform(lift);
      return true;
    }
    names.push_back(object.name);
  }
  Error(input.line, fmt::format("{}.on: no object '{}' is listed before it — {}", what, *other,
                                names.empty() ? std::string("list that object first")
                                              : Suggest(*other, names)));
  return false;
}

/// Exactly one of mesh, box, cylinder, sphere, plane.
std::optional<TriangleMesh> SceneReader::ReadShape(const Fields& fields, const std::string& what,
                                                   ShapeSource* source) {
  std::vector<std::pair<std::string, Value>> shapes;
  for (const char* key : {"mesh", "box", "cylinder", "sphere", "plane"}) {
    if (const auto v = fields.Get(key)) shapes.emplace_back(key, *v);
  }
  if (shapes.size() != 1) {
    Error(shapes.empty() ? fields.line() : shapes[1].second.line,
          fmt::format("{} needs exactly one shape, got {} — give one of mesh, box, cylinder, "
                      "sphere, plane",
                      what, shapes.size()));
    return std::nullopt;
  }
  const auto& [shape, input] = shapes.front();
  if (shape == "mesh") return ReadMesh(input, what + ".mesh", source);
  return ReadPrimitive(shape, input, what + "." + shape, source);
}

std::optional<TriangleMesh> SceneReader::ReadPrimitive(const std::string& shape,
                                                       const Value& input,
                                                       const std::string& what,
                                                       ShapeSource* source) {
  // SYSTEM.md: primitives are tessellated with a chord error below F / 10.
  const double chord = problem_->cell_size / 10.0;
  const bool is_box = shape == "box", is_plane = shape == "plane";
  const Fields fields = is_box || is_plane  ? Fields(input, what, {"size"}, &reporter_)
                        : shape == "sphere" ? Fields(input, what, {"radius"}, &reporter_)
                                            : Fields(input, what, {"radius", "length"}, &reporter_);
  const size_t errors_before = ErrorCount();
  const auto get = [&](const char* key, const char* example) {
    const auto v = fields.Get(key);
    if (!v) Missing(fields, key, example);
    return v;
  };
  std::optional<double> radius, length;
  std::optional<std::vector<double>> size;
  if (is_box || is_plane) {
    if (const auto v = get("size", is_box ? "size: [0.1, 0.2, 0.3]" : "size: [1.0, 1.0]")) {
      size = Numbers(*v, is_box ? 3 : 2, what + ".size");
      if (size && std::any_of(size->begin(), size->end(), [](double x) { return x <= 0; })) {
        Error(v->line, fmt::format("{}.size must be positive lengths [m] — fix the size", what));
      }
    }
  } else {
    if (const auto v = get("radius", "radius: 0.05")) radius = Positive(*v, what + ".radius");
    if (shape == "cylinder") {
      if (const auto v = get("length", "length: 0.1")) length = Positive(*v, what + ".length");
    }
  }
  if (ErrorCount() != errors_before) return std::nullopt;
  if (is_box || is_plane) {
    source->kind = is_box ? ShapeSource::Kind::kBox : ShapeSource::Kind::kPlane;
    for (size_t k = 0; k < size->size(); ++k) source->size[static_cast<Eigen::Index>(k)] = (*size)[k];
  } else {
    source->kind = shape == "sphere" ? ShapeSource::Kind::kSphere : ShapeSource::Kind::kCylinder;
    source->size.x() = *radius;
    if (length) source->size.y() = *length;
  }
  try {
    if (is_box) return MakeBox(Vec3((*size)[0], (*size)[1], (*size)[2]));
    if (is_plane) return MakePlane((*size)[0], (*size)[1]);
    if (shape == "sphere") return MakeSphere(*radius, chord);
    return MakeCylinder(*radius, *length, chord);
  } catch (const InputError& e) {
    Error(fields.line(), fmt::format("{}: {}", what, e.what()));
    return std::nullopt;
  }
}

std::optional<Vec3> SceneReader::ReadScale(const Value& input, const std::string& what) {
  std::optional<Vec3> scale;
  if (input.node.IsSequence()) {
    scale = Vector(input, what);
  } else if (const auto s = Number(input, what)) {
    scale = Vec3::Constant(*s);
  }
  if (scale && (scale->array() <= 0).any()) {
    Error(input.line, fmt::format("{} must be positive — give a number or [sx, sy, sz] > 0", what));
    return std::nullopt;
  }
  return scale;
}

std::optional<TriangleMesh> SceneReader::ReadMesh(const Value& input, const std::string& what,
                                                  ShapeSource* source) {
  const Fields fields(input, what, {"file", "scale"}, &reporter_);
  const auto file_node = fields.Get("file");
  if (!file_node) {
    Missing(fields, "file", "file: ../meshes/part.stl");
    return std::nullopt;
  }
  const auto file = Text(*file_node, what + ".file");
  Vec3 scale = Vec3::Ones();
  if (const auto v = fields.Get("scale")) {
    const auto s = ReadScale(*v, what + ".scale");
    if (!s) return std::nullopt;
    scale = *s;
  }
  if (!file) return std::nullopt;
  // Paths are relative to the scene file's folder, so a scene and its meshes move together.
  const fs::path resolved = fs::path(*file).is_absolute() ? fs::path(*file) : folder_ / *file;
  std::optional<TriangleMesh> mesh = CachedMesh(
      resolved, file_node->line,
      fmt::format("{}: mesh file '{}' not found (looked for '{}') — paths are relative to the "
                  "scene file's folder",
                  what, *file, resolved.string()),
      scale);
  source->kind = ShapeSource::Kind::kMesh;
  source->mesh_path = fs::absolute(resolved).lexically_normal().string();
  source->scale = scale;
  return mesh;
}

std::optional<TriangleMesh> SceneReader::CachedMesh(const fs::path& resolved,
                                                    int line,
                                                    const std::string& not_found,
                                                    const Vec3& scale) {
  std::error_code ec;
  if (!fs::exists(resolved, ec)) {  // a folder or device: LoadMeshFile says which
    Error(line, not_found);
    return std::nullopt;
  }
  const std::string key = resolved.lexically_normal().string();
  auto cached = mesh_cache_.find(key);
  if (cached == mesh_cache_.end()) {
    try {
      if (detail::IsCadFile(key)) {
        // Meshed to a quarter cell (issue 46); the parts kept for an assembly's objects.
        std::vector<detail::CadPart> parts = detail::ReadCadFile(key, problem_->cell_size / 4.0);
        TriangleMesh joined;
        for (const detail::CadPart& part : parts) joined.Append(part.mesh);
        cad_parts_[fs::absolute(resolved).lexically_normal().string()] = std::move(parts);
        cached = mesh_cache_.emplace(key, std::move(joined)).first;
      } else {
        cached = mesh_cache_.emplace(key, ReadMeshFile(key)).first;
      }
    } catch (const InputError& e) {
      Error(line, e.what());
      return std::nullopt;
    }
  }
  // Scaled before the vertices are checked and degenerate triangles dropped (issue 15).
  try {
    return scaled_meshes_.Get(cached->second, scale, key);
  } catch (const InputError& e) {
    Error(line, e.what());
    return std::nullopt;
  }
}

// ----- robots --------------------------------------------------------------------------------

void SceneReader::ReadRobots(const Value& input) {
  for (const Value& item : Items(input, "robots")) ReadRobot(item);
}

/// `{name, urdf, pose, joints: {joint: q}, targets: [links]}`: every link with visuals becomes
/// the object "NAME::LINK", an occluder unless `targets` lists the link.
void SceneReader::ReadRobot(const Value& input) {
  const Fields fields(input, "robot", {"name", "urdf", "pose", "joints", "targets"}, &reporter_);
  const size_t errors_before = ErrorCount();
  SceneRobot robot;
  robot.name = Name(fields, "robot").value_or("?");
  robot.line = fields.line();
  const std::string what = fmt::format("robot '{}'", robot.name);
  const auto same = [&](const SceneRobot& r) { return r.name == robot.name; };
  if (std::any_of(robots_.begin(), robots_.end(), same)) {
    Error(robot.line,
          fmt::format("robot name '{}' is used twice — names must be unique", robot.name));
    return;
  }
  // A robot with errors is reported once: mounts and states that name it add none.
  rejected_robots_.push_back(robot.name);
  if (const auto v = fields.Get("pose"))
    robot.world_from_base = PoseOf(*v, what + ".pose").value_or(Pose{});
  const auto urdf = fields.Get("urdf");
  if (!urdf) Missing(fields, "urdf", "urdf: ../robots/arm.urdf");
  const auto file = urdf ? Text(*urdf, what + ".urdf") : std::nullopt;
  if (!file) return;
  // Relative to the scene file's folder, as mesh files are.
  const fs::path path = fs::path(*file).is_absolute() ? fs::path(*file) : folder_ / *file;
  try {
    robot.model = LoadUrdf(path.lexically_normal().string());
  } catch (const InputError& e) {
    Error(urdf->line, fmt::format("{}: {}", what, e.what()));
    return;
  }
  if (const auto v = fields.Get("joints")) {
    if (const auto joints = ReadJoints(*v, robot.model, what + ".joints")) robot.joints = *joints;
  }
  std::vector<std::string> targets;
  if (const auto v = fields.Get("targets")) {
    if (!v->node.IsSequence()) {
      Error(v->line, fmt::format("{}.targets must be a list of link names, got {} — write e.g. "
                                 "[tool0]",
                                 what, Shown(v->node)));
    } else {
      for (size_t i = 0; i < v->node.size(); ++i) {
        const Value element = ElementOf(*v, i);
        const auto link = Text(element, fmt::format("{}.targets[{}]", what, i));
        if (!link) continue;
        const auto& links = robot.model.links;
        if (std::find(links.begin(), links.end(), *link) == links.end()) {
          Error(element.line,
                fmt::format("{}: no link '{}' — {}", what, *link, Suggest(*link, links)));
        } else {
          targets.push_back(*link);
        }
      }
    }
  }
  const std::string urdf_folder = path.parent_path().string();
  for (const std::string& link : robot.model.links) {
    TriangleMesh mesh;
    bool has_visual = false;
    for (const RobotVisual& visual : robot.model.visuals) {
      if (visual.link != link) continue;
      has_visual = true;
      std::optional<TriangleMesh> part =
          ReadRobotVisual(visual, urdf_folder, urdf->line, fmt::format("{} link '{}'", what, link));
      if (part) mesh.Append(*part);
    }
    if (has_visual) robot.link_meshes.emplace_back(link, std::move(mesh));
    if (!has_visual && std::find(targets.begin(), targets.end(), link) != targets.end())
      Error(fields.Get("targets")->line,
            fmt::format("{}: link '{}' has no <visual> — it cannot be a target", what, link));
  }
  // The collision geometry the arm's checks use (issue 45): <collision>, else the visuals.
  PlacedRobot placed;
  for (const std::string& link : robot.model.links) {
    const auto of_link = [&](const std::vector<RobotVisual>& shapes) {
      std::vector<PlacedRobot::LinkShape> out;
      for (const RobotVisual& shape : shapes) {
        if (shape.link != link) continue;
        std::optional<TriangleMesh> mesh = ReadRobotVisual(
            shape, urdf_folder, urdf->line, fmt::format("{} link '{}' <collision>", what, link));
        if (mesh) out.push_back({shape, std::move(*mesh)});
      }
      return out;
    };
    std::vector<PlacedRobot::LinkShape> shapes = of_link(robot.model.collisions);
    if (shapes.empty()) shapes = of_link(robot.model.visuals);
    if (!shapes.empty()) placed.collision_shapes.emplace_back(link, std::move(shapes));
  }
  if (ErrorCount() != errors_before) return;
  placed.name = robot.name;
  placed.model = robot.model;
  placed.world_from_base = robot.world_from_base;
  placed.joints = robot.joints;
  placed.visual_meshes = robot.link_meshes;
  placed.target_links = targets;
  placed.file = problem_->source;
  placed.line = robot.line;
  problem_->robots.push_back(std::move(placed));
  std::set<std::string> object_names = NamesOf(problem_->scene.objects);
  for (auto& [name, mesh] : robot.WorldMeshes(robot.joints)) {
    SceneObject object;
    object.name = std::move(name);
    const std::string link = object.name.substr(robot.name.size() + 2);
    const bool is_target = std::find(targets.begin(), targets.end(), link) != targets.end();
    object.role = is_target ? Role::kTarget : Role::kOccluder;
    object.mesh = std::move(mesh);
    object.file = problem_->source;
    object.line = robot.line;
    if (!object_names.insert(object.name).second) {
      Error(robot.line, fmt::format("{}: object name '{}' is already used — rename the object or "
                                    "the robot",
                                    what, object.name));
      return;
    }
    problem_->scene.objects.push_back(std::move(object));
  }
  rejected_robots_.pop_back();
  robots_.push_back(std::move(robot));
}

/// `{joint: position, ...}` [rad or m], each checked against the robot's joints at its own line
/// (JointPositionProblems); nullopt when any is wrong (reported).
std::optional<JointPositions> SceneReader::ReadJoints(const Value& input,
                                                      const RobotModel& robot,
                                                      const std::string& what) {
  if (!input.node.IsMap()) {
    Error(input.line, fmt::format("{} must be a mapping `joint: position` [rad or m], got {} — "
                                  "write e.g. {{elbow: 0.5}}",
                                  what, Shown(input.node)));
    return std::nullopt;
  }
  JointPositions joints;
  bool ok = true;
  for (const auto& entry : input.node) {
    const Value key{entry.first, LineOf(entry.first)};
    const auto name = Text(key, what + " key");
    const auto q =
        Number(Value{entry.second, key.line}, fmt::format("{}.{}", what, name.value_or("?")));
    if (!name || !q) {
      ok = false;
      continue;
    }
    if (!joints.emplace(*name, *q).second) {
      Error(key.line, fmt::format("{}: '{}' appears twice — keep one", what, *name));
      ok = false;
      continue;
    }
    for (const std::string& problem : JointPositionProblems(robot, {{*name, *q}})) {
      Error(key.line, fmt::format("{}: {}", what, problem));
      ok = false;
    }
  }
  if (!ok) return std::nullopt;
  return joints;
}

/// One visual in its link's frame: primitives tessellated as objects' are (chord F / 10), meshes
/// through the mesh loader, package:// paths through --package-path.
std::optional<TriangleMesh> SceneReader::ReadRobotVisual(const RobotVisual& visual,
                                                         const std::string& urdf_folder,
                                                         int line,
                                                         const std::string& what) {
  const double chord = problem_->cell_size / 10.0;
  std::optional<TriangleMesh> mesh;
  try {
    switch (visual.shape) {
      case RobotVisual::Shape::kBox:
        if ((visual.size.array() <= 0).any())
          throw InputError(fmt::format("box size {} {} {} must be positive — fix the URDF",
                                       visual.size.x(), visual.size.y(), visual.size.z()));
        mesh = MakeBox(visual.size);
        break;
      case RobotVisual::Shape::kCylinder:
        if (!(visual.radius > 0) || !(visual.length > 0))
          throw InputError("a cylinder's radius and length must be positive — fix the URDF");
        mesh = MakeCylinder(visual.radius, visual.length, chord);
        break;
      case RobotVisual::Shape::kSphere:
        if (!(visual.radius > 0))
          throw InputError("a sphere's radius must be positive — fix the URDF");
        mesh = MakeSphere(visual.radius, chord);
        break;
      case RobotVisual::Shape::kMesh: {
        const fs::path resolved =
            ResolveRobotFile(visual.mesh, urdf_folder, options_.package_paths);
        mesh = CachedMesh(resolved, line,
                          fmt::format("{}: mesh '{}' not found (looked for '{}')", what,
                                      visual.mesh, resolved.string()),
                          visual.scale);
        break;
      }
    }
  } catch (const InputError& e) {
    Error(line, fmt::format("{}: {}", what, e.what()));
    return std::nullopt;
  }
  if (mesh) mesh->Transform(visual.link_from_visual);
  return mesh;
}

// ----- populations and sensors ---------------------------------------------------------------

/// A type id that a population or sensor names: declared under sensor_types, or a catalog id.
std::optional<std::string> SceneReader::TypeReference(const Fields& fields,
                                                      const std::string& what) {
  const auto node = fields.Get("type");
  if (!node) {
    Missing(fields, "type", "type: intel_realsense_d415");
    return std::nullopt;
  }
  const auto id = Text(*node, what + ".type");
  if (!id) return std::nullopt;
  if (IsCustomType(*id) || FindCatalogType(*id)) return id;
  // Declared but rejected: its own error is reported already.
  if (std::find(rejected_type_ids_.begin(), rejected_type_ids_.end(), *id) !=
      rejected_type_ids_.end())
    return std::nullopt;
  std::vector<std::string> ids = CatalogIds();
  for (const SensorType& type : problem_->sensor_types) ids.push_back(type.id);
  const std::string* nearest = NearestId(*id, ids);
  Error(node->line,
        fmt::format("{}: unknown sensor type '{}' — {} (`vantage sensors` lists the catalog; "
                    "declare your own under sensor_types)",
                    what, *id,
                    nearest ? fmt::format("did you mean '{}'?", *nearest)
                            : "valid: " + detail::JoinQuoted(ids)));
  return std::nullopt;
}

void SceneReader::ReadPopulations(const Value& input) {
  std::set<std::string> names = NamesOf(problem_->populations);
  for (const Value& item : Items(input, "populations")) {
    std::optional<Population> population = ReadPopulation(item);
    if (!population) continue;
    if (!names.insert(population->name).second) {
      Error(item.line, fmt::format("population name '{}' is used twice — names must be unique",
                                   population->name));
      continue;
    }
    problem_->populations.push_back(std::move(*population));
  }
}

std::optional<Distribution> ParseDistribution(const std::string& name) {
  static const std::map<std::string, Distribution> kNames = {
      {"random", Distribution::kRandom},    {"uniform", Distribution::kUniform},
      {"grid", Distribution::kGrid},        {"linear-x", Distribution::kLinearX},
      {"linear-y", Distribution::kLinearY}, {"linear-z", Distribution::kLinearZ}};
  const auto it = kNames.find(name);
  if (it == kNames.end()) return std::nullopt;
  return it->second;
}

std::optional<Population> SceneReader::ReadPopulation(const Value& input) {
  const Fields fields(input, "population",
                      {"name", "type", "pose", "distribution", "box", "cylinder", "count", "rows",
                       "cols", "step", "mount", "arm", "reach"},
                      &reporter_);
  const size_t errors_before = ErrorCount();
  Population population;
  population.name = Name(fields, "population").value_or("?");
  population.file = problem_->source;
  population.line = fields.line();
  const std::string what = fmt::format("population '{}'", population.name);
  population.sensor_type = TypeReference(fields, what).value_or("");
  if (const auto v = fields.Get("pose"))
    population.pose = PoseOf(*v, what + ".pose").value_or(Pose{});
  if (const auto v = fields.Get("mount"))
    population.model_from_camera = PoseOf(*v, what + ".mount").value_or(Pose{});
  if (const auto v = fields.Get("distribution")) {
    if (const auto name = Text(*v, what + ".distribution")) {
      if (const auto distribution = ParseDistribution(*name)) {
        population.distribution = *distribution;
      } else {
        Error(v->line, fmt::format("{}: distribution '{}' is unknown — {}", what, *name,
                                   Suggest(*name, {"random", "uniform", "grid", "linear-x",
                                                   "linear-y", "linear-z"})));
        return std::nullopt;
      }
    }
  }
  if (const auto v = fields.Get("arm")) {
    // Kind `arm`: views from the arm's joint space; no region, no distribution of positions.
    for (const char* key : {"box", "cylinder", "rows", "cols", "step", "distribution", "pose",
                            "mount", "reach"}) {
      if (const auto other = fields.Get(key))
        Error(other->line, fmt::format("{}: an `arm` population takes no '{}' (its views come "
                                       "from the arm's joints; the camera's pose on the link is "
                                       "arm.mount) — remove it",
                                       what, key));
    }
    population.arm = ReadArmMount(*v, what + ".arm", true);
    population.arm_views = true;
    population.region = RegionShape::kNone;
    if (population.arm && population.arm->sampling != JointSampling::kList) {
      const auto count = fields.Get("count");
      if (!count) {
        Missing(fields, "count", "count: 200");
      } else if (const auto n = Integer(*count, what + ".count", 1, 1'000'000)) {
        population.count = static_cast<int>(*n);
      }
    } else if (const auto count = fields.Get("count"); count && population.arm) {
      // Only once the mount was read: a robot that failed to load left no sampling to blame.
      Error(count->line, fmt::format("{}: the views are arm.configurations — remove `count`",
                                     what));
    }
    if (!population.arm || ErrorCount() != errors_before) return std::nullopt;
    population.arm->file = problem_->source;
    if (population.arm->sampling == JointSampling::kList)
      population.count = static_cast<int>(population.arm->configurations.size());
    return population;
  }
  if (const auto v = fields.Get("reach")) {
    population.arm = ReadArmMount(*v, what + ".reach", false);
    if (population.arm) population.arm->file = problem_->source;
  }
  const bool ok = population.distribution == Distribution::kGrid
                      ? ReadGrid(fields, what, &population)
                      : ReadRegion(fields, what, &population);
  if (!ok || ErrorCount() != errors_before) return std::nullopt;
  return population;
}

/// Box or cylinder region and a count (GAZEBO.md, "Sensor populations").
bool SceneReader::ReadRegion(const Fields& fields, const std::string& what, Population* p) {
  for (const char* key : {"rows", "cols", "step"}) {
    if (const auto v = fields.Get(key)) {
      Error(v->line, fmt::format("{}: '{}' belongs to the grid distribution — remove it or set "
                                 "`distribution: grid`",
                                 what, key));
    }
  }
  const auto box = fields.Get("box");
  const auto cylinder = fields.Get("cylinder");
  if (box.has_value() == cylinder.has_value()) {
    Error(fields.line(), fmt::format("{} needs one region, box or cylinder — add e.g. `box: "
                                     "{{size: [1, 1, 0.5]}}`",
                                     what));
    return false;
  }
  const bool is_linear =
      p->distribution != Distribution::kRandom && p->distribution != Distribution::kUniform;
  if (cylinder && is_linear) {
    Error(cylinder->line, fmt::format("{}: linear distributions need a box region (GAZEBO.md "
                                      "defines no linear cylinder) — use a box",
                                      what));
    return false;
  }
  if (box) {
    const Fields region(*box, what + ".box", {"size"}, &reporter_);
    p->region = RegionShape::kBox;
    if (const auto size = region.Get("size")) {
      const auto v = Vector(*size, what + ".box.size");
      if (v && (v->array() <= 0).any())
        Error(size->line,
              fmt::format("{}.box.size must be three positive lengths [m] — fix the size", what));
      if (v) p->box_size = *v;
    } else {
      Missing(region, "size", "size: [1.0, 1.0, 0.5]");
    }
  } else {
    const Fields region(*cylinder, what + ".cylinder", {"radius", "length"}, &reporter_);
    p->region = RegionShape::kCylinder;
    const auto radius = region.Get("radius");
    const auto length = region.Get("length");
    if (!radius) Missing(region, "radius", "radius: 0.5");
    if (!length) Missing(region, "length", "length: 0.3");
    if (radius) p->radius = Positive(*radius, what + ".cylinder.radius").value_or(0);
    if (length) p->length = Positive(*length, what + ".cylinder.length").value_or(0);
  }
  const auto count = fields.Get("count");
  if (!count) {
    Missing(fields, "count", "count: 20");
    return false;
  }
  constexpr int64_t kMaxCount = 1'000'000;  // the bound PopulationPositions enforces
  const auto n = Integer(*count, what + ".count", 1, kMaxCount);
  if (n) p->count = static_cast<int>(*n);
  return n.has_value();
}

/// Grid: rows × cols sensors spaced by step, no region, no count (GAZEBO.md).
bool SceneReader::ReadGrid(const Fields& fields, const std::string& what, Population* p) {
  for (const char* key : {"box", "cylinder", "count"}) {
    if (const auto v = fields.Get(key)) {
      Error(v->line, fmt::format("{}: a grid takes no '{}' (it places rows × cols sensors) — "
                                 "remove it",
                                 what, key));
    }
  }
  p->region = RegionShape::kNone;
  constexpr int64_t kMaxSide = 1'000;
  const auto integer = [&](const char* key, int* out) {
    const auto v = fields.Get(key);
    if (!v) return Missing(fields, key, fmt::format("{}: 3", key));
    if (const auto n = Integer(*v, fmt::format("{}.{}", what, key), 1, kMaxSide))
      *out = static_cast<int>(*n);
  };
  integer("rows", &p->rows);
  integer("cols", &p->cols);
  if (const auto v = fields.Get("step")) {
    if (const auto step = Vector(*v, what + ".step")) {
      p->step = *step;
      // A zero step stacks a row or column at one point: copies of one candidate, never useful.
      for (const auto& [axis, count, name] : {std::tuple{0, p->cols, "columns"},
                                              std::tuple{1, p->rows, "rows"}}) {
        if (count > 1 && (*step)[axis] == 0)
          Error(v->line, fmt::format("{}.step is 0 along {}, which puts the {} {} at one point — "
                                     "give a step, or {}: 1",
                                     what, axis == 0 ? "x" : "y", count, name,
                                     axis == 0 ? "cols" : "rows"));
      }
    }
  } else {
    Missing(fields, "step", "step: [0.3, 0.3, 0]");
  }
  return p->rows >= 1 && p->cols >= 1;
}

void SceneReader::ReadSensors(const Value& input) {
  std::set<std::string> names = NamesOf(problem_->sensors);
  for (const Value& item : Items(input, "sensors")) {
    std::optional<ExplicitSensor> sensor = ReadSensor(item);
    if (!sensor) continue;
    const auto clone_of = [&](const Population& p) {
      return sensor->name.rfind(p.name + "_", 0) == 0;
    };
    if (!names.insert(sensor->name).second ||
        std::any_of(problem_->populations.begin(), problem_->populations.end(), clone_of)) {
      Error(item.line, fmt::format("sensor name '{}' is already used (by a sensor, or by a "
                                   "population's clones NAME_i) — rename it",
                                   sensor->name));
      continue;
    }
    problem_->sensors.push_back(std::move(*sensor));
  }
}

std::optional<ExplicitSensor> SceneReader::ReadSensor(const Value& input) {
  const Fields fields(input, "sensor", {"name", "type", "position", "orientation", "mount"},
                      &reporter_);
  const size_t errors_before = ErrorCount();
  ExplicitSensor sensor;
  sensor.name = Name(fields, "sensor").value_or("?");
  sensor.file = problem_->source;
  sensor.line = fields.line();
  const std::string what = fmt::format("sensor '{}'", sensor.name);
  sensor.sensor_type = TypeReference(fields, what).value_or("");
  const auto mount = fields.Get("mount");
  if (mount && mount->node.IsMap() && mount->node["link"].IsDefined()) {
    // On a robot link: the link's pose places it (no position, orientation or look-at).
    for (const char* key : {"position", "orientation"}) {
      if (const auto v = fields.Get(key))
        Error(v->line, fmt::format("{}: '{}' does not go with a link mount (the link places the "
                                   "sensor) — remove it, or give mount.pose",
                                   what, key));
    }
    ReadLinkMount(*mount, what, &sensor);
    if (ErrorCount() != errors_before) return std::nullopt;
    return sensor;
  }
  if (const auto v = fields.Get("position")) {
    sensor.pose.position = Vector(*v, what + ".position").value_or(Vec3::Zero());
  } else {
    Missing(fields, "position", "position: [0.5, 0, 1.2]");
  }
  // Without an orientation the sensor looks at the observation point, as the plugin re-orients
  // every sensor (GAZEBO.md, "Sensor orientation").
  if (const auto v = fields.Get("orientation")) {
    const Fields orientation(*v, what + ".orientation", {"rpy", "rpy_deg", "quaternion"},
                             &reporter_);
    if (!orientation.Has("rpy") && !orientation.Has("rpy_deg") && !orientation.Has("quaternion"))
      Missing(orientation, "rpy", "rpy: [0, 0.5, 3.14]");
    sensor.pose.rotation = Rotation(orientation, what + ".orientation").value_or(Quat::Identity());
    sensor.look_at = false;
  }
  if (const auto v = fields.Get("mount"))
    sensor.model_from_camera = PoseOf(*v, what + ".mount").value_or(Pose{});
  if (ErrorCount() != errors_before) return std::nullopt;
  return sensor;
}

/// `mount: {robot: NAME, link: LINK, pose: {xyz, rpy}}` (robot optional with one robot): the
/// sensor's model pose is world_from_link · pose at the scene's joint positions, and follows the
/// link through the states' joint positions.
bool SceneReader::ReadLinkMount(const Value& input,
                                const std::string& what,
                                ExplicitSensor* sensor) {
  const Fields fields(input, what + ".mount", {"robot", "link", "pose"}, &reporter_);
  const size_t errors_before = ErrorCount();
  LinkMount mount;
  mount.sensor = sensor->name;
  if (const auto v = fields.Get("pose"))
    mount.link_from_model = PoseOf(*v, what + ".mount.pose").value_or(Pose{});
  std::vector<std::string> robot_names;
  for (const SceneRobot& robot : robots_) robot_names.push_back(robot.name);
  if (const auto v = fields.Get("robot")) {
    const auto name = Text(*v, what + ".mount.robot");
    if (!name || IsRejectedRobot(*name)) return false;
    const auto it = std::find(robot_names.begin(), robot_names.end(), *name);
    if (it == robot_names.end()) {
      Error(v->line, fmt::format("{}.mount: no robot '{}' — {}", what, *name,
                                 robot_names.empty() ? std::string("the scene has no `robots:`")
                                                     : Suggest(*name, robot_names)));
      return false;
    }
    mount.robot = static_cast<size_t>(it - robot_names.begin());
  } else if (robots_.size() != 1) {
    if (robots_.empty() && rejected_robots_.size() == 1) return false;  // reported already
    Error(fields.line(), fmt::format("{}.mount: the scene has {} robots — name one with "
                                     "`robot: NAME`",
                                     what, robots_.size()));
    return false;
  }
  const auto link = fields.Get("link");
  const auto link_name = link ? Text(*link, what + ".mount.link") : std::nullopt;
  if (!link_name) return false;
  const SceneRobot& robot = robots_[mount.robot];
  const auto& links = robot.model.links;
  if (std::find(links.begin(), links.end(), *link_name) == links.end()) {
    Error(link->line, fmt::format("{}.mount: robot '{}' has no link '{}' — {}", what, robot.name,
                                  *link_name, Suggest(*link_name, links)));
    return false;
  }
  mount.link = *link_name;
  if (ErrorCount() != errors_before) return false;
  sensor->pose = LinkPoses(robot.model, robot.world_from_base, robot.joints).at(mount.link) *
                 mount.link_from_model;
  sensor->look_at = false;
  link_mounts_.push_back(std::move(mount));
  return true;
}

/// `{robot, link, mount, sampling, joints, configurations, allowed_collisions, home}` (kind
/// `arm`) or `{robot, link, mount, position_tolerance, angle_tolerance_deg, restarts,
/// allowed_collisions, home}` (`reach:`). What can be checked without moving the arm is checked
/// here, at its line: the robot and link, a link that no joint moves (a camera on a fixed base),
/// a moving joint without limits, joints and configurations outside the limits.
std::optional<ArmMount> SceneReader::ReadArmMount(const Value& input, const std::string& what,
                                                  bool joint_space) {
  const Fields fields =
      joint_space
          ? Fields(input, what,
                   {"robot", "link", "mount", "allowed_collisions", "home", "sampling", "joints",
                    "configurations"},
                   &reporter_)
          : Fields(input, what,
                   {"robot", "link", "mount", "allowed_collisions", "home", "joints",
                    "position_tolerance", "angle_tolerance_deg", "restarts", "match"},
                   &reporter_);
  const size_t errors_before = ErrorCount();
  ArmMount arm;
  arm.line = fields.line();
  arm.robot_line = fields.line();
  std::vector<std::string> robot_names;
  for (const SceneRobot& robot : robots_) robot_names.push_back(robot.name);
  size_t robot_index = 0;
  if (const auto v = fields.Get("robot")) {
    arm.robot_line = v->line;
    const auto name = Text(*v, what + ".robot");
    if (!name || IsRejectedRobot(*name)) return std::nullopt;
    const auto it = std::find(robot_names.begin(), robot_names.end(), *name);
    if (it == robot_names.end()) {
      Error(v->line, fmt::format("{}: no robot '{}' — {}", what, *name,
                                 robot_names.empty() ? std::string("the scene has no `robots:`")
                                                     : Suggest(*name, robot_names)));
      return std::nullopt;
    }
    robot_index = static_cast<size_t>(it - robot_names.begin());
  } else if (robots_.size() != 1) {
    if (robots_.empty() && !rejected_robots_.empty()) return std::nullopt;  // reported already
    Error(fields.line(),
          fmt::format("{}: the scene has {} robots — name one with `robot: NAME`", what,
                      robots_.size()));
    return std::nullopt;
  }
  const SceneRobot& robot = robots_[robot_index];
  const RobotModel& model = robot.model;
  arm.robot = robot.name;
  const auto link = fields.Get("link");
  if (!link) {
    Missing(fields, "link", "link: tool0");
    return std::nullopt;
  }
  arm.link_line = link->line;
  const auto link_name = Text(*link, what + ".link");
  if (!link_name) return std::nullopt;
  if (std::find(model.links.begin(), model.links.end(), *link_name) == model.links.end()) {
    Error(link->line, fmt::format("{}: robot '{}' has no link '{}' — {}", what, robot.name,
                                  *link_name, Suggest(*link_name, model.links)));
    return std::nullopt;
  }
  arm.link = *link_name;
  if (const auto v = fields.Get("mount")) {
    arm.link_from_camera = PoseOf(*v, what + ".mount").value_or(Pose{});
    // An offset beyond what vantage ray casts put every view "out of reach" of the IK.
    if (const std::string beyond = WorldPointProblem(arm.link_from_camera.position);
        !beyond.empty())
      Error(v->line, fmt::format("{}.mount: its offset {} — give the camera's place on the link",
                                 what, beyond));
  }
  // The movable joints between the root and the link: what can carry the camera.
  std::vector<const RobotJoint*> chain;
  for (std::string at = arm.link; at != model.root_link;) {
    const auto joint = std::find_if(model.joints.begin(), model.joints.end(),
                                    [&](const RobotJoint& j) { return j.child_link == at; });
    if (joint == model.joints.end()) break;
    if (joint->IsSettable()) chain.insert(chain.begin(), &*joint);
    at = joint->parent_link;
  }
  if (chain.empty()) {
    Error(link->line, fmt::format("{}: no joint moves link '{}' of robot '{}' (it is fixed to "
                                  "the base) — a camera there has nothing to move; name a link "
                                  "beyond a revolute or prismatic joint",
                                  what, arm.link, robot.name));
    return std::nullopt;
  }
  const auto need_limits = [&](const RobotJoint& joint, int line) {
    if (joint.limits) return true;
    Error(line, fmt::format("{}: joint '{}' of robot '{}' ({}:{}) has no <limit lower upper> "
                            "(a continuous joint) — the arm's views are drawn within limits; "
                            "make it revolute with limits, or leave it out of `joints`",
                            what, joint.name, robot.name, model.file, joint.line));
    return false;
  };
  std::vector<std::string> chain_names;
  for (const RobotJoint* joint : chain) chain_names.push_back(joint->name);
  if (const auto v = fields.Get("joints")) {
    if (!v->node.IsSequence() || v->node.size() == 0) {
      Error(v->line, fmt::format("{}.joints must be a list of joint names, got {} — write e.g. "
                                 "[{}]",
                                 what, Shown(v->node), chain_names.front()));
    } else {
      for (size_t i = 0; i < v->node.size(); ++i) {
        const Value element = ElementOf(*v, i);
        const auto name = Text(element, fmt::format("{}.joints[{}]", what, i));
        if (!name) continue;
        if (std::find(chain_names.begin(), chain_names.end(), *name) == chain_names.end()) {
          Error(element.line, fmt::format("{}.joints: '{}' is not a movable joint between robot "
                                          "'{}''s root and link '{}' — {}",
                                          what, *name, robot.name, arm.link,
                                          Suggest(*name, chain_names)));
        } else if (std::find(arm.joints.begin(), arm.joints.end(), *name) != arm.joints.end()) {
          Error(element.line, fmt::format("{}.joints: '{}' appears twice — keep one", what, *name));
        } else if (need_limits(*model.FindJoint(*name), element.line)) {
          arm.joints.push_back(*name);
        }
      }
    }
  } else {
    for (const RobotJoint* joint : chain) {
      if (need_limits(*joint, link->line)) arm.joints.push_back(joint->name);
    }
  }
  if (joint_space) {
    const auto configurations = fields.Get("configurations");
    if (const auto v = fields.Get("sampling")) {
      const auto name = Text(*v, what + ".sampling");
      static const std::map<std::string, JointSampling> kNames = {
          {"random", JointSampling::kRandom},
          {"halton", JointSampling::kHalton},
          {"grid", JointSampling::kGrid}};
      if (name && kNames.count(*name)) {
        arm.sampling = kNames.at(*name);
      } else if (name) {
        Error(v->line, fmt::format("{}.sampling: '{}' is unknown — {}", what, *name,
                                   Suggest(*name, {"random", "halton", "grid"})));
      }
      if (configurations)
        Error(v->line, fmt::format("{}: give `sampling` or `configurations`, not both", what));
    }
    if (configurations) {
      arm.sampling = JointSampling::kList;
      if (!configurations->node.IsSequence() || configurations->node.size() == 0) {
        Error(configurations->line,
              fmt::format("{}.configurations must be a list of `{{joint: position}}` mappings — "
                          "write e.g. [{{{}: 0.5}}]",
                          what, chain_names.front()));
      } else {
        for (size_t i = 0; i < configurations->node.size(); ++i) {
          const Value element = ElementOf(*configurations, i);
          const auto q =
              ReadJoints(element, model, fmt::format("{}.configurations[{}]", what, i));
          if (!q) continue;
          arm.configurations.push_back(*q);
          arm.configuration_lines.push_back(element.line);
        }
      }
    }
  } else {
    if (const auto v = fields.Get("position_tolerance"))
      arm.position_tolerance = Positive(*v, what + ".position_tolerance").value_or(1e-3);
    if (const auto v = fields.Get("angle_tolerance_deg"))
      arm.angle_tolerance =
          Positive(*v, what + ".angle_tolerance_deg").value_or(0.0573) * std::numbers::pi / 180;
    if (const auto v = fields.Get("match")) {
      const auto name = Text(*v, what + ".match");
      static const std::map<std::string, ArmMount::Match> kMatches = {
          {"pose", ArmMount::Match::kPose},
          {"direction", ArmMount::Match::kDirection},
          {"position", ArmMount::Match::kPosition}};
      if (name && kMatches.count(*name)) {
        arm.match = kMatches.at(*name);
      } else if (name) {
        Error(v->line, fmt::format("{}.match: '{}' is unknown — {}", what, *name,
                                   Suggest(*name, {"pose", "direction", "position"})));
      }
    }
    if (const auto v = fields.Get("restarts"))
      arm.ik_restarts = static_cast<int>(Integer(*v, what + ".restarts", 1, 1000).value_or(8));
  }
  if (const auto v = fields.Get("home")) {
    if (const auto q = ReadJoints(*v, model, what + ".home")) arm.home = *q;
  }
  if (const auto v = fields.Get("allowed_collisions")) {
    if (!v->node.IsSequence()) {
      Error(v->line, fmt::format("{}.allowed_collisions must be a list of pairs [a, b] of link "
                                 "or object names",
                                 what));
    } else {
      std::vector<std::string> names = model.links;
      for (const SceneObject& object : problem_->scene.objects) names.push_back(object.name);
      for (size_t i = 0; i < v->node.size(); ++i) {
        const Value pair = ElementOf(*v, i);
        if (!pair.node.IsSequence() || pair.node.size() != 2) {
          Error(pair.line, fmt::format("{}.allowed_collisions[{}] must be a pair [a, b]", what, i));
          continue;
        }
        std::array<std::string, 2> both;
        bool ok = true;
        for (size_t k = 0; k < 2; ++k) {
          const Value element = ElementOf(pair, k);
          const auto name = Text(element, fmt::format("{}.allowed_collisions[{}]", what, i));
          if (!name) {
            ok = false;
          } else if (std::find(names.begin(), names.end(), *name) == names.end()) {
            Error(element.line, fmt::format("{}.allowed_collisions: '{}' is neither a link of "
                                            "robot '{}' nor an object — {}",
                                            what, *name, robot.name, Suggest(*name, names)));
            ok = false;
          } else {
            both[k] = *name;
          }
        }
        // A shape never collides with itself: [a, a] exempts nothing, so it is a mistaken name.
        if (ok && both[0] == both[1]) {
          Error(pair.line, fmt::format("{}.allowed_collisions[{}] pairs '{}' with itself, which "
                                       "exempts nothing — name the two links or objects that may "
                                       "touch",
                                       what, i, both[0]));
          ok = false;
        }
        if (ok) arm.allowed_pairs.emplace_back(both[0], both[1]);
      }
    }
  }
  if (ErrorCount() != errors_before) return std::nullopt;
  return arm;
}

// ----- states --------------------------------------------------------------------------------

void SceneReader::ReadStates(const Value& input) {
  const std::vector<Value> items = Items(input, "states");
  if (items.empty()) {
    Error(input.line, "states is empty — list at least one state (e.g. `- name: full`), or "
                      "remove the key");
  }
  // Each state is a copy of the scene, observed in full (R and every candidate traced again):
  // 2·10⁵ states ran for hours, their copies filling the memory (session 14).
  constexpr size_t kMaxStates = 1'000;
  if (items.size() > kMaxStates) {
    Error(input.line, fmt::format("{} states: give at most {} — each state is a copy of the "
                                  "scene, observed in full",
                                  items.size(), kMaxStates));
    return;
  }
  std::set<std::string> names;  // was a scan of the states before each: quadratic
  for (const Value& item : items) {
    std::optional<SceneState> state = ReadState(item);
    if (!state) continue;
    if (!names.insert(state->name).second) {
      Error(item.line,
            fmt::format("state name '{}' is used twice — names must be unique", state->name));
      continue;
    }
    problem_->states.push_back(std::move(*state));
  }
}

/// `{name, remove: [names], move: {name: {xyz, rpy | quaternion}}, add: [objects]}`.
std::optional<SceneState> SceneReader::ReadState(const Value& input) {
  const Fields fields(input, "state", {"name", "joints", "remove", "move", "add"}, &reporter_);
  const size_t errors_before = ErrorCount();
  SceneState state;
  state.name = Name(fields, "state").value_or("?");
  state.file = problem_->source;
  state.line = fields.line();
  const std::string what = fmt::format("state '{}'", state.name);
  if (const auto v = fields.Get("joints")) ReadStateJoints(*v, what, &state);
  if (const auto v = fields.Get("remove")) {
    if (!v->node.IsSequence()) {
      Error(v->line, fmt::format("{}.remove must be a list of object names, got {} — write e.g. "
                                 "[part_3]",
                                 what, Shown(v->node)));
    } else {
      for (size_t i = 0; i < v->node.size(); ++i) {
        if (const auto name = Text(ElementOf(*v, i), fmt::format("{}.remove[{}]", what, i)))
          state.remove.push_back(*name);
      }
    }
  }
  if (const auto v = fields.Get("move")) {
    if (!v->node.IsMap()) {
      Error(v->line, fmt::format("{}.move must be a mapping `object: {{xyz: [dx, dy, dz], rpy: "
                                 "[r, p, y]}}`, got {}",
                                 what, Shown(v->node)));
    } else {
      for (const auto& entry : v->node) {
        const Value key{entry.first, LineOf(entry.first)};
        const auto name = Text(key, what + ".move key");
        if (!name) continue;
        const auto same = [&](const auto& m) { return m.first == *name; };
        if (std::any_of(state.move.begin(), state.move.end(), same)) {
          Error(key.line, fmt::format("{}.move: '{}' appears twice — keep one", what, *name));
          continue;
        }
        const auto pose = PoseOf(Value{entry.second, key.line}, what + ".move." + *name);
        if (pose) state.move.emplace_back(*name, *pose);
      }
    }
  }
  if (const auto v = fields.Get("add")) {
    // An added object's `on:` rests on the object as it stands in this state — moved, reshaped
    // by the state's joints, or added before it — not as in the base scene (issue 15), and not
    // on one the state removed.
    std::vector<SceneObject> standing = StateObjects(problem_->scene, state);
    for (const Value& item : Items(*v, what + ".add")) {
      if (std::optional<SceneObject> object = ReadObject(item, &standing)) {
        standing.push_back(*object);
        state.add.push_back(std::move(*object));
      }
    }
  }
  if (ErrorCount() != errors_before) return std::nullopt;
  return state;
}

/// `joints: {ROBOT: {joint: position}}`: the robots' links at the scene's joint positions
/// overridden by these (reshaped), and the sensors mounted on them moved.
void SceneReader::ReadStateJoints(const Value& input, const std::string& what, SceneState* state) {
  if (!input.node.IsMap()) {
    Error(input.line, fmt::format("{}.joints must be a mapping `robot: {{joint: position}}`, got "
                                  "{}",
                                  what, Shown(input.node)));
    return;
  }
  std::vector<std::string> robot_names;
  for (const SceneRobot& robot : robots_) robot_names.push_back(robot.name);
  for (const auto& entry : input.node) {
    const Value key{entry.first, LineOf(entry.first)};
    const auto name = Text(key, what + ".joints key");
    if (!name) continue;
    if (IsRejectedRobot(*name)) continue;
    const auto it = std::find(robot_names.begin(), robot_names.end(), *name);
    if (it == robot_names.end()) {
      Error(key.line, fmt::format("{}.joints: no robot '{}' — {}", what, *name,
                                  robot_names.empty() ? std::string("the scene has no `robots:`")
                                                      : Suggest(*name, robot_names)));
      continue;
    }
    const size_t index = static_cast<size_t>(it - robot_names.begin());
    const SceneRobot& robot = robots_[index];
    const auto given =
        ReadJoints(Value{entry.second, key.line}, robot.model, what + ".joints." + *name);
    if (!given) continue;
    JointPositions positions = robot.joints;
    for (const auto& [joint, q] : *given) positions[joint] = q;
    for (auto& reshaped : robot.WorldMeshes(positions))
      state->reshape.push_back(std::move(reshaped));
    const std::map<std::string, Pose> world_from_link =
        LinkPoses(robot.model, robot.world_from_base, positions);
    for (const LinkMount& mount : link_mounts_) {
      if (mount.robot == index)
        state->sensor_poses.emplace_back(mount.sensor,
                                         world_from_link.at(mount.link) * mount.link_from_model);
    }
  }
}

/// Object names a state removes, moves or adds are checked against the objects, once --target
/// has set the roles (a state must keep a target).
// ----- mounting rules (docs/constraints.md) ---------------------------------------------------

void SceneReader::ReadKeepOut(const Value& input) {
  const std::vector<Value> items = Items(input, "keep_out");
  for (size_t i = 0; i < items.size(); ++i) {
    if (std::optional<KeepOutBox> box = ReadKeepOutBox(items[i], i))
      problem_->mounting.keep_out.push_back(std::move(*box));
  }
}

/// `{name?, pose?, size, center?}` or `{name?, pose?, min, max}`: a box in the frame `pose`
/// (the world's when absent).
std::optional<KeepOutBox> SceneReader::ReadKeepOutBox(const Value& input, size_t index) {
  const Fields fields(input, fmt::format("keep_out[{}]", index),
                      {"name", "pose", "center", "size", "min", "max"}, &reporter_);
  const size_t errors_before = ErrorCount();
  KeepOutBox box;
  box.file = problem_->source;
  box.line = fields.line();
  box.name = fmt::format("keep_out[{}]", index);
  if (const auto v = fields.Get("name")) box.name = Text(*v, box.name + ".name").value_or(box.name);
  const std::string what = fmt::format("keep_out '{}'", box.name);
  if (const auto v = fields.Get("pose")) box.world_from_box = PoseOf(*v, what + ".pose").value_or(Pose{});
  const bool by_size = fields.Has("size") || fields.Has("center");
  const bool by_corners = fields.Has("min") || fields.Has("max");
  if (by_size == by_corners) {
    Error(fields.line(),
          fmt::format("{} needs either `size` (and an optional `center`) or `min` and `max` — "
                      "write e.g. `{{center: [0, 0, 0.5], size: [1, 1, 1]}}`",
                      what));
    return std::nullopt;
  }
  if (by_size) {
    const auto size = fields.Get("size");
    if (!size) {
      Missing(fields, "size", "size: [1, 1, 1]");
      return std::nullopt;
    }
    const auto extent = Vector(*size, what + ".size");
    Vec3 center = Vec3::Zero();
    if (const auto v = fields.Get("center")) center = Vector(*v, what + ".center").value_or(center);
    if (extent && (extent->array() <= 0).any())
      Error(size->line, fmt::format("{}.size must be three positive lengths [m] — fix the size",
                                    what));
    if (extent) {
      box.min = center - 0.5 * *extent;
      box.max = center + 0.5 * *extent;
    }
  } else {
    const auto min = fields.Get("min");
    const auto max = fields.Get("max");
    if (!min || !max) {
      Missing(fields, min ? "max" : "min", min ? "max: [1, 1, 1]" : "min: [0, 0, 0]");
      return std::nullopt;
    }
    const auto low = Vector(*min, what + ".min");
    const auto high = Vector(*max, what + ".max");
    if (low && high && (low->array() >= high->array()).any())
      Error(max->line, fmt::format("{}: max must exceed min on every axis — swap or fix them",
                                   what));
    if (low && high) {
      box.min = *low;
      box.max = *high;
    }
  }
  if (ErrorCount() != errors_before) return std::nullopt;
  return box;
}

void SceneReader::CheckStates() {
  for (const SceneState& state : problem_->states) {
    for (const std::string& message : StateProblems(problem_->scene, state))
      Error(state.line, message);
  }
}

// ----- the whole file ------------------------------------------------------------------------

/// --target NAME makes exactly the named objects targets (GAZEBO.md, "Targets").
void SceneReader::ApplyTargetOverride() {
  if (options_.targets.empty()) return;
  std::vector<std::string> names;
  for (const SceneObject& object : problem_->scene.objects) names.push_back(object.name);
  for (const SceneState& state : problem_->states) {
    for (const SceneObject& object : state.add) {
      if (std::find(names.begin(), names.end(), object.name) == names.end())
        names.push_back(object.name);
    }
  }
  for (const std::string& target : options_.targets) {
    if (std::find(names.begin(), names.end(), target) == names.end()) {
      Error(0, fmt::format("{} '{}' names no object of the scene — {}", options_.targets_origin, target,
                           Suggest(target, names)));
    }
  }
  const auto set_role = [&](SceneObject& object) {
    const bool is_target = std::find(options_.targets.begin(), options_.targets.end(),
                                     object.name) != options_.targets.end();
    object.role = is_target ? Role::kTarget : Role::kOccluder;
  };
  for (SceneObject& object : problem_->scene.objects) set_role(object);
  for (SceneState& state : problem_->states) {
    for (SceneObject& object : state.add) set_role(object);
  }
}

/// Problem::sensor_types holds every type the populations and sensors name, catalog ones too.
void SceneReader::AddReferencedCatalogTypes() {
  const auto add = [&](const std::string& id) {
    if (IsCustomType(id)) return;
    if (const SensorType* type = FindCatalogType(id)) problem_->sensor_types.push_back(*type);
  };
  for (const Population& p : problem_->populations) add(p.sensor_type);
  for (const ExplicitSensor& s : problem_->sensors) add(s.sensor_type);
}

void SceneReader::Read(const YAML::Node& root) {
  if (root.IsNull()) {
    Error(1, "the scene file is empty — see docs/scene-format.md for an example");
    return;
  }
  const Fields top(
      ValueOf(root), "the scene",
      {"settings", "sensor_types", "objects", "robots", "populations", "sensors", "states",
       "keep_out", "min_separation"},
      &reporter_);
  if (!root.IsMap()) return;
  // Settings first: the cell size sets the primitives' tessellation (--cell-size replaces it).
  if (const auto v = top.Get("settings")) ReadSettings(*v);
  if (options_.cell_size) problem_->cell_size = *options_.cell_size;
  if (const auto v = top.Get("sensor_types")) ReadSensorTypes(*v);
  if (const auto v = top.Get("objects")) {
    ReadObjects(*v);
  } else {
    Missing(top, "objects", "objects: [{name: part, role: target, box: {size: [0.1, 0.1, 0.1]}}]");
    return;
  }
  if (const auto v = top.Get("robots")) ReadRobots(*v);
  if (const auto v = top.Get("populations")) ReadPopulations(*v);
  if (const auto v = top.Get("sensors")) ReadSensors(*v);
  if (const auto v = top.Get("states")) ReadStates(*v);
  if (const auto v = top.Get("keep_out")) ReadKeepOut(*v);
  if (const auto v = top.Get("min_separation")) {
    problem_->mounting.min_separation = Positive(*v, "min_separation");
    const std::optional<double> metres = problem_->mounting.min_separation;
    if (metres && !MinSeparationProblem(*metres).empty()) {
      Error(v->line, MinSeparationProblem(*metres));
      problem_->mounting.min_separation.reset();
    }
    problem_->mounting.min_separation_file = problem_->source;
    problem_->mounting.min_separation_line = v->line;
  }
  AddReferencedCatalogTypes();
  ApplyTargetOverride();
  if (ErrorCount() == 0 && problem_->scene.TargetCount() == 0) {
    Error(objects_line_,
          "no object is a target — set `role: target` on at least one object, or "
          "pass --target NAME");
  }
  if (ErrorCount() == 0) CheckStates();
  if (ErrorCount() == 0 && !observation_point_given_) {
    // Candidates look at the part, not at the world's origin, unless told otherwise.
    const Aabb bounds = problem_->scene.TargetBounds();
    problem_->observation_point = 0.5 * (bounds.min + bounds.max);
    const Vec3& p = problem_->observation_point;
    problem_->notes.push_back(fmt::format(
        "settings.observation_point not given: candidates look at the centre of the targets' "
        "bounds, [{:.4g}, {:.4g}, {:.4g}] m",
        p.x(), p.y(), p.z()));
  }
}

}  // namespace

const SensorType* Problem::FindType(const std::string& id) const {
  for (const SensorType& type : sensor_types) {
    if (type.id == id) return &type;
  }
  return nullptr;
}

Problem LoadYamlScene(const std::string& path, const LoadOptions& options) {
  options.Validate();
  Problem problem;
  problem.source = path;
  Diagnostics diag(path);
  const std::string text = detail::ReadInputFile(path, "scene file");
  // yaml-cpp reads UTF-16 and UTF-32 files (a BOM or NUL bytes first, YAML 1.2 5.2) itself.
  const bool utf8 = text.substr(0, 2) != "\xFE\xFF" && text.substr(0, 2) != "\xFF\xFE" &&
                    text.substr(0, 4).find('\0') == std::string::npos;
  if (utf8) detail::CheckUtf8File(text, path);
  YAML::Node root;
  try {
    root = YAML::Load(text);
  } catch (const YAML::Exception& e) {
    diag.Error(
        e.mark.is_null() ? 0 : e.mark.line + 1,
        fmt::format("malformed YAML: {} — fix the syntax (indentation, colons, brackets)", e.msg));
    diag.ThrowIfAny();
  }
  SceneReader reader(path, options, &diag, &problem);
  try {
    reader.Read(root);
  } catch (const YAML::Exception& e) {
    // The reader checks every node's kind first, so this is unexpected; still the user's file.
    diag.Error(e.mark.is_null() ? 0 : e.mark.line + 1,
               fmt::format("cannot read this value: {} — see docs/scene-format.md", e.msg));
  }
  diag.ThrowIfAny();
  return problem;
}

}  // namespace vantage
