#pragma once
/// Changing scenes (issue 9): a scene may list several states (bin full / half / empty, a hand
/// in two poses, parts moved). The same candidates observe every state; selection maximises the
/// mean or the worst case of the per-state coverage. Each state has its own reference set R_s
/// and its own visibility matrix; the matrices simply stack (docs/scene-format.md, States).
#include <cstdint>
#include <span>
#include <string>
#include <utility>
#include <vector>

#include "vantage/observe.hpp"
#include "vantage/reference.hpp"
#include "vantage/scene.hpp"
#include "vantage/select.hpp"

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

/// What selection over states maximises (`--over-states mean|min`).
enum class OverStates { kMean, kMin };
/// "mean" or "min"; InputError naming `--over-states` and listing mean|min otherwise.
OverStates ParseOverStates(const std::string& name);
std::string OverStatesName(OverStates over);

/// The observations of one state (non-owning): one Observation per candidate, the candidates in
/// the same order in every state, indices into `reference->keys`.
struct StateObservations {
  std::string name;
  const Reference* reference = nullptr;
  std::span<const Observation> observations;
};

/// A selection scored over states.
struct StateSelection {
  /// coverage = the aggregate (mean or min over states) of |∪O_s ∩ R_s| / |R_s|;
  /// paper_coverage = the same aggregate of each state's |∪O_s| / |R_s| (keys outside R_s
  /// included); objective = "coverage".
  Selection selection;
  std::vector<double> state_coverage;        ///< |∪O_s ∩ R_s| / |R_s| per state, in state order
  std::vector<double> state_paper_coverage;  ///< |∪O_s| / |R_s| per state, in state order
};

/// Selection maximising the aggregate over states of the coverage. Methods (options.method):
/// best (n = 1: the single candidate with the best aggregate), ransac (Algorithm 2's draws, as
/// Select's, each kept when its aggregate is strictly better), greedy (adds the candidate that
/// raises the aggregate most; ties: for min the larger mean, then the lowest index), local
/// (greedy, then the best 1-swap while the aggregate improves), all (best, then ransac, greedy
/// and local for every n from 1 to options.n). Aggregates are compared exactly (whole numbers of
/// cells per state, on a common denominator); deterministic, single-threaded.
/// InputError (naming --over-states) for exact and the goal, k and budget objectives;
/// for no state, states with different candidate counts, an empty R_s, or indices beyond R_s;
/// and for what SelectOptions::Validate rejects.
std::vector<StateSelection> SelectOverStates(std::span<const StateObservations> states,
                                             OverStates over,
                                             const SelectOptions& options);

}  // namespace vantage
