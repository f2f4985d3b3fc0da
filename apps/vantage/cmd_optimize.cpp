#include <spdlog/spdlog.h>

#include <map>
#include <memory>

#include "commands.hpp"
#include "vantage/yaml_export.hpp"
#include "vantage/gazebo_export.hpp"
#include "vantage/robustness.hpp"

namespace vantage::cli {
namespace {

struct OptimizeOptions {
  SceneOptions scene;
  SelectionOptions selection;
  std::string out = "vantage_out";
};

void RunOptimize(const OptimizeOptions& options) {
  const auto start = std::chrono::steady_clock::now();
  ObservedScene observed = ObserveScene(options.scene, &options.selection);
  const SelectOptions select_options =
      ResolveSelectOptions(observed.data, options.selection, options.scene.seed, "all");
  const auto select_start = std::chrono::steady_clock::now();
  std::vector<Selection> results =
      Select(observed.data.observations, observed.data.reference.size(), select_options);
  observed.timings.select = SecondsSince(select_start);
  observed.timings.total = SecondsSince(start);

  Report report;
  report.scene = observed.data.scene;
  report.seed = select_options.seed;
  report.data = &observed.data;
  report.results = std::move(results);
  report.timings = observed.timings;
  report.notes = observed.notes;
  // constellation.world: the input world with only the primary result's sensors (SYSTEM.md).
  std::map<std::string, std::string> extra_files;
  const int primary = report.primary >= 0 ? report.primary : PrimaryResult(report.results);
  if (IsGazeboWorldPath(options.scene.scene) && primary >= 0) {
    std::vector<Candidate> chosen;
    for (uint32_t i : report.results[static_cast<size_t>(primary)].chosen)
      chosen.push_back(observed.data.candidates[i]);
    std::vector<std::string> notes;
    extra_files["constellation.world"] = ConstellationWorld(
        options.scene.scene, chosen, observed.populations, observed.sensors, &notes);
    for (const std::string& note : notes) spdlog::warn("{}", note);
    report.notes.insert(report.notes.end(), notes.begin(), notes.end());
  }
  if (!IsGazeboWorldPath(options.scene.scene) && primary >= 0) {
    std::vector<Candidate> chosen;
    for (uint32_t i : report.results[static_cast<size_t>(primary)].chosen)
      chosen.push_back(observed.data.candidates[i]);
    extra_files["constellation.yaml"] = ConstellationYaml(options.scene.scene, chosen);
  }
  if (primary >= 0) {
    report.robustness = AssessRobustness(observed.data, report.results, primary, &observed.scene,
                                         options.selection.fov_tolerance_deg,
                                         options.selection.alternatives_within / 100.0);
  }
  extra_files["report.html"] = HtmlReport(report, observed.scene);
  extra_files["static_transforms.yaml"] = StaticTransformsYaml(report);
  WriteOutputs(options.out, report, extra_files);
  PrintSummary(observed.data, report.results, report.timings, options.out, report.robustness);
}

}  // namespace

void SetupOptimize(CLI::App* parent) {
  auto options = std::make_shared<OptimizeOptions>();
  CLI::App* app =
      parent->add_subcommand("optimize", "the whole pipeline: scene -> best constellation");
  AddSceneOptions(app, &options->scene);
  AddSelectionOptions(app, &options->selection);
  app->add_option("-o,--out", options->out, "output folder (replaced atomically)")
      ->capture_default_str();
  app->callback([options] { RunOptimize(*options); });
}

}  // namespace vantage::cli
