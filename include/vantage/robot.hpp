#pragma once
/// URDF robots in a scene (issue 19; docs/scene-format.md, `robots`): a robot's kinematic tree
/// and visual geometry as urdfdom reads them, its forward kinematics, and `package://` paths.
/// The YAML reader turns each link's visuals into one scene object "ROBOT::LINK".
#include <map>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "vantage/scene.hpp"
#include "vantage/types.hpp"

namespace vantage {

/// The joint speeds a tour is timed with [rad/s or m/s] (a URDF's <limit velocity>, --joint-speed):
/// slower than 1e-6 a tour's seconds outgrow any print and any cycle time; faster than 1e6 no
/// arm moves.
constexpr double kMinJointSpeed = 1e-6;
constexpr double kMaxJointSpeed = 1e6;
/// The largest joint limit, mimic offset or mimic factor taken, and a stored joint position
/// [rad, m, or 1]: far beyond any real joint's travel, small enough that ranges, their squares
/// and the planner's steps stay finite and resolvable.
constexpr double kMaxJointTravel = 1e6;

/// One joint of a URDF robot (urdfdom's `urdf::Joint`, converted).
struct RobotJoint {
  enum class Type { kRevolute, kContinuous, kPrismatic, kFixed, kFloating, kPlanar };
  std::string name;
  Type type = Type::kFixed;
  std::string parent_link;
  std::string child_link;
  Pose parent_from_joint;     ///< `<origin>`: the joint frame in the parent link's frame
  Vec3 axis = Vec3::UnitX();  ///< `<axis>`, unit length, in the joint frame
  /// `<limit lower upper>` of a revolute or prismatic joint [rad or m]; none for the others.
  std::optional<std::pair<double, double>> limits;
  /// `<limit velocity>` [rad/s or m/s]; 0 when not given (the tour then needs --joint-speed).
  double velocity = 0;
  /// `<mimic joint multiplier offset>`: q = multiplier · q(mimic) + offset; "" when none.
  std::string mimic;
  double mimic_multiplier = 1.0;
  double mimic_offset = 0.0;
  int line = 0;  ///< line of the `<joint>` element in the URDF file (0 when unknown)

  /// Revolute, continuous or prismatic, and not a mimic: a position may be given for it.
  bool IsSettable() const;
};

/// One `<visual>` of a link: a primitive or a mesh at a pose in the link's frame.
struct RobotVisual {
  enum class Shape { kBox, kCylinder, kSphere, kMesh };
  std::string link;
  Pose link_from_visual;  ///< the visual's `<origin>`
  Shape shape = Shape::kBox;
  Vec3 size = Vec3::Zero();   ///< kBox [m]
  double radius = 0;          ///< kCylinder, kSphere [m]
  double length = 0;          ///< kCylinder [m], along the visual's z
  std::string mesh;           ///< kMesh: the filename as written (package://, file://, a path)
  Vec3 scale = Vec3::Ones();  ///< kMesh
};

/// A URDF robot: links, joints (a tree) and visuals, in tree order.
struct RobotModel {
  std::string name;  ///< `<robot name>`
  std::string file;  ///< the URDF file, as given
  std::string root_link;
  std::vector<std::string> links;    ///< every link, each after its parent
  std::vector<RobotJoint> joints;    ///< every joint, each after the joint of its parent link
  std::vector<RobotVisual> visuals;  ///< in link order, then document order
  /// `<collision>` geometry, as visuals are read (`link` names its link): what the arm's
  /// collision checks use, a link's visuals standing in where it has none (issue 45).
  std::vector<RobotVisual> collisions;
  /// Joint name -> its index in `joints` (LoadUrdf fills it): FindJoint in logarithmic time, so
  /// that robots of thousands of joints load in linear-logarithmic time.
  std::map<std::string, size_t> joint_index;

  /// The joint named `name`, or nullptr.
  const RobotJoint* FindJoint(const std::string& name) const;
};

/// Reads a URDF file with urdfdom. Throws InputError "file:line: ..." for an unreadable file,
/// malformed XML (its line), and what urdfdom rejects (its message; the line of the joint or
/// link it names, when it names one), or a zero joint axis.
RobotModel LoadUrdf(const std::string& path);

/// Joint positions by joint name [rad for revolute/continuous, m for prismatic].
using JointPositions = std::map<std::string, double>;

/// What is wrong with `positions` for `robot`, one message per joint, without its place: an
/// unknown name (with the closest joint names), a joint that cannot be set (fixed, floating,
/// planar, mimic), a non-finite value, a position outside the joint's limits. Empty when fine.
std::vector<std::string> JointPositionProblems(const RobotModel& robot,
                                               const JointPositions& positions);

/// world_from_link of every link: world_from_base for the root, then per joint
/// world_from_child = world_from_parent · parent_from_joint · motion(q), motion a rotation by q
/// about the axis (revolute, continuous), a translation q · axis (prismatic), identity (fixed,
/// floating, planar: their origin). Joints not in `positions` are at 0; mimic joints follow
/// their joint. Call JointPositionProblems first (InternalError for an unknown name).
std::map<std::string, Pose> LinkPoses(const RobotModel& robot,
                                      const Pose& world_from_base,
                                      const JointPositions& positions);

/// The file a URDF mesh filename names: `package://PKG/rest` through the package folders
/// (PKG found as FOLDER/share/PKG, FOLDER/PKG or FOLDER itself when named PKG, for each of
/// `package_paths`, then ROS_PACKAGE_PATH's and AMENT_PREFIX_PATH's folders), `file://` paths,
/// absolute paths, and paths relative to `urdf_folder`. Throws InputError (no place) naming a
/// package that is in none of the folders, with the folders searched.
std::string ResolveRobotFile(const std::string& filename,
                             const std::string& urdf_folder,
                             const std::vector<std::string>& package_paths);

/// A robot as a scene places it (YAML `robots:`), kept beside the scene's objects for the
/// stages that move it (the `arm` populations, issue 45): its model, base pose, joint positions
/// and, per link, its geometry in the link frame.
struct PlacedRobot {
  std::string name;
  RobotModel model;
  Pose world_from_base;
  JointPositions joints;  ///< the `robots:` entry's positions (others at 0)
  /// Per link with visuals, their meshes together (link frame): the object "NAME::LINK".
  std::vector<std::pair<std::string, TriangleMesh>> visual_meshes;
  /// One shape of a link's collision geometry: as written, and tessellated or loaded into the
  /// link frame (its origin applied).
  struct LinkShape {
    RobotVisual shape;
    TriangleMesh mesh;
  };
  /// Per link with geometry, in tree order: its `<collision>` shapes, else its visuals.
  std::vector<std::pair<std::string, std::vector<LinkShape>>> collision_shapes;
  std::vector<std::string> target_links;  ///< links whose visuals are targets
  std::string file;  ///< the scene file
  int line = 0;      ///< the `robots:` entry
};

}  // namespace vantage
