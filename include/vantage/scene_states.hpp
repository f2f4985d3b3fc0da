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
/// the order remove, move, add.
struct SceneState {
  std::string name;
  std::vector<std::string> remove;  ///< names of objects taken out
  std::vector<SceneObject> add;     ///< objects put in (world coordinates; names new)
  /// Object name -> rigid displacement applied to its (world-frame) mesh: p -> rotation * p +
  /// position, the rotation about the world origin (YAML `move: {name: {xyz, rpy}}`).
  std::vector<std::pair<std::string, Pose>> move;
  std::string file;  ///< where it was declared, for messages
  int line = 0;
};

/// The problems ApplyState would report, without their place: unknown object names (with the
/// names there are), added names already present, no target left. Empty when the state applies.
std::vector<std::string> StateProblems(const Scene& base, const SceneState& state);

/// The base scene changed by the state: remove, then move, then add. Throws one InputError
/// ("file:line: state 'x': ...", one line per problem) listing every StateProblems entry.
Scene ApplyState(const Scene& base, const SceneState& state);

/// Exact equality of the objects (order, names, roles, vertices, triangles): when true, the
/// observations of one scene are those of the other, so a caller need not trace both.
bool SameGeometry(const Scene& a, const Scene& b);

}  // namespace vantage
