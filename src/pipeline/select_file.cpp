// `vantage select`: selection from a saved visibility file, then assess and report.
#include <fmt/format.h>
#include <spdlog/spdlog.h>

#include <algorithm>
#include <chrono>
#include <filesystem>

#include "pipeline/common.hpp"
#include "util/atomic_file.hpp"
#include "vantage/error.hpp"

namespace vantage {
namespace {

// The scene as observe read it (its absolute path, folders, targets and cell size: format 10),
// or from the path as typed in older files, when it is still there: for report.html's meshes,
// the shrunk fields of view and the pose tolerance, and the arms of a camera on an arm. nullopt
// (logged, `without` says what goes) when it is not found from here or no longer loads.
// `visibility_file` names where the folders came from.
std::optional<Problem> ReloadScene(const std::string& path, LoadOptions load,
                                   const std::string& visibility_file, const std::string& without) {
  std::error_code error;
  if (path.empty() || !std::filesystem::exists(path, error)) {
    spdlog::info("{}: scene '{}' not found from here", without, path);
    return std::nullopt;
  }
  const std::string origin = fmt::format("{}: the scene's", visibility_file);
  load.model_paths_origin = origin + " model paths";
  load.resource_paths_origin = origin + " resource paths";
  load.package_paths_origin = origin + " package paths";
  load.targets_origin = origin + " targets";
  try {
    return LoadProblem(path, load);
  } catch (const InputError& e) {
    spdlog::warn("{}: {}", without, e.what());
    return std::nullopt;
  }
}

}  // namespace

MatrixSelection ResolveMatrixSelection(const VisibilityFile& data, const SelectionRequest& request,
                                       uint64_t seed, Method default_method,
                                       const std::string& source) {
  MatrixSelection resolved;
  // The settings are the file's (stored from its scene by observe): an error in them names the
  // file, where they now are, and the scene they came from (issue 15: the scene alone misled).
  const std::string settings_source =
      source.empty() ? data.scene
                     : fmt::format("{} (settings stored from {})", source, data.scene);
  resolved.options = ResolveSelection(data.selection, request, seed, data.candidates,
                                      settings_source, default_method, data.reference.cell_size);
  if (resolved.options.min_points &&
      !std::all_of(data.observations.begin(), data.observations.end(),
                   [](const Observation& o) { return o.has_point_counts(); }))
    throw InputError(AtPlace(
        source.empty() ? std::string("the visibility file") : source, 0,
        fmt::format("has no pixel counts per cell (written before format version 4), which {} "
                    "needs — observe the scene again with `vantage observe`",
                    request.min_density ? "--min-density" : "--min-points")));
  // The scene's mounting rules as the file keeps them (format 5; none in older files): its
  // min_separation applies, and its keep-out boxes are reported, as in `optimize` on the scene.
  request.constraints.Validate();
  detail::CheckSeparationPairs(data.candidates, data.mounting);
  resolved.constraints =
      detail::ResolveConstraints(request.constraints, resolved.options, data.candidates,
                                 data.observations, data.mounting, data.kept_out);
  if (resolved.constraints) resolved.options.constraints = resolved.constraints->constraints;
  return resolved;
}

RunResult SelectFromFile(const SelectFileOptions& options) {
  const auto start = std::chrono::steady_clock::now();
  options.robustness.Validate();
  if (options.pose_tolerance) options.pose_tolerance->Validate();
  options.arm.Validate();
  RunResult run;
  run.data = std::make_unique<VisibilityFile>(LoadVisibilityFile(options.visibility_file));
  const VisibilityFile& data = *run.data;
  detail::CheckCandidates(data.candidates, [&](size_t i) {
    return AtPlace(options.visibility_file, 0,
                   fmt::format("candidate {} ('{}')", i, data.candidates[i].name));
  });
  if (options.selection.over_states)
    throw InputError(AtPlace("--over-states", 0,
                             "a visibility file holds one state — run `vantage optimize` on the "
                             "scene with states instead"));
  if (options.arm.track)
    throw InputError(AtPlace("--track", 0,
                             "a visibility file holds one state — run `vantage optimize` on the "
                             "scene with states and --track instead"));
  // As observe read the scene (format 10; older files: the path as typed).
  const std::string& scene_path = data.scene_path.empty() ? data.scene : data.scene_path;
  // A camera on an arm (format 11): the scene reloaded now, before any work, its arms rebuilt
  // and checked against the stored views (issue 45).
  std::optional<Problem> problem;
  std::vector<ArmSetup> arms;
  if (!data.arm_views.empty()) {
    problem = ReloadScene(scene_path, data.load, options.visibility_file,
                          "no tours and report.html without meshes");
    if (problem) {
      arms = detail::RebuildArmViews(&*problem, options.visibility_file, run.data.get());
    } else {
      spdlog::warn("{}: its cameras on an arm get no tours: their robot and cell are the scene's "
                   "({}), which does not load from here",
                   options.visibility_file, scene_path);
    }
  }
  Timings timings;
  timings.load = detail::SecondsSince(start);
  if (data.arm_views.empty())
    detail::RefuseTourOptionsWithoutArm(
        options.arm, fmt::format("{} holds no camera on an arm", options.visibility_file),
        "observe a scene with an `arm` population (docs/arm.md; a file written before format 11 "
        "does not keep the arm's views: observe it again)");
  if (options.arm.cycle_time) {
    if (arms.empty())
      throw InputError(AtPlace("--cycle-time", 0,
                               fmt::format("the scene of {} ({}) does not load from here, and the "
                                           "arm's tour needs its robot and cell",
                                           options.visibility_file, scene_path)));
    detail::RefuseGroupObjectiveBeside(options.selection, "--cycle-time");
  }
  const auto select_start = std::chrono::steady_clock::now();
  MatrixSelection resolved =
      ResolveMatrixSelection(data, options.selection, options.seed.value_or(data.seed),
                             Method::kAll, options.visibility_file);
  const SelectOptions& select = resolved.options;  // constraints included
  if (options.arm.cycle_time) detail::RefuseObjectiveBesideCycleTime(select, options.selection);
  if (!arms.empty()) detail::CheckArmTourInputs(data.candidates, arms, options.arm, select.seed);
  Report& report = run.report;
  report.constraints = std::move(resolved.constraints);
  if (options.arm.cycle_time) {
    // As optimize: the most coverage whose tour fits the cycle time replaces the methods.
    report.results.push_back(
        detail::CycleTimeSelection(data, arms, options.arm, select.seed));
    report.cycle_time = options.arm.cycle_time;
  } else {
    detail::SelectOnMatrix(data, options.selection, select, &report);
  }
  timings.select = detail::SecondsSince(select_start);
  timings.total = detail::SecondsSince(start);
  report.scene = data.scene;
  report.seed = select.seed;
  report.data = run.data.get();
  report.timings = timings;
  RunInputs inputs;
  inputs.command = "select";
  inputs.visibility_file = detail::AbsolutePath(options.visibility_file).string();
  detail::SetSceneInputs(scene_path, data.load, &inputs);
  inputs.cull = true;
  inputs.quality = data.quality;
  inputs.physical = data.physical;
  inputs.seed = options.seed;
  detail::AddSelectionInputs(options.selection, &inputs);
  inputs.fov_tolerance_deg = options.robustness.fov_tolerance_deg;
  inputs.alternatives_within = 100.0 * options.robustness.within;
  report.inputs = std::move(inputs);
  detail::AddArmTours(data.candidates, arms, options.arm, &report);
  DeriveReport(&report);
  if (data.arm_views.empty()) {
    problem = ReloadScene(scene_path, data.load, options.visibility_file,
                          "report.html without meshes");
    if (problem && std::any_of(problem->populations.begin(), problem->populations.end(),
                               [](const Population& p) { return p.arm.has_value(); }))
      spdlog::warn("{}: its scene has a camera on an arm, but the file (written before format "
                   "11) does not keep the arm's views: no tours — observe the scene again for "
                   "them",
                   options.visibility_file);
  }
  const Scene scene = problem ? std::move(problem->scene) : Scene{};
  // The shrunk fields of view and the pose tolerance need the geometry: only when the scene
  // still loads from here.
  const std::unique_ptr<RayScene> rays =
      scene.objects.empty() || (report.primary < 0 && !options.pose_tolerance)
          ? nullptr
          : std::make_unique<RayScene>(scene);
  if (report.primary >= 0 && !report.CountsGroups()) {  // robustness counts all cells
    detail::AddRobustness(data, select, options.robustness, rays.get(), ObserveOptions{},
                          &report);
  }
  detail::AddPoseTolerance(options.pose_tolerance, rays.get(), ObserveOptions{}, &report);
  detail::FinishRun(scene, {}, &run);
  return run;
}

}  // namespace vantage
