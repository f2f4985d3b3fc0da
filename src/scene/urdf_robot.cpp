// URDF robots (issue 19): urdfdom reads the file, vantage converts its model to RobotModel and
// computes the links' poses with Eigen (include/vantage/robot.hpp).
#include <console_bridge/console.h>
#include <fmt/format.h>
#include <urdf_parser/urdf_parser.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <deque>
#include <filesystem>
#include <map>
#include <memory>
#include <set>
#include <string_view>
#include <vector>

#include "util/words.hpp"
#include "util/xml.hpp"
#include "vantage/error.hpp"
#include "vantage/robot.hpp"

namespace vantage {
namespace {

namespace fs = std::filesystem;

// ----- reading -------------------------------------------------------------------------------

/// Collects urdfdom's console_bridge messages while it parses (it reports errors only there),
/// and restores the previous handler afterwards.
class CapturedLog : public console_bridge::OutputHandler {
 public:
  CapturedLog() { console_bridge::useOutputHandler(this); }
  ~CapturedLog() override { console_bridge::restorePreviousOutputHandler(); }
  CapturedLog(const CapturedLog&) = delete;
  CapturedLog& operator=(const CapturedLog&) = delete;

  void log(const std::string& text,
           console_bridge::LogLevel level,
           const char* /*filename*/,
           int /*line*/) override {
    if (level >= console_bridge::CONSOLE_BRIDGE_LOG_ERROR) errors_.push_back(text);
  }
  const std::vector<std::string>& errors() const { return errors_; }

