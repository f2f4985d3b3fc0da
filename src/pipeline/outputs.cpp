// What every command writes: the inputs block that reproduces the run, and the output files,
// each produced by its serialiser from the derived report.
#include <tbb/parallel_invoke.h>

#include <exception>
#include <filesystem>

#include "pipeline/common.hpp"
#include <fmt/format.h>
#include <spdlog/spdlog.h>

#include "util/atomic_file.hpp"
#include "vantage/error.hpp"
#include "vantage/gazebo_export.hpp"
#include "vantage/visualize.hpp"
#include "vantage/yaml_export.hpp"

namespace vantage {
namespace detail {

std::string AbsoluteText(const std::string& path) {
  if (path.empty()) return path;
  std::error_code error;
  const std::filesystem::path absolute = std::filesystem::absolute(path, error);
  return error ? path : absolute.lexically_normal().string();
}

LoadOptions AbsoluteFolders(LoadOptions load) {
  for (auto* list : {&load.model_paths, &load.resource_paths, &load.package_paths})
    for (std::string& path : *list) path = AbsoluteText(path);
  return load;
}

void SetSceneInputs(const std::string& scene, const LoadOptions& load, RunInputs* inputs) {
  inputs->scene = scene;
  inputs->model_paths = load.model_paths;
  inputs->resource_paths = load.resource_paths;
  inputs->package_paths = load.package_paths;
  inputs->targets = load.targets;
  inputs->cell_size = load.cell_size;
}

ScoringOptions ScoringOf(const VisibilityFile& data, const RunInputs& inputs) {
  ScoringOptions scoring;
  scoring.cell_size = data.reference.cell_size;
  scoring.quality = data.quality;
  scoring.min_points = inputs.selection.min_points;
  scoring.min_density = inputs.selection.min_density;
  return scoring;
}

RunInputs InputsOf(const std::string& command, const SceneInput& scene,
                   const ObserveOptions& observe) {
  RunInputs inputs;
  inputs.command = command;
  SetSceneInputs(AbsoluteText(scene.path), AbsoluteFolders(scene.load), &inputs);
  inputs.seed = scene.seed;
  inputs.observation_point = scene.observation_point;
  inputs.random_roll = scene.random_roll;
  inputs.exposed_only = scene.exposed_only.value_or(false);
  inputs.cull = observe.cull;
  inputs.quality = observe.quality;
  return inputs;
}

void AddPoseTolerance(const std::optional<PoseToleranceOptions>& options, const RayScene* rays,
                      const ObserveOptions& observe, Report* report) {
  if (!options) return;
  if (report->inputs) {
    report->inputs->pose_tolerance_m = options->position;
    report->inputs->pose_tolerance_deg = options->angle_deg;
    report->inputs->pose_samples = options->samples;
  }
  std::string skipped;
  if (report->states) {
    skipped = "the results count over scene states";
  } else if (report->CountsGroups()) {
    skipped = "the results count an aggregate of groups of cells, not all cells together";
  } else if (!rays) {
    skipped = "the scene no longer loads from here, and its geometry is needed to re-trace";
  }
  if (!skipped.empty()) {
    const std::string note = fmt::format("--pose-tolerance: skipped — {}", skipped);
    spdlog::warn("{}", note);
    report->notes.push_back(note);
    return;
  }
  PoseToleranceOptions seeded = *options;
  seeded.seed = report->seed;
  const auto start = std::chrono::steady_clock::now();
  report->pose_tolerance =
      AssessPoseTolerance(*report->data, report->results, *rays, observe, seeded);
  spdlog::info("pose tolerance: {} results x {} layouts in {:.3f} s", report->results.size(),
               seeded.samples, SecondsSince(start));
}

void AddSelectionInputs(const SelectionRequest& request, RunInputs* inputs) {
  inputs->selection = request;
}

std::map<std::string, std::string> ConstellationFiles(const std::string& scene_path,
                                                      const Scene& scene,
                                                      const std::vector<Candidate>& chosen,
                                                      const std::vector<Population>& populations,
                                                      const std::vector<ExplicitSensor>& sensors,
                                                      const ScoringOptions& scoring,
                                                      std::vector<std::string>* notes) {
  std::map<std::string, std::string> files;
  if (IsGazeboWorldPath(scene_path)) {
    files["constellation.world"] =
        ConstellationWorld(scene_path, chosen, populations, sensors, notes);
    files["constellation.sdf"] = ConstellationSdf(scene_path, chosen, populations, sensors);
  } else {
    files["constellation.yaml"] = ConstellationYaml(scene_path, chosen);
    files["constellation.sdf"] = SceneConstellationSdf(scene, chosen, scoring, notes);
  }
  return files;
}

void FinishRun(const Scene& scene, std::map<std::string, std::string> extra, RunResult* run) {
  VANTAGE_CHECK(run->report.is_derived && run->report.data == run->data.get());
  // The serialisers read the derived report and write nothing else, so they run side by side
  // (issue 47: report.html alone took as long as the others together, each on one core). A
  // failure is raised in the order they were called in before.
  std::map<std::string, std::string> files;
  std::string html, yaml, launch, xacro;
  std::exception_ptr errors[3];
  const auto guarded = [&errors](int k, auto&& work) {
    try {
      work();
    } catch (...) {
      errors[k] = std::current_exception();
    }
  };
  tbb::parallel_invoke(
      [&] { guarded(0, [&] { files = ReportFiles(run->report); }); },
      [&] { guarded(1, [&] { html = HtmlReport(run->report, scene); }); },
      [&] {
        guarded(2, [&] {
          yaml = StaticTransformsYaml(run->report);
          launch = StaticTransformsLaunch(run->report);
          xacro = CamerasXacro(run->report);
        });
      });
  for (const std::exception_ptr& error : errors)
    if (error) std::rethrow_exception(error);
  run->files = std::move(files);
  extra["report.html"] = std::move(html);
  extra["static_transforms.yaml"] = std::move(yaml);
  extra["static_transforms.launch.py"] = std::move(launch);
  extra["cameras.urdf.xacro"] = std::move(xacro);
  run->files.merge(extra);
}

}  // namespace detail

void CheckRunFolder(const std::string& out_dir) { detail::CheckOutputFolder(out_dir); }

void CheckOutputFile(const std::string& path) { detail::CheckOutputFile(path); }

void WriteRun(const std::string& out_dir, const RunResult& result) {
  VANTAGE_CHECK(!result.files.empty());
  // A name missing from RunFolderFileNames would survive a later run that does not write it.
  for (const auto& [name, content] : result.files) VANTAGE_CHECK(RunFolderFileNames().count(name));
  detail::WriteFolderAtomically(out_dir, result.files, RunFolderFileNames());
  for (const std::string& warning : result.export_warnings) spdlog::warn("{}", warning);
}

}  // namespace vantage
