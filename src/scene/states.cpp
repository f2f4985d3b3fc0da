// Changing scenes (issue 9): the states of a scene, applied to its objects (reshape, remove, move,
// add).
#include "vantage/scene_states.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <string_view>

#include "util/words.hpp"
#include "vantage/error.hpp"

namespace vantage {
namespace {

// ----- states of a scene -----------------------------------------------------------------------

std::vector<std::string> NamesOf(const std::vector<SceneObject>& objects) {
  std::vector<std::string> names;
  names.reserve(objects.size());
  for (const SceneObject& object : objects) names.push_back(object.name);
  return names;
}

// "did you mean 'x'? objects are: 'a', 'b'" (the suggestion only when one is close).
std::string ObjectsHint(const std::string& name, const std::vector<std::string>& names) {
  if (names.empty()) return "the state has no objects left";
  const std::string all = detail::JoinQuoted(names);
  if (const std::string* best = detail::ClosestWord(name, names))
    return fmt::format("did you mean '{}'? objects are: {}", *best, all);
  return "objects are: " + all;
}

// Applies the state to `objects`, recording problems instead of throwing.
std::vector<SceneObject> Applied(const Scene& base,
                                 const SceneState& state,
                                 std::vector<std::string>* problems) {
  std::vector<SceneObject> objects = base.objects;
  const auto find = [&](const std::string& name) {
    return std::find_if(objects.begin(), objects.end(),
                        [&](const SceneObject& o) { return o.name == name; });
  };
  const auto unknown = [&](const std::string& verb, const std::string& name) {
    problems->push_back(fmt::format("state '{}': {}: no object named '{}' — {}", state.name, verb,
                                    name, ObjectsHint(name, NamesOf(objects))));
  };
  for (const auto& [name, mesh] : state.reshape) {
    const auto it = find(name);
    if (it == objects.end()) {
      unknown("reshape", name);
    } else {
      it->mesh = mesh;
      it->shapes.clear();  // a robot's new pose: the links' shapes are not tracked
    }
  }
  for (const std::string& name : state.remove) {
    const auto it = find(name);
    if (it == objects.end()) {
      unknown("remove", name);
    } else {
      objects.erase(it);
    }
  }
  for (const auto& [name, displacement] : state.move) {
    const auto it = find(name);
    if (it == objects.end()) {
      unknown("move", name);
    } else {
      it->mesh.Transform(displacement);
      for (ShapeSource& shape : it->shapes) shape.world_from_shape = displacement * shape.world_from_shape;
    }
  }
  for (const SceneObject& object : state.add) {
    if (find(object.name) != objects.end()) {
      problems->push_back(fmt::format("state '{}': add: an object named '{}' is already in the "
                                      "scene — give the added object another name",
                                      state.name, object.name));
    } else {
      objects.push_back(object);
    }
  }
  const bool has_target =
      std::any_of(objects.begin(), objects.end(), [](const SceneObject& o) { return o.is_target(); });
  if (problems->empty() && !has_target) {
    problems->push_back(fmt::format("state '{}' has no target once its changes are applied — keep "
                                    "a target, or add one with `role: target`",
                                    state.name));
  }
  return objects;
}

}  // namespace

std::vector<std::string> StateProblems(const Scene& base, const SceneState& state) {
  std::vector<std::string> problems;
  Applied(base, state, &problems);
  return problems;
}

std::vector<SceneObject> StateObjects(const Scene& base, const SceneState& state) {
  std::vector<std::string> ignored;  // reported by ApplyState, at the state's line
  return Applied(base, state, &ignored);
}

Scene ApplyState(const Scene& base, const SceneState& state) {
  std::vector<std::string> problems;
  Scene scene;
  scene.objects = Applied(base, state, &problems);
  Diagnostics diag(state.file);
  for (const std::string& problem : problems) diag.Error(state.line, problem);
  diag.ThrowIfAny();
  return scene;
}

bool SameGeometry(const Scene& a, const Scene& b) {
  if (a.objects.size() != b.objects.size()) return false;
  for (size_t i = 0; i < a.objects.size(); ++i) {
    const SceneObject& x = a.objects[i];
    const SceneObject& y = b.objects[i];
    if (x.name != y.name || x.role != y.role) return false;
    if (x.mesh.triangles != y.mesh.triangles) return false;
    if (x.mesh.vertices.size() != y.mesh.vertices.size()) return false;
    for (size_t v = 0; v < x.mesh.vertices.size(); ++v) {
      if (x.mesh.vertices[v] != y.mesh.vertices[v]) return false;
    }
  }
  return true;
}

}  // namespace vantage
