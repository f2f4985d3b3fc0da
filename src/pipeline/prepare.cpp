// Load → overrides → states → deploy: everything before the first ray, with every option checked.
#include <fmt/format.h>
#include <spdlog/spdlog.h>

#include <algorithm>
#include <chrono>
#include <cmath>

#include "pipeline/common.hpp"
#include "vantage/arm.hpp"
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
  if (!(max_seconds >= 0) || !std::isfinite(max_seconds))
    throw InputError(AtPlace("--max-seconds", 0,
                             fmt::format("{} is not a number of seconds >= 0 — give e.g. "
                                         "--max-seconds 3600 (0: no limit)",
                                         max_seconds)));
}

double EstimateObserveSeconds(uint64_t rays, size_t candidates, size_t threads) {
  return (static_cast<double>(rays) * kSecondsPerRay +
          static_cast<double>(candidates) * kSecondsPerCandidate) /
         static_cast<double>(std::max<size_t>(1, threads));
}

double EstimateSceneSeconds(uint64_t built_triangles, uint64_t scene_triangles, size_t threads) {
  return static_cast<double>(built_triangles) * kSecondsPerTriangle /
             static_cast<double>(std::max<size_t>(1, threads)) +
         static_cast<double>(scene_triangles) * kOutputSecondsPerTriangle;
}

namespace {

// The candidates in a state that moves sensors on robot links: each moved explicit sensor's model
// pose composed with its mount, as DeployCandidates composes them.
std::vector<Candidate> MovedCandidates(const std::vector<Candidate>& candidates,
                                       const Problem& problem,
                                       const SceneState& state) {
  std::vector<Candidate> moved = candidates;
  for (const auto& [sensor_name, world_from_model] : state.sensor_poses) {
    const std::string& name = sensor_name;  // clang 14 (the fuzz build) captures no bindings
    const auto sensor = std::find_if(problem.sensors.begin(), problem.sensors.end(),
                                     [&](const ExplicitSensor& s) { return s.name == name; });
    const auto candidate = std::find_if(moved.begin(), moved.end(), [&](const Candidate& c) {
      return c.population.empty() && c.name == name;
    });
    VANTAGE_CHECK(sensor != problem.sensors.end() && candidate != moved.end());
    candidate->world_from_body = world_from_model * sensor->model_from_camera;
  }
  return moved;
}

// Mounting rules: candidates inside a keep-out box, in the base scene or any state, are dropped
// from every state's list before any ray (docs/constraints.md).
void ExcludeKeptOut(PreparedScene* prepared) {
  const std::vector<KeepOutBox>& boxes = prepared->problem.mounting.keep_out;
  if (boxes.empty()) return;
  const auto inside = [&](const Candidate& c) {
    return InKeepOut(boxes, c.world_from_body.position);
  };
  const size_t count = prepared->candidates.size();
  std::vector<bool> out(count, false);
  for (size_t i = 0; i < count; ++i) {
    out[i] = inside(prepared->candidates[i]);
    for (const std::vector<Candidate>& state : prepared->state_candidates)
      out[i] = out[i] || inside(state[i]);
  }
  const auto keep = [&](std::vector<Candidate>* list, std::vector<Candidate>* dropped) {
    std::vector<Candidate> kept;
    for (size_t i = 0; i < count; ++i) {
      if (!out[i]) {
        kept.push_back(std::move((*list)[i]));
      } else if (dropped != nullptr) {
        dropped->push_back(std::move((*list)[i]));
      }
    }
    *list = std::move(kept);
  };
  keep(&prepared->candidates, &prepared->kept_out);
  for (std::vector<Candidate>& state : prepared->state_candidates) keep(&state, nullptr);
  const KeepOutBox& first = boxes.front();
  if (prepared->candidates.empty())
    throw InputError(AtPlace(first.file, first.line,
                             fmt::format("every one of the {} candidates lies inside a keep_out "
                                         "box — shrink or move the boxes, or the populations",
                                         count)));
  const std::string note =
      fmt::format("keep_out: {} of {} candidates lie inside the {} keep-out box{} and are "
                  "excluded (no rays cast for them)",
                  prepared->kept_out.size(), count, boxes.size(), boxes.size() == 1 ? "" : "es");
  spdlog::info("{}", note);
  if (!prepared->kept_out.empty()) prepared->notes.push_back(note);
}

// Cameras on arms (issue 45): the regions' `reach:` poses through inverse kinematics, the kind
// `arm` populations' views, each collision-free, before any ray. The robots that carry cameras
// leave the ray scene: each arm view carries its links as they stand in it (observe's
// ArmOcclusion), so a static copy at the `robots:` joints would hide views it does not block.
void ApplyArmPopulations(PreparedScene* prepared, bool follows_states) {
  Problem& problem = prepared->problem;
  const auto has_arm = [](const Population& p) { return p.arm.has_value(); };
  if (std::none_of(problem.populations.begin(), problem.populations.end(), has_arm)) return;
  for (const Population& population : problem.populations) {
    if (!population.arm) continue;
    const ArmMount& arm = *population.arm;
    if (!problem.states.empty() && !follows_states)
      throw InputError(AtPlace(arm.file, arm.line,
                               fmt::format("population '{}': a camera on an arm in a scene with "
                                           "`states:` follows them only with --track (one view "
                                           "per state, docs/arm.md) — add --track, or remove "
                                           "the states or the arm population",
                                           population.name)));
    // The carrying arm's pose is each view's: a state may not set it.
    const std::string own = arm.robot + "::";
    for (const SceneState& state : problem.states) {
      std::vector<std::string> touched = state.remove;
      for (const auto& [name, mesh] : state.reshape) touched.push_back(name);
      for (const auto& [name, pose] : state.move) touched.push_back(name);
      for (const std::string& name : touched) {
        if (name.rfind(own, 0) != 0) continue;
        throw InputError(AtPlace(state.file.empty() ? problem.source : state.file, state.line,
                                 fmt::format("state '{}' changes '{}' of robot '{}', which "
                                             "carries population '{}''s camera — each view sets "
                                             "that arm's joints; change other objects only",
                                             state.name, name, arm.robot, population.name)));
      }
    }
    for (const PlacedRobot& robot : problem.robots) {
      if (robot.name == arm.robot && !robot.target_links.empty())
        throw InputError(AtPlace(robot.file, robot.line,
                                 fmt::format("robot '{}' carries population '{}''s camera and "
                                             "has target links ({}) — a camera cannot inspect "
                                             "the arm that carries it; remove `targets`",
                                             robot.name, population.name,
                                             robot.target_links.front())));
    }
  }
  ArmViews arms = ApplyArms(problem, std::move(prepared->candidates), problem.seed);
  prepared->candidates = std::move(arms.candidates);
  for (std::string& note : arms.notes) {
    spdlog::info("{}", note);
    prepared->notes.push_back(std::move(note));
  }
  std::vector<SceneObject> kept;
  for (SceneObject& object : problem.scene.objects) {
    const bool carried = std::any_of(arms.arms.begin(), arms.arms.end(), [&](const ArmSetup& a) {
      return object.name.rfind(a.robot + "::", 0) == 0;
    });
    if (!carried) kept.push_back(std::move(object));
  }
  problem.scene.objects = std::move(kept);
  prepared->arms = std::move(arms.arms);
}

}  // namespace

