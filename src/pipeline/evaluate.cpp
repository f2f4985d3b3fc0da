// `vantage evaluate` and `vantage render`: a given constellation observed again in its scene,
// with the options of the run that made it (report.json `inputs`) unless given anew.
#include <fmt/format.h>
#include <spdlog/spdlog.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>

#include "pipeline/common.hpp"
#include "util/atomic_file.hpp"
#include "vantage/error.hpp"
#include "vantage/scene_states.hpp"
#include "vantage/sensors.hpp"
#include "vantage/words.hpp"

namespace vantage {
namespace {

namespace fs = std::filesystem;

// The scene input of a re-run: what the caller gave, the rest from the run's inputs block (or,
// for a report without one, its `scene` and `cell_size`).
SceneInput InheritScene(SceneInput scene, const Constellation& constellation,
                        const std::string& report_path) {
  const std::optional<RunInputs>& inputs = constellation.inputs;
  if (scene.path.empty()) scene.path = inputs && !inputs->scene.empty() ? inputs->scene : constellation.scene;
  if (!inputs) return scene;
  // A folder of the run's that is gone is named at the report's field (was: under the option the
  // user never typed, or the model "not found"); the option replaces the whole list.
  const auto inherit = [&](std::vector<std::string>* given, std::string* origin,
                           const std::vector<std::string>& run, const char* field) {
    if (!given->empty() || run.empty()) return;
    *given = run;
    *origin = fmt::format("{}: inputs.{} (give {} to use other folders)", report_path, field, *origin);
  };
  inherit(&scene.load.model_paths, &scene.load.model_paths_origin, inputs->model_paths,
          "model_paths");
  inherit(&scene.load.resource_paths, &scene.load.resource_paths_origin, inputs->resource_paths,
          "resource_paths");
  inherit(&scene.load.package_paths, &scene.load.package_paths_origin, inputs->package_paths,
          "package_paths");
  if (scene.load.targets.empty() && !inputs->targets.empty()) {
    scene.load.targets = inputs->targets;
    scene.load.targets_origin = report_path + ": inputs.targets";
  }
  if (!scene.load.cell_size) scene.load.cell_size = inputs->cell_size;
  if (!scene.exposed_only && inputs->exposed_only) scene.exposed_only = true;
  return scene;
}

// The quality filter of a re-run: the caller's, else the run's.
QualityFilter InheritQuality(const QualityFilter& given, const Constellation& constellation,
                             const std::string& path) {
  if (given.active() || !constellation.inputs || !constellation.inputs->quality.active())
    return given;
  const QualityFilter& run = constellation.inputs->quality;
  try {
    run.Validate();
  } catch (const InputError& e) {
    throw InputError(AtPlace(path, 0, fmt::format("inputs: {}", e.what())));
  }
  spdlog::info("{}: scoring with the run's quality filter (report.json inputs)", path);
  return run;
}

/// The given sensors' types as the scene (or the catalog) defines them. A report.json carries
/// each sensor's intrinsics and is evaluated with them, but its exports name only the type: a
/// type whose definition differs from the intrinsics (an edited file) would make
/// constellation.yaml describe other cameras than those scored (issue 15), so it is refused; a
/// type neither defines is returned, and the exports are left out.
std::vector<std::string> CheckGivenTypes(const Constellation& constellation, const Problem& problem,
                                         const std::string& file) {
  std::vector<std::string> unknown;
  for (const Candidate& c : constellation.sensors) {
    const SensorType* defined = problem.FindType(c.sensor.id);
    if (defined == nullptr) defined = FindCatalogType(c.sensor.id);
    if (defined == nullptr) {
      unknown.push_back(c.sensor.id);
      continue;
    }
    const SensorType& given = c.sensor;
    const auto same = [](double a, double b) {
      return std::abs(a - b) <= 1e-9 * std::max({1.0, std::abs(a), std::abs(b)});
    };
    if (given.width != defined->width || given.height != defined->height ||
        !same(given.fx, defined->fx) || !same(given.fy, defined->fy) ||
        !same(given.cx, defined->cx) || !same(given.cy, defined->cy) ||
        !same(given.near, defined->near) || !same(given.far, defined->far))
      throw InputError(AtPlace(
          file, 0,
          fmt::format("sensor '{}': its type '{}' is {}x{} px, fx {:g}, range {:g}-{:g} m where "
                      "the scene or the catalog defines it, but the file gives {}x{} px, fx {:g}, "
                      "range {:g}-{:g} m — the file was edited: give the type that matches its "
                      "intrinsics",
                      c.name, c.sensor.id, defined->width, defined->height, defined->fx,
                      defined->near, defined->far, given.width, given.height, given.fx,
                      given.near, given.far)));
  }
  return unknown;
}

// The constellation observed in the scene: its own reference, observations and "given" result.
struct Reobserved {
  Problem problem;
  std::unique_ptr<VisibilityFile> data;
  std::unique_ptr<RayScene> rays;
  Selection given;
  Timings timings;
  std::vector<std::string> unknown_types;  ///< sensor types neither the scene nor the catalog has
};

/// `file`: the report.json the constellation came from ("" for a scene's declared layout).
Reobserved Reobserve(const SceneInput& scene, const Constellation& constellation,
                     const std::string& file, const ObserveOptions& observe,
                     const RunLimits& limits,
                     const std::function<void(Problem*, std::vector<Candidate>*)>& adjust = {}) {
  const auto start = std::chrono::steady_clock::now();
  Reobserved result;
  result.problem = LoadScene(scene);
  const Problem& problem = result.problem;
  if (!file.empty()) result.unknown_types = CheckGivenTypes(constellation, problem, file);  // before any ray
  if (!problem.states.empty())
    spdlog::warn("{}: evaluated on the objects as listed; its {} states are scored by `vantage "
                 "optimize` only",
                 problem.source, problem.states.size());
  result.timings.load = detail::SecondsSince(start);
  auto stage = std::chrono::steady_clock::now();
  result.data = std::make_unique<VisibilityFile>();
  VisibilityFile& data = *result.data;
  data.scene = problem.source;
  data.seed = problem.seed;
  data.selection.n = static_cast<int>(constellation.sensors.size());
  data.candidates = constellation.sensors;
  data.quality = observe.quality;
  // A type the scene defines carries its own second aperture (report.json keeps intrinsics
  // only): the scene's definition, so that the layout is seen with the scene's model.
  for (Candidate& c : data.candidates) {
    const SensorType* defined = problem.FindType(c.sensor.id);
    if (defined && !c.sensor.second_aperture) c.sensor.second_aperture = defined->second_aperture;
  }
  // A camera on an arm (render): the arm at each chosen view, as optimize observed it.
  if (adjust) adjust(&result.problem, &data.candidates);
  data.physical = observe.physical.value_or(true) && detail::AnyApertureIn(data.candidates);
  const ReferenceOptions reference{problem.cell_size, scene.exposed_only.value_or(false)};
  data.reference = detail::BuildRunReference(problem.scene, reference, problem.source);
  result.timings.reference = detail::SecondsSince(stage);
  detail::CheckObserveMemory(problem.scene, data.reference.size(), data.candidates,
                             limits.max_memory_mib, problem.source);
  stage = std::chrono::steady_clock::now();
  result.rays = std::make_unique<RayScene>(problem.scene);
  ObserveOptions model = observe;
  model.physical = data.physical;
  data.observations = Observe(*result.rays, data.reference, data.candidates, model);
  result.timings.observe = detail::SecondsSince(stage);
  stage = std::chrono::steady_clock::now();
  result.given = detail::GivenSelection(CoverageEvaluator(data.observations, data.reference.size()));
  result.timings.select = result.given.seconds = detail::SecondsSince(stage);
  result.timings.total = detail::SecondsSince(start);
  return result;
}

// The layout a scene declares itself: its explicit sensors (a gz-sim world's cameras, a YAML
// scene's `sensors:`), deployed as optimize deploys them; populations are not a layout.
Constellation DeclaredLayout(const SceneInput& scene) {
  if (scene.path.empty())
    throw InputError(AtPlace("--constellation", 0,
                             "give a report.json, or a scene whose declared sensors are the "
                             "layout to score"));
  const Problem problem = LoadScene(scene);
  if (problem.sensors.empty())
    throw InputError(AtPlace(problem.source, 0,
                             "declares no sensors of its own (only populations, or none) — give "
                             "--constellation report.json"));
  DeployOptions deploy;
  deploy.observation_point = problem.observation_point;
  deploy.random_roll = problem.random_roll;
  deploy.seed = problem.seed;
  Constellation constellation;
  constellation.sensors = DeployCandidates({}, problem.sensors, problem.sensor_types, deploy);
  detail::CheckDeployedCandidates(constellation.sensors, problem);
  constellation.scene = problem.source;
  return constellation;
}

}  // namespace

EvaluateResult Evaluate(const EvaluateOptions& options) {
  options.observe.Validate();
  options.limits.Validate();
  options.constraints.Validate();
  if (options.pose_tolerance) options.pose_tolerance->Validate();
  detail::ResolveMinPoints(options.min_points, options.min_density, 0.01);  // before any work
  Constellation constellation;
  if (options.constellation.empty()) {
    constellation = DeclaredLayout(options.scene);
  } else {
    try {
      constellation = LoadConstellation(options.constellation);
    } catch (const InputError&) {
      // A scene given on the command line is reported first when both are bad, as it is read
      // first when the constellation is good.
      if (!options.scene.path.empty()) LoadScene(options.scene);
      throw;
    }
  }
  const SceneInput scene = InheritScene(options.scene, constellation, options.constellation);
  ObserveOptions observe = options.observe;
  if (!options.constellation.empty())
    observe.quality =
        InheritQuality(options.observe.quality, constellation, options.constellation);
  // The sensor model: --ideal/--physical, else the run's when it was physical, else the scene's.
  if (!observe.physical && constellation.inputs && constellation.inputs->physical)
    observe.physical = true;
  observe = detail::WithSensorModel(observe, scene.path);
  // The constraints, the caller's (checked above, so that their errors name the flags) over the
  // run's, checked before any ray.
  ConstraintOptions constraints = options.constraints;
  if (constellation.inputs) {
    const ConstraintOptions& run = constellation.inputs->selection.constraints;
    if (!constraints.interference) constraints.interference = run.interference;
    if (!constraints.interference_overlap) constraints.interference_overlap = run.interference_overlap;
    if (!constraints.calibration_overlap && !constraints.calibration_overlap_frac) {
      constraints.calibration_overlap = run.calibration_overlap;
      constraints.calibration_overlap_frac = run.calibration_overlap_frac;
    }
  }
  try {
    constraints.Validate();
  } catch (const InputError& e) {
    // Only the run's inputs can be at fault now: name the file they came from (issue 15).
    throw InputError(AtPlace(options.constellation, 0, fmt::format("inputs: {}", e.what())));
  }
  // The point density, the caller's, else the run's: the run's is checked here, before any ray,
  // naming the file and key (issue 44: an edited value was blamed on --min-points); --min-density
  // is converted with the run's cell size once the scene is read, and checked again there.
  std::optional<int64_t> min_points = options.min_points;
  std::optional<double> min_density = options.min_density;
  std::string density_origin;  // empty: the flags
  if (!min_points && !min_density && constellation.inputs) {
    min_points = constellation.inputs->selection.min_points;
    min_density = constellation.inputs->selection.min_density;
    density_origin = options.constellation;
    detail::ResolveMinPoints(min_points, min_density, scene.load.cell_size.value_or(1e-9),
                             density_origin);
  }
  Reobserved reobserved =
      Reobserve(scene, constellation, options.constellation, observe, options.limits);
  const std::vector<std::string>& unknown_types = reobserved.unknown_types;

  EvaluateResult result;
  const VisibilityFile& data = *reobserved.data;
  const CoverageEvaluator evaluator(data.observations, data.reference.size());
  for (size_t i = 0; i < data.candidates.size(); ++i) {
    const std::vector<uint32_t> one{static_cast<uint32_t>(i)};
    result.sensor_coverage.push_back(evaluator.Coverage(one));
  }
  RunResult& run = result.run;
  run.data = std::move(reobserved.data);
  Report& report = run.report;
  report.scene = run.data->scene;
  report.seed = run.data->seed;
  report.data = run.data.get();
  report.results = {reobserved.given};
  report.timings = reobserved.timings;
  if (const std::optional<uint32_t> points = detail::ResolveMinPoints(
          min_points, min_density, run.data->reference.cell_size, density_origin)) {
    // The layout's coverage counting only the cells with enough points (docs/constraints.md).
    SelectOptions density;
    density.min_points = points;
    const double seconds = report.results.front().seconds;
    report.results.front() = ScoreChosen(evaluator, report.results.front().chosen, "given", density);
    report.results.front().seconds = seconds;
  }
  // Over scene states a pair interferes when it does in any state (docs/constraints.md, Over
  // scene states): the given sensors observe each state too, at their given poses. Entry 0 stands
  // for the objects as listed, which `data` observed.
  std::vector<ObservedState> states;
  const Problem& problem = reobserved.problem;
  const bool wants_interference =
      constraints.interference.value_or(constraints.interference_overlap.has_value());
  if (!problem.states.empty() && wants_interference) {
    states.emplace_back();
    ObserveOptions state_model = observe;
    state_model.physical = run.data->physical;
    for (const SceneState& state : problem.states) {
      const Scene scene_of_state = ApplyState(problem.scene, state);
      ObservedState observed;
      observed.name = state.name;
      observed.reference =
          detail::BuildRunReference(scene_of_state,
                                    {problem.cell_size, scene.exposed_only.value_or(false)},
                                    problem.source);
      observed.observations =
          Observe(RayScene(scene_of_state), observed.reference, run.data->candidates, state_model);
      states.push_back(std::move(observed));
    }
  }
  report.constraints =
      detail::ResolveConstraints(constraints, SelectOptions{}, run.data->candidates,
                                 run.data->observations, problem.mounting, 0, states);
  if (report.constraints) report.constraints->is_applied = false;
  report.inputs = detail::InputsOf("evaluate", scene, observe);
  report.inputs->physical = run.data->physical;
  report.inputs->selection.constraints = options.constraints;
  report.inputs->selection.min_points = options.min_points;
  report.inputs->selection.min_density = options.min_density;
  if (!options.constellation.empty())
    report.inputs->constellation = detail::AbsolutePath(options.constellation).string();
  DeriveReport(&report);
  // The layout evaluated, as the exports of optimize: a Gazebo world's edit finds each sensor's
  // element by its population or name, so a constellation from elsewhere may not fit it.
  std::map<std::string, std::string> extra;
  std::vector<std::string> notes;
  try {
    if (!unknown_types.empty())
      throw InputError(fmt::format(
          "the sensor type '{}' of {} is neither the scene's nor the catalog's, so these files "
          "could not name it (the coverage above used the file's own intrinsics)",
          unknown_types.front(), options.constellation));
    extra = detail::ConstellationFiles(scene.path, reobserved.problem.scene, run.data->candidates,
                                       reobserved.problem.populations,
                                       reobserved.problem.sensors,
                                       detail::ScoringOf(*run.data, *report.inputs), &notes);
  } catch (const InputError& e) {
    extra.clear();
    notes.push_back(fmt::format("constellation files not written: {}", e.what()));
  }
  run.export_warnings = notes;
  report.notes.insert(report.notes.end(), notes.begin(), notes.end());
  detail::AddPoseTolerance(options.pose_tolerance, reobserved.rays.get(), observe, &report);
  detail::FinishRun(reobserved.problem.scene, std::move(extra), &run);
  return result;
}

namespace {

// The method of the result a report.json's sensors were taken from (its primary result, as
// LoadConstellation takes them), for the picture's legend; "given" when it names none.
std::string ShownMethod(const std::string& report_path) {
  std::ifstream in(report_path);
  const nlohmann::json j = nlohmann::json::parse(in, nullptr, false);
  if (j.is_discarded() || !j.contains("results") || !j["results"].is_array() ||
      j["results"].empty())
    return "given";
  size_t which = 0;
  if (j.contains("primary_result") && j["primary_result"].is_number_unsigned() &&
      j["primary_result"].get<size_t>() < j["results"].size())
    which = j["primary_result"].get<size_t>();
  const nlohmann::json& result = j["results"][which];
  return result.contains("method") && result["method"].is_string()
             ? result["method"].get<std::string>()
             : "given";
}

}  // namespace

RenderRunResult RenderRun(const RenderRunOptions& options) {
  options.render.Validate();
  if (!options.png.empty()) CheckOutputFile(options.png);  // before the scene is loaded
  const std::string report_path = fs::is_directory(options.run)
                                      ? (fs::path(options.run) / "report.json").string()
                                      : options.run;
  // By default view.png beside report.json, whether the run was given as its folder or as that
  // file (was: RUN/report.json/view.png, a write that failed).
  const std::string png = options.png.empty()
                              ? (fs::path(report_path).parent_path() / "view.png").string()
                              : options.png;
  const OutputGuard guard({{options.png.empty() ? "render" : "--png", png}});
  std::error_code error;
  if (!fs::is_regular_file(report_path, error))
    throw InputError(AtPlace(report_path, 0,
                             "cannot open report.json — give an output folder of `vantage "
                             "optimize`, `select` or `evaluate`"));
  const Constellation constellation = LoadConstellation(report_path);
  // The picture is always a PNG: a.jpg holding one would mislead every viewer and tool. After
  // the checks that say more (a folder, a device, the report.json read), before the scene.
  if (LowerExtension(png) != ".png")
    throw InputError(fmt::format("--png: '{}' does not end in .png — render writes PNG pictures "
                                 "only; give a name like view.png",
                                 ShownOnOneLine(png)));
  SceneInput scene = InheritScene(options.scene, constellation, report_path);
  if (scene.path.empty())
    throw InputError(AtPlace(report_path, 0, "no 'scene' path — give the scene with --scene PATH"));
  if (!fs::exists(scene.path, error))
    throw InputError(AtPlace(report_path, 0,
                             fmt::format("its scene '{}' is not found from here — run from the "
                                         "folder the run started in, or give --scene PATH",
                                         scene.path)));
  // The voxels of the report: its own cell size (the scene's may have changed since).
  if (!scene.load.cell_size) {
    if (!(constellation.cell_size > 0))
      throw InputError(AtPlace(report_path, 0,
                               "'cell_size' must be a positive number — give a report.json "
                               "written by vantage"));
    scene.load.cell_size = constellation.cell_size;
  }
  ObserveOptions observe;
  if (constellation.inputs) observe.cull = constellation.inputs->cull;
  observe.quality = InheritQuality({}, constellation, report_path);
  // The run's model: report.json says physical when it was (issue 43).
  observe.physical = constellation.inputs && constellation.inputs->physical;
  // Re-observe the chosen sensors: the same voxels as the report counts.
  // A run of a camera on an arm: its views.yaml beside report.json gives each view's joints.
  const fs::path views_path = fs::path(report_path).parent_path() / "views.yaml";
  std::optional<detail::ArmAtViews> arm;
  if (fs::is_regular_file(views_path, error))
    arm = detail::ArmAtViews(ReadArmViews(views_path.string()), views_path.string(),
                             options.arm_view);
  else if (options.arm_view)
    throw InputError(AtPlace("--arm-view", 0,
                             fmt::format("the run has no views.yaml ({}) — only a run of a camera "
                                         "on an arm draws the arm",
                                         views_path.string())));
  const Reobserved reobserved =
      Reobserve(scene, constellation, report_path, observe, RunLimits{},
                arm ? std::function<void(Problem*, std::vector<Candidate>*)>(
                          [&](Problem* problem, std::vector<Candidate>* sensors) {
                            arm->Apply(problem, sensors);
                          })
                    : std::function<void(Problem*, std::vector<Candidate>*)>());
  // An `optimize --track` run's coverage is the mean over its states of each state's one view:
  // not the union this picture colours (in the base scene), so no mismatch to warn of.
  bool tracked = false;
  if (arm) {
    std::ifstream in(report_path);
    const nlohmann::json j = nlohmann::json::parse(in, nullptr, false);
    tracked = j.is_object() && j.contains("track");
  }
  if (tracked)
    spdlog::info("{}: a --track run — the picture colours the union of its views in the base "
                 "scene; report.json's coverage is the mean of each state's one view",
                 report_path);
  else if (constellation.coverage &&
           std::abs(*constellation.coverage - reobserved.given.coverage) > 1e-9)
    spdlog::warn("{}: coverage {:.4f} % now, {:.4f} % in the report — has the scene changed since?",
                 report_path, 100.0 * reobserved.given.coverage, 100.0 * *constellation.coverage);

  Report report;
  report.scene = scene.path;
  report.data = reobserved.data.get();
  report.results = {reobserved.given};
  report.results.front().method = ShownMethod(report_path);
  DeriveReport(&report);
  RenderRunResult result;
  result.png = png;
  if (arm) {
    // The arm at the chosen view, its links in the picture and in its framing.
    RenderOptions render = options.render;
    const Scene shown = arm->SceneAtView(reobserved.problem.scene, &render.frame_also);
    WritePng(result.png, RenderView(shown, report, render));
  } else {
    WritePng(result.png,
             RenderView(*reobserved.rays, reobserved.problem.scene, report, options.render));
  }
  result.sensors = reobserved.data->candidates.size();
  result.coverage = reobserved.given.coverage;
  return result;
}

}  // namespace vantage
