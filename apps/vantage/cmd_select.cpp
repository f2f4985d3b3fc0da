#include <spdlog/spdlog.h>

#include <memory>

#include "commands.hpp"

namespace vantage::cli {
namespace {

struct SelectCommandOptions {
  std::string file;
  SelectionOptions selection;
  std::optional<uint64_t> seed;
  std::string out = "vantage_out";
};

void RunSelect(const SelectCommandOptions& options) {
  const auto start = std::chrono::steady_clock::now();
  VisibilityFile data = LoadVisibilityFile(options.file);
  Timings timings;
  timings.load = SecondsSince(start);
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
  WriteOutputs(options.out, report);
  PrintSummary(data, report.results, timings, options.out);
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
