#pragma once
/// Changing scenes (issue 9): a scene may list several states (bin full / half / empty, a hand
/// in two poses, parts moved), each a change of the scene's objects (docs/scene-format.md,
/// States). Selection over the states is select_states.hpp.
#include <string>
#include <utility>
#include <vector>

#include "vantage/scene.hpp"

namespace vantage {

/// One state of a changing scene, as changes to the scene's objects. ApplyState applies them in
/// the order reshape, remove, move, add.
struct SceneState {
  std::string name;
  /// Object name -> its mesh in this state (world frame), replacing the base scene's and keeping
  /// its role: a robot's links at the state's joint positions (YAML `joints:`).
  std::vector<std::pair<std::string, TriangleMesh>> reshape;
  std::vector<std::string> remove;  ///< names of objects taken out
  std::vector<SceneObject> add;     ///< objects put in (world coordinates; names new)
  /// Object name -> rigid displacement applied to its (world-frame) mesh: p -> rotation * p +
  /// position, the rotation about the world origin (YAML `move: {name: {xyz, rpy}}`).
  std::vector<std::pair<std::string, Pose>> move;
  /// Explicit sensor name -> its model pose in the world in this state (a sensor mounted on a
  /// robot link moves with it); the pipeline composes it with the sensor's mount as
  /// DeployCandidates does. Sensors not listed keep their pose.
  std::vector<std::pair<std::string, Pose>> sensor_poses;
  std::string file;  ///< where it was declared, for messages
  int line = 0;
};

/// The problems ApplyState would report, without their place: unknown object names (with the
/// names there are), added names already present, no target left. Empty when the state applies.
std::vector<std::string> StateProblems(const Scene& base, const SceneState& state);

/// The base scene's objects changed by the state as far as it applies (unknown names skipped,
/// no error): what an object the state adds with `on:` rests on.
std::vector<SceneObject> StateObjects(const Scene& base, const SceneState& state);

/// The base scene changed by the state: reshape, remove, then move, then add. Throws one
/// InputError ("file:line: state 'x': ...", one line per problem) listing every StateProblems
/// entry.
Scene ApplyState(const Scene& base, const SceneState& state);

/// Exact equality of the objects (order, names, roles, vertices, triangles): when true, the
/// observations of one scene are those of the other, so a caller need not trace both.
bool SameGeometry(const Scene& a, const Scene& b);

}  // namespace vantage
