// `vantage optimize`: prepare → observe → select → refine → assess → report.
#include <fmt/format.h>
#include <spdlog/spdlog.h>

#include <algorithm>
#include <chrono>

#include "pipeline/common.hpp"
#include "vantage/error.hpp"
#include "vantage/gazebo_export.hpp"
#include "vantage/yaml_export.hpp"

namespace vantage {
namespace {

// --refine: new poses around the primary result's sensors, traced and re-selected; the refined
// constellation is appended to the results (method "refined") with its candidates.
std::optional<RefinementInfo> RefinePrimary(const RefineOptions& options,
                                            const SelectOptions& select, OverStates over,
                                            ObservedScene* observed,
                                            std::vector<Selection>* results) {
  const int from = PrimaryResult(*results);
  if (from < 0) return std::nullopt;
  VisibilityFile& data = observed->data;
  // Over scene states: every state after the first, traced in its own geometry (a state with the
  // geometry of an earlier one shares that one's).
  RefineOptions with_states = options;
  std::vector<std::unique_ptr<RayScene>> state_rays;
  for (size_t s = 1; s < observed->states.size(); ++s) {
    const ObservedState& state = observed->states[s];
    const RayScene* rays = nullptr;
    const Reference* reference = &state.reference;
    if (state.same_as == 0) {
      rays = observed->rays.get();
      reference = &data.reference;
    } else if (state.same_as > 0) {
      rays = with_states.states[static_cast<size_t>(state.same_as) - 1].rays;
      reference = with_states.states[static_cast<size_t>(state.same_as) - 1].reference;
    } else {
      state_rays.push_back(std::make_unique<RayScene>(observed->state_scenes.at(s)));
      rays = state_rays.back().get();
    }
    with_states.states.push_back({state.name, rays, reference, state.observations});
  }
  if (!observed->states.empty()) with_states.over = over;
  RefineResult refined = Refine(*observed->rays, data.reference, data.candidates,
                                data.observations, observed->populations,
                                observed->observation_point, (*results)[static_cast<size_t>(from)],
                                select, with_states);
  data.candidates = std::move(refined.candidates);
  data.observations = std::move(refined.observations);
  if (!observed->states.empty()) {
    observed->states[0].observations = data.observations;
    for (size_t s = 1; s < observed->states.size(); ++s)
      observed->states[s].observations = std::move(refined.state_observations[s - 1]);
  }
  Selection selection = refined.selection;  // scored, seconds included, by Refine
  selection.method = "refined";
  results->push_back(selection);
  RefinementInfo info;
  info.from_result = from;
  info.result = static_cast<int>(results->size()) - 1;
  info.coverage_before = refined.coverage_before;
  info.coverage_after = selection.coverage;
  info.history = refined.history;
  info.rounds = refined.rounds;
  info.new_candidates = refined.new_candidates;
  info.extra_rays = refined.extra_rays;
  info.seconds = refined.seconds;
  spdlog::info("refine: {} rounds, {} new poses, {:.1f} M rays, {:+.2f} points in {:.3f} s",
               info.rounds, info.new_candidates, info.extra_rays / 1e6,
               100.0 * (info.coverage_after - info.coverage_before), info.seconds);
  return info;
}

}  // namespace

OptimizeObserved ObserveForOptimize(const OptimizeOptions& options) {
  const auto start = std::chrono::steady_clock::now();
  // Every option is checked before the scene is read, the selection before any ray is cast.
  options.observe.Validate();
  options.limits.Validate();
  options.robustness.Validate();
  if (options.pose_tolerance) options.pose_tolerance->Validate();
  if (options.refine) {
    options.refine->Validate();
    // A run that asks for refinement asks for a round (the library reads 0 as none: the Python
    // module's refine_rounds=0 did nothing silently; the CLI checked 1..100 only itself).
    if (options.refine->max_rounds < 1 || options.refine->max_rounds > kMaxRefineRounds)
      throw InputError(fmt::format("--refine-rounds: {} is out of range — give a whole number "
                                   "from 1 to {}",
                                   options.refine->max_rounds, kMaxRefineRounds));
  }
  options.arm.Validate();
  SceneInput scene = options.scene;
  scene.arm_follows_states = options.arm.track;
  PreparedScene prepared = Prepare(scene);
  const std::string source = prepared.problem.source;
  const SelectOptions select = ResolveSelection(prepared.problem.selection, options.selection,
                                                prepared.problem.seed, prepared.candidates,
                                                source, Method::kAll, prepared.problem.cell_size);
  const bool has_states = !prepared.problem.states.empty();
  if (!has_states && options.selection.over_states)
    throw InputError(AtPlace("--over-states", 0,
                             "the scene has no states — add a `states:` list "
                             "(docs/scene-format.md) or drop --over-states"));
  const std::optional<OverStates>& over_parts = options.selection.over_parts;
  const std::optional<OverStates>& over_states = options.selection.over_states;
  if (has_states && over_parts && over_states && *over_parts != *over_states)
    // Two aggregations (the mean over states of the worst part) are a two-level objective.
    throw InputError(AtPlace(
        "--over-parts", 0,
        fmt::format("{} with --over-states {} is a two-level objective (the {} over the states "
                    "of the {} over each state's parts), which selection does not take — give "
                    "both mean or both min (one aggregation over every state's parts), or drop "
                    "one",
                    OverStatesName(*over_parts), OverStatesName(*over_states),
                    OverStatesName(*over_states), OverStatesName(*over_parts))));
  // An objective over groups of cells: beside the scene's states it runs over every state's
  // groups; not with what chooses or re-scores by the coverage of all cells together.
  detail::RefuseGroupObjectiveBeside(options.selection, options.refine           ? "--refine"
                                                        : options.by_type        ? "--by-type"
                                                        : options.arm.cycle_time ? "--cycle-time"
                                                        : options.arm.track      ? "--track"
                                                                                 : nullptr);
  if (has_states && options.refine && !prepared.state_candidates.empty())
    throw InputError(AtPlace("--refine", 0,
                             "refinement over scene states whose sensors move with a robot is not "
                             "supported yet — drop --refine or the robot's joints in the states"));
  options.selection.constraints.Validate();
  if (options.selection.keep_existing) {
    const std::vector<KeepOutBox>& boxes = prepared.problem.mounting.keep_out;
    for (const Candidate& c : prepared.kept_out) {
      if (!c.population.empty()) continue;
      // The box that holds it (in the base scene).
      const auto holder = std::find_if(boxes.begin(), boxes.end(), [&](const KeepOutBox& box) {
        return box.Contains(c.world_from_body.position);
      });
      const KeepOutBox& box = holder != boxes.end() ? *holder : boxes.front();
      throw InputError(AtPlace(box.file, box.line,
                               fmt::format("the declared sensor '{}' lies inside the keep-out "
                                           "box '{}', and --keep-existing would keep it — move "
                                           "it, or drop --keep-existing",
                                           c.name, box.name)));
    }
  }
  if (!prepared.arms.empty()) {
    detail::CheckArmTourInputs(prepared.candidates, prepared.arms, options.arm, select.seed);
  } else {
    // Without an arm they change nothing (--joint-speed 2 on a fixed-camera scene ran as without).
    detail::RefuseTourOptionsWithoutArm(options.arm, "no candidate is on an arm",
                                        "add an `arm` population (docs/arm.md)");
  }
  if (options.by_type) {
    // Refused before any ray: each of these answers something other than "n sensors of a type".
    const char* conflict = has_states                      ? "the scene's states"
                           : options.selection.keep_existing ? "--keep-existing"
                           : options.refine                 ? "--refine"
                           : options.arm.cycle_time         ? "--cycle-time"
                           : select.goal                    ? "a coverage goal"
                           : select.budget                  ? "a budget"
                                                            : nullptr;
    if (conflict)
      throw InputError(AtPlace("--by-type", 0,
                               fmt::format("compares n sensors of each type, which {} does not "
                                           "choose — drop one of --by-type and {}",
                                           conflict, conflict)));
  }
  if (options.arm.cycle_time && (has_states || options.refine))
    throw InputError(AtPlace("--cycle-time", 0, "--cycle-time takes no --refine and no states"));
  if (options.arm.cycle_time) detail::RefuseObjectiveBesideCycleTime(select, options.selection);
  if (options.arm.track) {
    // One view per state by coverage of one view: no other objective, no constraints.
    const char* conflict = options.by_type                 ? "--by-type"
                           : options.selection.over_states ? "--over-states"
                                                           : detail::ObjectiveBesideArmSelection(
                                                                 select, options.selection);
    if (conflict)
      throw InputError(AtPlace("--track", 0,
                               fmt::format("--track scores one view per state by its coverage, "
                                           "which {} does not — drop one of --track and {}",
                                           conflict, conflict)));
    detail::PrepareArmTrack(&prepared, options.arm);
  }
  ObservedScene observed =
      ObservePrepared(std::move(prepared), options.observe, options.limits, options.trace);
  return OptimizeObserved{std::move(observed), select, start};
}

RunResult FinishOptimize(const OptimizeOptions& options, OptimizeObserved first) {
  ObservedScene& observed = first.observed;
  const SelectOptions& select = first.select;
  const auto start = first.start;
  const auto select_start = std::chrono::steady_clock::now();
  RunResult run;
  Report& report = run.report;
  detail::CheckSelectionTime(observed.data.observations, select, observed.states.size(),
                             options.limits.max_seconds, observed.data.scene);
  report.constraints = detail::ResolveConstraints(
      options.selection.constraints, select, observed.data.candidates, observed.data.observations,
      observed.data.mounting, observed.data.kept_out, observed.states);
  if (options.arm.track) {
    // One view per state, exactly (dynamic programme over the checked moves).
    detail::TrackSelection(observed, options.arm, select.seed, &report);
  } else if (options.arm.cycle_time) {
    // The most coverage whose tour fits the cycle time replaces the methods' results.
    report.results.push_back(detail::CycleTimeSelection(observed.data, observed.arms, options.arm,
                                                        select.seed));
    report.cycle_time = options.arm.cycle_time;
  } else {
    detail::SelectResults(observed, options.selection, select, &report);
  }
  if (options.by_type) {
    SelectOptions own = select;
    if (report.constraints) own.constraints = report.constraints->constraints;
    report.by_type = detail::CompareTypes(observed.data, own, report.results, report.curve);
  }
  if (options.refine) {
    RefineOptions refine = *options.refine;
    refine.seed = select.seed;
    refine.observe = options.observe;
    refine.observe.physical = observed.data.physical;  // new poses seen as the run's were
    refine.observe.progress = nullptr;
    if (report.constraints) {
      // New poses obey the run's constraints: none inside a keep-out box, and the pairs and the
      // calibration rule over old and new candidates together.
      const ConstraintsInfo& info = *report.constraints;
      refine.may_mount = [&info](const Pose& body) {
        return !InKeepOut(info.keep_out_boxes, body.position);
      };
      refine.constraints = [&info](std::span<const Candidate> candidates,
                                   std::span<const Observation> observations) {
        return detail::ConstraintsOverGrown(info, candidates, observations);
      };
    }
    report.refinement =
        RefinePrimary(refine, select, options.selection.over_states.value_or(OverStates::kMean),
                      &observed, &report.results);
    if (report.constraints) {
      ConstraintsInfo& info = *report.constraints;
      info.constraints = detail::ConstraintsOverGrown(info, observed.data.candidates,
                                                      observed.data.observations);
      const std::vector<bool> projecting = detail::ProjectingCandidates(observed.data.candidates);
      info.projecting = static_cast<size_t>(std::count(projecting.begin(), projecting.end(), true));
    }
  }
  observed.timings.select = detail::SecondsSince(select_start);
  observed.timings.total = detail::SecondsSince(start);

  run.data = std::make_unique<VisibilityFile>(std::move(observed.data));
  const VisibilityFile& data = *run.data;
  report.scene = data.scene;
  report.seed = select.seed;
  report.data = run.data.get();
  report.timings = observed.timings;
  report.notes = observed.notes;
  report.inputs = detail::InputsOf("optimize", options.scene, options.observe);
  report.inputs->physical = data.physical;
  detail::AddSelectionInputs(options.selection, &*report.inputs);
  report.inputs->refine = options.refine.has_value();
  if (options.refine) report.inputs->refine_rounds = options.refine->max_rounds;
  report.inputs->fov_tolerance_deg = options.robustness.fov_tolerance_deg;
  report.inputs->alternatives_within = 100.0 * options.robustness.within;
  if (report.states) {
    report.notes.push_back(fmt::format(
        "scene states: candidates' coverages, reference.ply, observed.ply and report.html's 3D "
        "view and chosen-sensor table show the first state '{}'; each result's state_coverage "
        "lists every state",
        report.states->states.front().name));
  }
  if (!options.arm.track) detail::AddArmTours(data.candidates, observed.arms, options.arm, &report);
  DeriveReport(&report);

  // constellation.world (or .yaml): the input scene with only the primary result's sensors.
  std::map<std::string, std::string> extra;
  if (report.primary >= 0) {
    std::vector<Candidate> chosen;
    for (uint32_t i : report.PrimaryChosen()) chosen.push_back(data.candidates[i]);
    std::vector<std::string> notes;
    extra = detail::ConstellationFiles(options.scene.path, observed.scene, chosen,
                                       observed.populations, observed.sensors,
                                       detail::ScoringOf(data, *report.inputs), &notes);
    run.export_warnings = notes;
    report.notes.insert(report.notes.end(), notes.begin(), notes.end());
    // Robustness reads `data`, the first state's sets: not meaningful over states (nor for an
    // objective over groups of cells: it counts all cells together).
    if (!report.CountsGroups()) {
      detail::AddRobustness(data, select, options.robustness, observed.rays.get(),
                            options.observe, &report);
    }
  }
  detail::AddPoseTolerance(options.pose_tolerance, observed.rays.get(), options.observe, &report);
  detail::FinishRun(observed.scene, std::move(extra), &run);
  return run;
}

RunResult Optimize(const OptimizeOptions& options) {
  return FinishOptimize(options, ObserveForOptimize(options));
}

}  // namespace vantage
