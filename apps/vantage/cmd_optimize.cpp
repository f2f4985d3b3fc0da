#include <fmt/format.h>
#include <spdlog/spdlog.h>

#include <map>
#include <memory>
#include <optional>

#include "commands.hpp"
#include "vantage/yaml_export.hpp"
#include "vantage/gazebo_export.hpp"
#include "vantage/refine.hpp"
#include "vantage/robustness.hpp"

namespace vantage::cli {
namespace {

struct OptimizeOptions {
  SceneOptions scene;
  SelectionOptions selection;
  std::string out = "vantage_out";
  bool refine = false;
  RefineOptions refine_options;
};

// --refine: new poses around the primary result's sensors, traced and re-selected; the refined
// constellation is appended to the results (method "refined") with its candidates.
std::optional<RefinementInfo> RefinePrimary(const OptimizeOptions& options, const SelectOptions& select,
                                            ObservedScene* observed, std::vector<Selection>* results) {
  const int from = PrimaryResult(*results);
  if (from < 0) return std::nullopt;
  RefineOptions refine = options.refine_options;
  refine.seed = select.seed;
  VisibilityFile& data = observed->data;
  RefineResult refined = Refine(observed->scene, data.reference, data.candidates, data.observations,
                                observed->populations, observed->observation_point,
                                (*results)[static_cast<size_t>(from)], select, refine);
  data.candidates = std::move(refined.candidates);
  data.observations = std::move(refined.observations);
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
  spdlog::info("refine: {} rounds, {} new poses, {:.1f} M rays, {:+.2f} points in {:.3f} s", info.rounds,
               info.new_candidates, info.extra_rays / 1e6, 100.0 * (info.coverage_after - info.coverage_before),
               info.seconds);
  return info;
}

void RunOptimize(const OptimizeOptions& options) {
  const auto start = std::chrono::steady_clock::now();
  ObservedScene observed = ObserveScene(options.scene, &options.selection);
  const SelectOptions select_options =
      ResolveSelectOptions(observed.data, options.selection, options.scene.seed, "all");
  if (options.refine && !observed.states.empty())
    throw InputError(AtPlace("--refine", 0, "refinement over scene states is not supported yet — drop "
                                            "--refine or the scene's states"));
  const auto select_start = std::chrono::steady_clock::now();
  Report report;
  SelectResults(observed, options.selection, select_options, &report);
  if (options.refine) report.refinement = RefinePrimary(options, select_options, &observed, &report.results);
  observed.timings.select = SecondsSince(select_start);
  observed.timings.total = SecondsSince(start);

  report.scene = observed.data.scene;
  report.seed = select_options.seed;
  report.data = &observed.data;
  report.timings = observed.timings;
  report.notes = observed.notes;
  if (report.states) {
    report.notes.push_back(fmt::format(
        "scene states: candidates' coverages, reference.ply, observed.ply and report.html's 3D view and "
        "chosen-sensor table show the first state '{}'; each result's state_coverage lists every state",
        report.states->states.front().name));
  }
  // constellation.world: the input world with only the primary result's sensors (SYSTEM.md).
  std::map<std::string, std::string> extra_files;
  const int primary = report.primary >= 0 ? report.primary : PrimaryResult(report.results);
  std::vector<Candidate> chosen;
  if (primary >= 0) {
    for (uint32_t i : report.results[static_cast<size_t>(primary)].chosen)
      chosen.push_back(observed.data.candidates[i]);
  }
  if (IsGazeboWorldPath(options.scene.scene) && primary >= 0) {
    std::vector<std::string> notes;
    extra_files["constellation.world"] = ConstellationWorld(
        options.scene.scene, chosen, observed.populations, observed.sensors, &notes);
    for (const std::string& note : notes) spdlog::warn("{}", note);
    report.notes.insert(report.notes.end(), notes.begin(), notes.end());
  }
  if (!IsGazeboWorldPath(options.scene.scene) && primary >= 0) {
    extra_files["constellation.yaml"] = ConstellationYaml(options.scene.scene, chosen);
  }
  // Robustness reads `data`, the first state's sets: not meaningful over states.
  if (primary >= 0 && !report.states) {
    report.robustness = AssessRobustness(observed.data, report.results, primary, &observed.scene,
                                         options.selection.fov_tolerance_deg,
                                         options.selection.alternatives_within / 100.0);
  }
  extra_files["report.html"] = HtmlReport(report, observed.scene);
  extra_files["static_transforms.yaml"] = StaticTransformsYaml(report);
  WriteOutputs(options.out, report, extra_files);
  PrintSummary(report, options.out);
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
  app->add_flag("--refine", options->refine,
                "after selection, search new poses around the chosen sensors (inside their "
                "regions), trace only those and re-select while coverage improves");
  app->add_option("--refine-rounds", options->refine_options.max_rounds, "rounds of --refine")
      ->check(CLI::Range(1, 100))
      ->capture_default_str();
  app->callback([options] { RunOptimize(*options); });
}

}  // namespace vantage::cli