 private:
  std::vector<std::string> errors_;
};

/// Lines of the `<joint>` and `<link>` elements directly under `<robot>`, by name.
struct ElementLines {
  std::map<std::string, int> joints;
  std::map<std::string, int> links;
};

/// The line of `name` in `table` (ElementLines::joints or links); 0 when vantage's XML reader did
/// not see it under that name.
int LineOf(const std::map<std::string, int>& table, const std::string& name) {
  const auto it = table.find(name);
  return it == table.end() ? 0 : it->second;
}

ElementLines LinesOf(const detail::XmlDocument& document) {
  ElementLines lines;
  for (const detail::XmlElement& child : document.root.children) {
    const std::string* name = child.Attribute("name");
    if (!name) continue;
    if (child.name == "joint") lines.joints.emplace(*name, child.line);
    if (child.name == "link") lines.links.emplace(*name, child.line);
  }
  return lines;
}

/// The line of the first joint or link that a urdfdom message names in brackets or quotes
/// ("Joint [elbow] is missing ...", "child link [x] of joint [y] not found"); 0 when none.
int LineNamedIn(const std::string& message, const ElementLines& lines) {
  for (size_t open = message.find_first_of("['"); open != std::string::npos;
       open = message.find_first_of("['", open + 1)) {
    const char close = message[open] == '[' ? ']' : '\'';
    const size_t end = message.find(close, open + 1);
    if (end == std::string::npos) break;
    const std::string name = message.substr(open + 1, end - open - 1);
    for (const auto* table : {&lines.joints, &lines.links}) {
      if (const auto it = table->find(name); it != table->end()) return it->second;
    }
  }
  return 0;
}

Pose PoseOf(const urdf::Pose& pose) {
  const urdf::Rotation& r = pose.rotation;
  return Pose{Vec3(pose.position.x, pose.position.y, pose.position.z),
              Quat(r.w, r.x, r.y, r.z).normalized()};
}

RobotJoint::Type TypeOf(int type) {
  switch (type) {
    case urdf::Joint::REVOLUTE:
      return RobotJoint::Type::kRevolute;
    case urdf::Joint::CONTINUOUS:
      return RobotJoint::Type::kContinuous;
    case urdf::Joint::PRISMATIC:
      return RobotJoint::Type::kPrismatic;
    case urdf::Joint::FLOATING:
      return RobotJoint::Type::kFloating;
    case urdf::Joint::PLANAR:
      return RobotJoint::Type::kPlanar;
    default:
      return RobotJoint::Type::kFixed;
  }
}

/// A `<visual>` or `<collision>` (the same origin and geometry fields).
template <typename Element>
std::optional<RobotVisual> VisualOf(const std::string& link, const Element& visual) {
  if (!visual.geometry) return std::nullopt;
  RobotVisual out;
  out.link = link;
  out.link_from_visual = PoseOf(visual.origin);
  const urdf::Geometry& geometry = *visual.geometry;
  switch (geometry.type) {
    case urdf::Geometry::BOX: {
      const auto& box = static_cast<const urdf::Box&>(geometry);
      out.shape = RobotVisual::Shape::kBox;
      out.size = Vec3(box.dim.x, box.dim.y, box.dim.z);
      break;
    }
    case urdf::Geometry::CYLINDER: {
      const auto& cylinder = static_cast<const urdf::Cylinder&>(geometry);
      out.shape = RobotVisual::Shape::kCylinder;
      out.radius = cylinder.radius;
      out.length = cylinder.length;
      break;
    }
    case urdf::Geometry::SPHERE:
      out.shape = RobotVisual::Shape::kSphere;
      out.radius = static_cast<const urdf::Sphere&>(geometry).radius;
      break;
    case urdf::Geometry::MESH: {
      const auto& mesh = static_cast<const urdf::Mesh&>(geometry);
      out.shape = RobotVisual::Shape::kMesh;
      out.mesh = mesh.filename;
      out.scale = Vec3(mesh.scale.x, mesh.scale.y, mesh.scale.z);
      break;
    }
  }
  return out;
}

// ----- packages ------------------------------------------------------------------------------

std::vector<std::string> SplitPaths(const char* variable) {
  std::vector<std::string> paths;
  // Read while loading only; vantage never sets the environment.
  const char* value = std::getenv(variable);  // NOLINT(concurrency-mt-unsafe)
  if (!value) return paths;
  std::string_view rest(value);
  while (!rest.empty()) {
    const size_t colon = rest.find(':');
    const std::string_view item = rest.substr(0, colon);
    if (!item.empty()) paths.emplace_back(item);
    if (colon == std::string_view::npos) break;
    rest.remove_prefix(colon + 1);
  }
  return paths;
}

/// The joints' tree as the XML declares it, checked before urdfdom builds it: urdfdom 3 links a
/// link that is the child of two joints, or of itself, into a cycle of shared pointers — a
/// model that the walk below could not finish (session 14: it ran until the memory was gone)
/// and that is never freed (the urdf_robot fuzzer, session 15). Joints without a parent or child
/// link are left to urdfdom's own messages.
void CheckJointTree(const detail::XmlDocument& document, Diagnostics* diag) {
  struct Edge {
    std::string joint, parent;
    int line = 0;
  };
  std::map<std::string, Edge> parent_of;  // child link -> the joint that holds it
  for (const detail::XmlElement& element : document.root.children) {
    if (element.name != "joint") continue;
    const detail::XmlElement* parent = element.Child("parent");
    const detail::XmlElement* child = element.Child("child");
    const std::string* parent_link = parent ? parent->Attribute("link") : nullptr;
    const std::string* child_link = child ? child->Attribute("link") : nullptr;
    const std::string* name = element.Attribute("name");
    if (!parent_link || !child_link || !name) continue;
    if (*parent_link == *child_link) {
      diag->Error(element.line, fmt::format("joint '{}' joins link '{}' to itself — give it "
                                            "another child link",
                                            *name, *child_link));
      continue;
    }
    const auto [first, is_new] =
        parent_of.emplace(*child_link, Edge{*name, *parent_link, element.line});
    if (!is_new)
      diag->Error(element.line, fmt::format("joint '{}' makes link '{}' the child of a second "
                                            "joint ('{}' is the first) — a URDF is a tree, each "
                                            "link the child of one joint",
                                            *name, *child_link, first->second.joint));
  }
  if (diag->HasErrors()) return;
  // Each link has one parent joint now: going up from a link ends at the root, or meets a link
  // again — a loop, that no path from the root reaches. Each walk stops at a link an earlier
  // walk settled, so that a long chain is walked once.
  std::set<std::string> settled;  // links whose way up is known: to the root, or to a loop
  for (const auto& [start, unused] : parent_of) {
    std::vector<std::string> up = {start};  // each link's parent the next
    std::set<std::string> on_the_way = {start};
    for (auto edge = parent_of.find(start); edge != parent_of.end();
         edge = parent_of.find(edge->second.parent)) {
      const std::string& parent = edge->second.parent;
      if (settled.count(parent)) break;
      if (on_the_way.insert(parent).second) {
        up.push_back(parent);
        continue;
      }
      const auto again = std::find(up.begin(), up.end(), parent);
      // Parent to child, from the child of the loop's last joint in the file: the one to remove.
      std::vector<std::string> loop(again, up.end());
      std::reverse(loop.begin(), loop.end());
      const auto closing =
          std::max_element(loop.begin(), loop.end(), [&](const auto& a, const auto& b) {
            return parent_of.at(a).line < parent_of.at(b).line;
          });
      std::rotate(loop.begin(), closing, loop.end());
      const Edge& joint = parent_of.at(loop.front());
      diag->Error(joint.line, fmt::format("joint '{}' closes a loop of links ({} -> {}) — a URDF "
                                          "is a tree: remove one joint of the loop",
                                          joint.joint, fmt::join(loop, " -> "), loop.front()));
      break;
    }
    settled.insert(up.begin(), up.end());
  }
}

bool IsFolder(const fs::path& path) {
  std::error_code ec;
  return fs::is_directory(path, ec);
}

}  // namespace

bool RobotJoint::IsSettable() const {
  return mimic.empty() &&
         (type == Type::kRevolute || type == Type::kContinuous || type == Type::kPrismatic);
}

const RobotJoint* RobotModel::FindJoint(const std::string& joint_name) const {
  const auto it = joint_index.find(joint_name);
  return it == joint_index.end() ? nullptr : &joints.at(it->second);
}

RobotModel LoadUrdf(const std::string& path) {
  const std::string text = detail::ReadInputFile(path, "URDF file");
  detail::CheckUtf8File(text, path);
  // vantage's XML reader first: malformed XML with its line, and the elements' lines for
  // urdfdom's messages, which carry none.
  const detail::XmlDocument document = detail::ParseXml(text, path);
  const ElementLines lines = LinesOf(document);
  {
    Diagnostics tree(path);
    CheckJointTree(document, &tree);
    tree.ThrowIfAny();
  }
  urdf::ModelInterfaceSharedPtr model;
  std::vector<std::string> errors;
  {
    const CapturedLog log;
    try {
      model = urdf::parseURDF(text);
    } catch (const std::exception& e) {
      model.reset();
      errors.push_back(e.what());
    }
    errors.insert(errors.end(), log.errors().begin(), log.errors().end());
  }
  // urdfdom 3 logs a visual or collision it cannot parse (a box size of two numbers, a <sphere/>
  // without radius, an unknown shape, a radius "nan") and drops it, returning a model without
  // it: an occluder missing silently, or a link whose collision checks (issue 45) fell back to
  // its visuals or lost one of its shapes. Any error it logged refuses the file.
  if (!model || !errors.empty()) {
    Diagnostics diag(path);
    if (errors.empty()) errors.push_back("not a URDF robot");
    // urdfdom's detail ("Parser found 2 elements but 3 expected") names no element; the
    // summary after it ("Could not parse visual element for Link [base]") does: give the detail
    // that line too.
    std::vector<int> error_lines(errors.size(), 0);
    for (size_t i = errors.size(); i-- > 0;) {
      error_lines[i] = LineNamedIn(errors[i], lines);
      if (error_lines[i] == 0 && i + 1 < errors.size()) error_lines[i] = error_lines[i + 1];
    }
    for (size_t i = 0; i < errors.size(); ++i)
      diag.Error(error_lines[i], fmt::format("urdfdom: {} — fix the URDF", errors[i]));
    diag.ThrowIfAny();
  }

  // urdfdom links a link's children by shared pointers: a loop of links it built (one that
  // CheckJointTree did not see, where its XML reader and urdfdom's disagree) would never be
  // freed. Cut every link's children when the model is done with.
  struct CutLinks {
    const urdf::ModelInterface& model;
    ~CutLinks() {
      for (const auto& [name, link] : model.links_) {
        if (!link) continue;
        link->child_links.clear();
        link->child_joints.clear();
      }
    }
  } cut_links{*model};
  RobotModel robot;
  robot.name = model->getName();
  robot.file = path;
  const urdf::LinkConstSharedPtr root = model->getRoot();
  VANTAGE_CHECK(root != nullptr);
  robot.root_link = root->name;
  Diagnostics diag(path);
  // Breadth first from the root: each link after its parent, each joint after its parent's.
  std::deque<urdf::LinkConstSharedPtr> queue = {root};
  // CheckJointTree made the joints a tree: the walk meets each link once, and every joint.
  std::set<std::string> reached = {root->name};
  while (!queue.empty()) {
    const urdf::LinkConstSharedPtr link = queue.front();
    queue.pop_front();
    robot.links.push_back(link->name);
    for (const urdf::VisualSharedPtr& visual : link->visual_array) {
      if (!visual) continue;
      if (std::optional<RobotVisual> converted = VisualOf(link->name, *visual))
        robot.visuals.push_back(std::move(*converted));
    }
    for (const urdf::CollisionSharedPtr& collision : link->collision_array) {
      if (!collision) continue;
      if (std::optional<RobotVisual> converted = VisualOf(link->name, *collision))
        robot.collisions.push_back(std::move(*converted));
    }
    for (const urdf::JointSharedPtr& joint : link->child_joints) {
      RobotJoint out;
      out.name = joint->name;
      out.type = TypeOf(joint->type);
      out.parent_link = joint->parent_link_name;
      out.child_link = joint->child_link_name;
      out.parent_from_joint = PoseOf(joint->parent_to_joint_origin_transform);
      out.line = LineOf(lines.joints, joint->name);
      const std::optional<Vec3> axis =
          UnitDirection(Vec3(joint->axis.x, joint->axis.y, joint->axis.z), 1e-12);
      const bool moves = out.type == RobotJoint::Type::kRevolute ||
                         out.type == RobotJoint::Type::kContinuous ||
                         out.type == RobotJoint::Type::kPrismatic;
      if (moves && !axis) {
        diag.Error(out.line, fmt::format("joint '{}' has a zero <axis> (shorter than 1e-12) — "
                                         "give a direction, e.g. xyz=\"0 0 1\"",
                                         joint->name));
      } else if (moves) {
        out.axis = *axis;
      }
      if (joint->limits &&
          (out.type == RobotJoint::Type::kRevolute || out.type == RobotJoint::Type::kPrismatic)) {
        out.limits = std::make_pair(joint->limits->lower, joint->limits->upper);
        // Sampling, inverse kinematics and the planner's motion resolution divide by the range:
        // upper="1e300" made OMPL's segment fraction 0 and stopped the run as an internal error.
        for (const double limit : {joint->limits->lower, joint->limits->upper}) {
          if (std::abs(limit) <= kMaxJointTravel) continue;
          diag.Error(out.line,
                     fmt::format("joint '{}': its <limit> {} is beyond the ±{:g} {} that vantage "
                                 "samples and plans over — give the joint's real travel{}",
                                 joint->name, limit, kMaxJointTravel,
                                 out.type == RobotJoint::Type::kRevolute ? "rad" : "m",
                                 out.type == RobotJoint::Type::kRevolute
                                     ? ", or type=\"continuous\" for a joint without limits"
                                     : ""));
          break;
        }
      }
      // urdfdom reads an absent velocity as 0; any other value is the joint's speed, so a
      // negative or non-finite one is an error here (it read as "has no <limit velocity>").
      if (joint->limits && joint->limits->velocity != 0) {
        out.velocity = joint->limits->velocity;
        if (!(out.velocity >= kMinJointSpeed && out.velocity <= kMaxJointSpeed))
          diag.Error(out.line, fmt::format("joint '{}': its <limit velocity> {} is not a speed "
                                           "from {:g} to {:g} [rad/s or m/s] — fix the URDF",
                                           joint->name, out.velocity, kMinJointSpeed,
                                           kMaxJointSpeed));
      }
      if (joint->mimic && !(std::abs(joint->mimic->multiplier) <= kMaxJointTravel &&
                            std::abs(joint->mimic->offset) <= kMaxJointTravel)) {
        diag.Error(out.line, fmt::format("joint '{}': its <mimic> multiplier {} and offset {} "
                                         "must lie within ±{:g} — fix the URDF",
                                         joint->name, joint->mimic->multiplier,
                                         joint->mimic->offset, kMaxJointTravel));
      } else if (joint->mimic) {
        out.mimic = joint->mimic->joint_name;
        out.mimic_multiplier = joint->mimic->multiplier;
        out.mimic_offset = joint->mimic->offset;
      }
      // By name (a map), not by a search of child_links: a link with 10⁴ children.
      const urdf::LinkConstSharedPtr child = model->getLink(joint->child_link_name);
      VANTAGE_CHECK(child != nullptr);
      if (!reached.insert(child->name).second) {
        // CheckJointTree refuses this from the XML; urdfdom's reader may still see a joint
        // that vantage's did not (the urdf_robot fuzzer, session 17: a byte order mark inside
        // a tag), so the walk checks it again rather than assume it.
        diag.Error(out.line, fmt::format("joint '{}' makes link '{}' the child of a second joint "
                                         "— a URDF is a tree, each link the child of one joint",
                                         joint->name, child->name));
        continue;
      }
      queue.push_back(child);
      robot.joints.push_back(std::move(out));
    }
  }
  for (size_t i = 0; i < robot.joints.size(); ++i)
    VANTAGE_CHECK(robot.joint_index.emplace(robot.joints[i].name, i).second);
  diag.ThrowIfAny();
  // Joints the walk from the root never met hang in a loop of links apart from the tree (as
  // above: a loop CheckJointTree could not see in the XML).
  for (const auto& [name, joint] : model->joints_) {
    if (!joint || robot.FindJoint(name)) continue;
    diag.Error(LineOf(lines.joints, name),
               fmt::format("joint '{}' (link '{}' to '{}') is not reached from the root link "
                           "'{}': its links form a loop apart from the tree — a URDF is one tree",
                           name, joint->parent_link_name, joint->child_link_name, robot.root_link));
  }
  diag.ThrowIfAny();
  for (const RobotJoint& joint : robot.joints) {
    if (!joint.mimic.empty() && !robot.FindJoint(joint.mimic))
      diag.Error(joint.line, fmt::format("joint '{}' mimics '{}', which is no joint of the robot",
                                         joint.name, joint.mimic));
  }
  diag.ThrowIfAny();
  // A chain of mimics must end at a joint that mimics none; a cycle has no position to follow.
  // Each walk stops at a joint an earlier walk settled, so that a long chain is walked once.
  std::set<std::string> settled;
  for (const RobotJoint& start : robot.joints) {
    std::vector<std::string> chain;
    std::set<std::string> in_chain;
    for (const RobotJoint* joint = &start;
         joint && !joint->mimic.empty() && !settled.count(joint->name);
         joint = robot.FindJoint(joint->mimic)) {
      chain.push_back(joint->name);
      in_chain.insert(joint->name);
      if (!in_chain.count(joint->mimic)) continue;
      // Named from its joint that comes first in the robot, once per cycle.
      std::vector<std::string> cycle(std::find(chain.begin(), chain.end(), joint->mimic),
                                     chain.end());
      std::rotate(cycle.begin(),
                  std::min_element(cycle.begin(), cycle.end(),
                                   [&](const std::string& a, const std::string& b) {
                                     return robot.joint_index.at(a) < robot.joint_index.at(b);
                                   }),
                  cycle.end());
      cycle.push_back(cycle.front());
      const RobotJoint& first = *robot.FindJoint(cycle.front());
      diag.Error(first.line,
                 fmt::format("joint '{}' mimics itself through {} — a mimic chain must end at "
                             "a joint that mimics none",
                             first.name, fmt::join(cycle, " -> ")));
      break;
    }
    settled.insert(chain.begin(), chain.end());
  }
  diag.ThrowIfAny();
  return robot;
}

std::vector<std::string> JointPositionProblems(const RobotModel& robot,
                                               const JointPositions& positions) {
  std::vector<std::string> problems;
  std::vector<std::string> settable;
  for (const RobotJoint& joint : robot.joints) {
    if (joint.IsSettable()) settable.push_back(joint.name);
  }
  for (const auto& [name, q] : positions) {
    const RobotJoint* joint = robot.FindJoint(name);
    if (!joint) {
      const std::string* best = detail::ClosestWord(name, settable);
      problems.push_back(fmt::format(
          "robot '{}' has no joint '{}' — {}{}", robot.name, name,
          best ? fmt::format("did you mean '{}'? ", *best) : std::string(),
          settable.empty() ? std::string("it has no movable joints")
                           : "its movable joints are: " + detail::JoinQuoted(settable)));
    } else if (!joint->mimic.empty()) {
      problems.push_back(fmt::format("joint '{}' of robot '{}' mimics '{}' — set '{}' instead",
                                     name, robot.name, joint->mimic, joint->mimic));
    } else if (!joint->IsSettable()) {
      problems.push_back(
          fmt::format("joint '{}' of robot '{}' is not revolute, continuous or "
                      "prismatic — it has no position to set",
                      name, robot.name));
    } else if (!std::isfinite(q)) {
      problems.push_back(fmt::format("joint '{}': position {} is not a finite number", name, q));
    } else if (joint->limits && !(joint->limits->first <= joint->limits->second)) {
      // Was blamed on the position ("outside its limits [1, -1]"), which no position can meet.
      problems.push_back(fmt::format(
          "joint '{}' of robot '{}': its <limit> has lower {} above upper {} ({}:{}) "
          "— no position is within them; fix the limits in the URDF",
          name, robot.name, joint->limits->first, joint->limits->second, robot.file, joint->line));
    } else if (joint->limits && (q < joint->limits->first || q > joint->limits->second)) {
      problems.push_back(
          fmt::format("joint '{}' of robot '{}': position {} is outside its limits "
                      "[{}, {}] ({}:{}) — give a position within them",
                      name, robot.name, q, joint->limits->first, joint->limits->second, robot.file,
                      joint->line));
    }
  }
  return problems;
}

std::map<std::string, Pose> LinkPoses(const RobotModel& robot,
                                      const Pose& world_from_base,
                                      const JointPositions& positions) {
  for (const auto& [name, q] : positions) VANTAGE_CHECK(robot.FindJoint(name) != nullptr);
  // A mimic joint follows its joint, which may itself mimic another (at most one per joint):
  // q = multiplier · q(mimic) + offset, each joint's position computed once, so that a chain of
  // thousands of mimics stays linear.
  std::vector<std::optional<double>> position(robot.joints.size());
  const auto position_of = [&](const RobotJoint& start) {
    const size_t start_index = robot.joint_index.at(start.name);
    std::vector<size_t> chain;  // mimics whose position waits for the next one's
    size_t at = start_index;
    while (!position[at]) {
      const RobotJoint& joint = robot.joints[at];
      if (joint.mimic.empty()) {
        const auto given = positions.find(joint.name);
        position[at] = given == positions.end() ? 0.0 : given->second;
        break;
      }
      chain.push_back(at);
      VANTAGE_CHECK(chain.size() <= robot.joints.size());
      const auto followed = robot.joint_index.find(joint.mimic);
      VANTAGE_CHECK(followed != robot.joint_index.end());
      at = followed->second;
    }
    for (auto it = chain.rbegin(); it != chain.rend(); ++it) {
      const RobotJoint& joint = robot.joints[*it];
      const double followed = *position[robot.joint_index.at(joint.mimic)];
      position[*it] = joint.mimic_multiplier * followed + joint.mimic_offset;
    }
    return *position[start_index];
  };
  std::map<std::string, Pose> world_from_link;
  world_from_link[robot.root_link] = world_from_base;
  for (const RobotJoint& joint : robot.joints) {
    const auto parent = world_from_link.find(joint.parent_link);
    VANTAGE_CHECK(parent != world_from_link.end());
    Pose joint_from_child;  // the joint's motion; identity for fixed, floating, planar
    const double q = position_of(joint);
    if (joint.type == RobotJoint::Type::kRevolute || joint.type == RobotJoint::Type::kContinuous)
      joint_from_child.rotation = Quat(Eigen::AngleAxisd(q, joint.axis));
    if (joint.type == RobotJoint::Type::kPrismatic) joint_from_child.position = q * joint.axis;
    world_from_link[joint.child_link] = parent->second * joint.parent_from_joint * joint_from_child;
  }
  return world_from_link;
}

std::string ResolveRobotFile(const std::string& filename,
                             const std::string& urdf_folder,
                             const std::vector<std::string>& package_paths) {
  constexpr std::string_view kPackage = "package://";
  constexpr std::string_view kFile = "file://";
  const std::string_view name(filename);
  if (name.substr(0, kFile.size()) == kFile) return std::string(name.substr(kFile.size()));
  if (name.substr(0, kPackage.size()) != kPackage) {
    const fs::path path(filename);
    return (path.is_absolute() ? path : fs::path(urdf_folder) / path).lexically_normal().string();
  }
  const std::string_view rest = name.substr(kPackage.size());
  const size_t slash = rest.find('/');
  const std::string package(rest.substr(0, slash));
  const std::string inside(slash == std::string_view::npos ? "" : rest.substr(slash + 1));
  // --package-path folders take every layout; ROS_PACKAGE_PATH holds packages (or folders of
  // them), AMENT_PREFIX_PATH install prefixes (<prefix>/share/<package>).
  std::vector<fs::path> candidates;
  std::vector<std::string> searched;
  for (const std::string& folder : package_paths) {
    candidates.push_back(fs::path(folder) / "share" / package);
    candidates.push_back(fs::path(folder) / package);
    if (fs::path(folder).lexically_normal().filename() == package) candidates.emplace_back(folder);
    searched.push_back(folder);
  }
  for (const std::string& folder : SplitPaths("ROS_PACKAGE_PATH")) {
    candidates.push_back(fs::path(folder) / package);
    if (fs::path(folder).lexically_normal().filename() == package) candidates.emplace_back(folder);
    searched.push_back(folder + " (ROS_PACKAGE_PATH)");
  }
  for (const std::string& folder : SplitPaths("AMENT_PREFIX_PATH")) {
    candidates.push_back(fs::path(folder) / "share" / package);
    searched.push_back(folder + " (AMENT_PREFIX_PATH)");
  }
  for (const fs::path& root : candidates) {
    if (IsFolder(root)) return (root / inside).lexically_normal().string();
  }
  throw InputError(fmt::format(
      "package '{}' of '{}' is in none of the package folders ({}) — give its folder with "
      "--package-path (a folder holding {}/, or an install prefix holding share/{}/)",
      package, filename,
      searched.empty() ? std::string("none given") : fmt::format("{}", fmt::join(searched, ", ")),
      package, package));
}

}  // namespace vantage
