#include <spdlog/spdlog.h>

#include <filesystem>
#include <memory>

#include "commands.hpp"
#include "vantage/robustness.hpp"

namespace vantage::cli {
namespace {

struct SelectCommandOptions {
  std::string file;
  SelectionOptions selection;
  std::optional<uint64_t> seed;
  std::string out = "vantage_out";
};

// The scene's meshes for report.html: reloaded from the path the visibility file names when it is
// still there; otherwise (or when it no longer loads) the page shows voxels and sensors only.
Scene ReportScene(const std::string& path) {
  std::error_code error;
  if (path.empty() || !std::filesystem::exists(path, error)) {
    spdlog::info("report.html without meshes: scene '{}' not found from here", path);
    return {};
  }
  try {
    return LoadProblem(path).scene;
  } catch (const InputError& e) {
    spdlog::warn("report.html without meshes: {}", e.what());
    return {};
  }
}

void RunSelect(const SelectCommandOptions& options) {
  const auto start = std::chrono::steady_clock::now();
  VisibilityFile data = LoadVisibilityFile(options.file);
  Timings timings;
  timings.load = SecondsSince(start);
  if (options.selection.over_states)
    throw InputError(AtPlace("--over-states", 0,
                             "a visibility file holds one state — run `vantage optimize` on the scene with "
                             "states instead"));
  const SelectOptions select_options = ResolveSelectOptions(data, options.selection, options.seed, "all");
  const auto select_start = std::chrono::steady_clock::now();
  Report report;
  report.results = Select(data.observations, data.reference.size(), select_options);
  timings.select = SecondsSince(select_start);
  timings.total = SecondsSince(start);
  report.scene = data.scene;
  report.seed = select_options.seed;
  report.data = &data;
  report.timings = timings;
  const Scene scene = ReportScene(data.scene);
  const int primary = PrimaryResult(report.results);
  if (primary >= 0) {
    // The shrunk fields of view need the geometry: only when the scene still loads from here.
    report.robustness = AssessRobustness(data, report.results, primary, scene.objects.empty() ? nullptr : &scene,
                                         options.selection.fov_tolerance_deg,
                                         options.selection.alternatives_within / 100.0);
  }
  WriteOutputs(options.out, report,
               {{"report.html", HtmlReport(report, scene)},
                {"static_transforms.yaml", StaticTransformsYaml(report)}});
  PrintSummary(report, options.out);
}

}  // namespace

void SetupSelect(CLI::App* parent) {
  auto options = std::make_shared<SelectCommandOptions>();
  CLI::App* app = parent->add_subcommand("select", "choose the constellation from a saved visibility matrix");
  app->add_option("file", options->file, "visibility matrix written by `vantage observe`")->required();
  AddSelectionOptions(app, &options->selection);
  app->add_option("--seed", options->seed, "random seed (default: the one stored in the file)");
  app->add_option("-o,--out", options->out, "output folder (replaced atomically)")->capture_default_str();
  app->callback([options] { RunSelect(*options); });
}

}  // namespace vantage::cli
