// `vantage select FILE`: selection from a saved visibility matrix, into an output folder.
#include <fmt/format.h>

#include <memory>

#include "commands.hpp"

namespace vantage::cli {
namespace {

struct SelectFlags {
  SelectFileOptions options;
  std::string out = "vantage_out";
};

void RunSelect(const SelectFlags& flags) {
  CheckRunFolder(flags.out);
  const RunResult run = SelectFromFile(flags.options);
  WriteRun(flags.out, run);
  PrintSummary(run.report, flags.out);
}

}  // namespace

void SetupSelect(CLI::App* parent) {
  auto flags = std::make_shared<SelectFlags>();
  CLI::App* app = parent->add_subcommand(
      "select", "choose the constellation from a saved visibility matrix");
  app->add_option("file", flags->options.visibility_file,
                  "visibility matrix written by `vantage observe`")
      ->required();
  AddSelectionFlags(app, &flags->options.selection);
  AddRobustnessFlags(app, &flags->options.robustness);
  AddPoseToleranceFlags(app, &flags->options.pose_tolerance);
  AddArmTourFlags(app, &flags->options.arm);  // a file of a camera on an arm (format 11)
  app->add_option("--seed", flags->options.seed,
                  "random seed (default: the one stored in the file)");
  app->add_option("-o,--out", flags->out, "output folder, default ./vantage_out (vantage's files in it are replaced "
                  "atomically; your own files there are kept)")
      ->check(OutPathValidator())
      ->capture_default_str();
  app->callback([flags] { RunSelect(*flags); });
}

}  // namespace vantage::cli