Problem LoadScene(const SceneInput& input) {
  input.Validate();
  Problem problem = LoadProblem(input.path, input.load);
  // Command-line options override the scene's (the Gazebo plugin's parameters, GAZEBO.md).
  if (input.seed) problem.seed = *input.seed;
  if (input.observation_point) problem.observation_point = *input.observation_point;
  if (input.random_roll) problem.random_roll = *input.random_roll;
  for (const std::string& note : problem.notes) {
    const bool warning = std::find(problem.warnings.begin(), problem.warnings.end(), note) !=
                         problem.warnings.end();
    spdlog::log(warning ? spdlog::level::warn : spdlog::level::info, "{}", note);
  }
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
  prepared.load = input.load;

  DeployOptions deploy;
  deploy.observation_point = problem.observation_point;
  deploy.random_roll = problem.random_roll;
  deploy.seed = problem.seed;
  prepared.candidates =
      DeployCandidates(problem.populations, problem.sensors, problem.sensor_types, deploy);
  ApplyArmPopulations(&prepared, input.arm_follows_states);
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
  // Each state is a copy of the scene's meshes, made here, before the estimates of the observe
  // stage: a large mesh in 1000 states filled the memory (session 14). These copies come before
  // any --max-memory is known, so they are held to 75 % of the RAM.
  if (!problem.states.empty()) {
    const double bytes = static_cast<double>(detail::MeshBytes(problem.scene));
    const double copies_mib = bytes * static_cast<double>(problem.states.size()) / detail::kMiB;
    const double limit_mib = detail::MemoryLimitMiB(0);
    if (copies_mib > limit_mib)
      throw InputError(AtPlace(
          problem.source, problem.states.front().line,
          fmt::format("{} states, each a copy of the scene's {:.0f} MiB of meshes, need about "
                      "{:.0f} MiB, above 75 % of the RAM ({:.0f} MiB) — use fewer states, or "
                      "simpler meshes",
                      problem.states.size(), bytes / detail::kMiB, copies_mib, limit_mib)));
  }
  // A scene with states: the first state is the scene everything below measures; the others
  // are observed after it with the same candidates.
  for (const SceneState& state : problem.states) {
    prepared.state_scenes.push_back(ApplyState(problem.scene, state));
    CheckSceneExtent(prepared.state_scenes.back(), problem.source, state.line, state.name);
    for (std::string& warning : CollapsedOccluderWarnings(
             prepared.state_scenes.back(), problem.source, state.line, state.name, &problem.scene)) {
      spdlog::warn("{}", warning);
      prepared.notes.push_back(std::move(warning));
    }
  }
  const auto moves_sensors = [](const SceneState& state) { return !state.sensor_poses.empty(); };
  if (std::any_of(problem.states.begin(), problem.states.end(), moves_sensors)) {
    for (const SceneState& state : problem.states) {
      prepared.state_candidates.push_back(MovedCandidates(prepared.candidates, problem, state));
      detail::CheckDeployedCandidates(prepared.state_candidates.back(), problem);
    }
    prepared.candidates = prepared.state_candidates.front();
  }
  if (!prepared.state_scenes.empty()) problem.scene = prepared.state_scenes.front();
  ExcludeKeptOut(&prepared);
  detail::CheckSeparationPairs(prepared.candidates, problem.mounting);
  prepared.cell_size_from_option = input.load.cell_size.has_value();
  prepared.exposed_only = input.exposed_only.value_or(false);
  prepared.timings.load = detail::SecondsSince(start);
  return prepared;
}

}  // namespace vantage
