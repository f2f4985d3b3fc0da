#include <spdlog/spdlog.h>

#include <memory>

#include "commands.hpp"

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
  WriteOutputs(options.out, report,
               {{"report.html", HtmlReport(report, observed.scene)},
                {"static_transforms.yaml", StaticTransformsYaml(report)}});
  PrintSummary(observed.data, report.results, report.timings, options.out);
}

}  // namespace

void SetupOptimize(CLI::App* parent) {
  auto options = std::make_shared<OptimizeOptions>();
  CLI::App* app = parent->add_subcommand("optimize", "the whole pipeline: scene -> best constellation");
  AddSceneOptions(app, &options->scene);
  AddSelectionOptions(app, &options->selection);
  app->add_option("-o,--out", options->out, "output folder (replaced atomically)")->capture_default_str();
  app->callback([options] { RunOptimize(*options); });
}

}  // namespace vantage::cli
