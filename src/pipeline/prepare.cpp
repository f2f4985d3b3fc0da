// Load → overrides → states → deploy: everything before the first ray, with every option checked.
#include <fmt/format.h>
#include <spdlog/spdlog.h>

#include <chrono>
#include <cmath>

#include "pipeline/common.hpp"
#include "vantage/error.hpp"
#include "vantage/pipeline.hpp"
#include "vantage/scene_states.hpp"

namespace vantage {

void SceneInput::Validate() const {
  if (path.empty()) throw InputError("scene: give the scene file (.yaml, .world or .sdf)");
  if (observation_point) detail::CheckWorldPoint(*observation_point, "--observation-point");
}

void RunLimits::Validate() const {
  if (!(max_memory_mib >= 0) || !std::isfinite(max_memory_mib))
    throw InputError(AtPlace("--max-memory", 0,
                             fmt::format("{} is not a positive number of MiB — give e.g. "
                                         "--max-memory 4096",
                                         max_memory_mib)));
}

Problem LoadScene(const SceneInput& input) {
  input.Validate();
  Problem problem = LoadProblem(input.path, input.load);
  // Command-line options override the scene's (the Gazebo plugin's parameters, GAZEBO.md).
  if (input.seed) problem.seed = *input.seed;
  if (input.observation_point) problem.observation_point = *input.observation_point;
  if (input.random_roll) problem.random_roll = *input.random_roll;
  for (const std::string& note : problem.notes) spdlog::info("{}", note);
  spdlog::info("scene {}: {} objects, {} targets, {} triangles", problem.source,
               problem.scene.objects.size(), problem.scene.TargetCount(),
               problem.scene.TriangleCount());
  return problem;
}

PreparedScene Prepare(const SceneInput& input) {
  const auto start = std::chrono::steady_clock::now();
  PreparedScene prepared;
  Problem& problem = prepared.problem;
  problem = LoadScene(input);

  DeployOptions deploy;
  deploy.observation_point = problem.observation_point;
  deploy.random_roll = problem.random_roll;
  deploy.seed = problem.seed;
  prepared.candidates =
      DeployCandidates(problem.populations, problem.sensors, problem.sensor_types, deploy);
  detail::CheckDeployedCandidates(prepared.candidates, problem);
  if (prepared.candidates.empty())
    throw InputError(
        AtPlace(problem.source, 0, "no candidate sensors — add a population or a sensor"));
  if (problem.expected_candidates &&
      *problem.expected_candidates != static_cast<int>(prepared.candidates.size())) {
    const std::string note = fmt::format(
        "{}: numberOfSamplingSensors is {} but the populations yield {} sensors", problem.source,
        *problem.expected_candidates, prepared.candidates.size());
    spdlog::warn("{}", note);
    prepared.notes.push_back(note);
  }
  // A scene with states: the first state is the scene everything below measures; the others
  // are observed after it with the same candidates.
  for (const SceneState& state : problem.states) {
    prepared.state_scenes.push_back(ApplyState(problem.scene, state));
    CheckSceneExtent(prepared.state_scenes.back(), problem.source);
  }
  if (!prepared.state_scenes.empty()) problem.scene = prepared.state_scenes.front();
  prepared.cell_size_from_option = input.load.cell_size.has_value();
  prepared.timings.load = detail::SecondsSince(start);
  return prepared;
}

}  // namespace vantage
